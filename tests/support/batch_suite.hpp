#pragma once
// The test cases of the batched algorithms (batch.hpp) against the single-state calls, compiled for the lanes of
// the including file's target: test_batch.cpp (default x86-64: SSE2, 2 doubles / 4 floats; aarch64: NEON, the same
// widths) and simd_batch.cpp (-mavx2 -mfma: 4 doubles / 8 floats). Models: the HOAP-3 models (compile-time, and a
// run-time twin), a compile-time tree of every joint type and random run-time trees of every joint type, double and
// float; the checks are those of batch_checks.hpp.
#include <spatial/spatial.hpp>

#include "batch_checks.hpp"
#include "compile_time_trees.hpp"
#include "random_model.hpp"

#if SPATIAL_TEST_COMPILE_TIME_TREES
#include <spatial/models/hoap3_double_pendulum.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::check_batch;

Model<double> random_tree(int n, spatial::testing::Shape shape, unsigned seed) {
  return spatial::testing::build_model_with_frames(spatial::testing::random_bodies(n, shape, seed, true), seed);
}

TEST(Batch, RandomRunTimeChainsOfEveryJointTypeMatchTheSingleStateCalls) {
  for (const unsigned seed : {11u, 12u}) {
    const Model<double> model = random_tree(12, spatial::testing::Shape::Chain, seed);
    check_batch<double>(model, "chain12", seed);
    check_batch<float>(model, "chain12", seed);
  }
}

TEST(Batch, RandomRunTimeBranchedTreesOfEveryJointTypeMatchTheSingleStateCalls) {
  for (const unsigned seed : {21u, 22u}) {
    const Model<double> model = random_tree(15, spatial::testing::Shape::Branched, seed);
    check_batch<double>(model, "branched15", seed);
    check_batch<float>(model, "branched15", seed);
  }
}

// FloatingBatch: random trees of every joint type under a free-flying root body, with fixed frames on the root and
// on two bodies (frame placements in the world and frame Jacobians through the free-flyer).
TEST(Batch, RandomRunTimeFloatingTreesMatchTheSingleStateCalls) {
  for (const unsigned seed : {13u, 14u}) {
    std::mt19937 rng(seed + 1000);
    const FloatingModel<double> model(random_tree(10, spatial::testing::Shape::Branched, seed),
                                      spatial::testing::random_root_inertia(rng), "root");
    check_batch<double>(model, "floating10", seed);
    check_batch<float>(model, "floating10", seed);
  }
}

TEST(Batch, HoapRunTimeTwinsMatchTheSingleStateCalls) {
#if SPATIAL_TEST_COMPILE_TIME_TREES
  check_batch<double>(models::hoap3_stance_right::model().to_runtime(), "stance21 (run time)", 31);
  check_batch<float>(models::hoap3_stance_right::model().to_runtime(), "stance21 (run time)", 31);
#else
  GTEST_SKIP() << "the generated models are compile-time trees (not built in this configuration)";
#endif
}

#if SPATIAL_TEST_COMPILE_TIME_TREES
using J = JointType;
// 8 bodies, branched, one of every joint type.
using EveryJoint = Tree<Parents<-1, 0, 1, 1, 0, 4, 5, 2>,
                        Joints<J::RevoluteX, J::RevoluteY, J::RevoluteZ, J::RevoluteAxis, J::PrismaticX,
                               J::PrismaticY, J::PrismaticZ, J::PrismaticAxis>>;

TEST(Batch, CompileTimeTreeOfEveryJointTypeMatchesTheSingleStateCalls) {
  auto bodies = spatial::testing::random_bodies(8, spatial::testing::Shape::Chain, 41, true);
  for (int i = 0; i < 8; ++i) {
    auto& b = bodies[static_cast<std::size_t>(i)];
    b.parent = EveryJoint::parent[static_cast<std::size_t>(i)];
    b.type = EveryJoint::joint[static_cast<std::size_t>(i)];
    if (b.type == J::RevoluteX || b.type == J::PrismaticX) b.axis = Vector3<double>::UnitX();
    if (b.type == J::RevoluteY || b.type == J::PrismaticY) b.axis = Vector3<double>::UnitY();
    if (b.type == J::RevoluteZ || b.type == J::PrismaticZ) b.axis = Vector3<double>::UnitZ();
  }
  const auto model = Model<double, EveryJoint>::from(spatial::testing::build_model_with_frames(bodies, 41));
  check_batch<double>(model, "every joint (ct)", 41);
  check_batch<float>(model, "every joint (ct)", 41);
}

// The stance model in double and float, the torso and the double pendulum in double: each compile-time model is a
// full instantiation of every batched algorithm (this file was the longest compilation of the CI build with all six),
// and bench_batch checks stance21 and torso8 in both scalars on the widest lanes before timing (scripts/main.sh).
TEST(Batch, HoapCompileTimeModelsMatchTheSingleStateCalls) {
  check_batch<double>(models::hoap3_stance_right::model(), "stance21", 51);
  check_batch<float>(models::hoap3_stance_right::model(), "stance21", 51);
  check_batch<double>(models::hoap3_torso::model(), "torso8", 52);
  check_batch<double>(models::hoap3_double_pendulum::model(), "pendulum2", 53);
}
// The floating HOAP-3 (27 DoF) in double (float: on the random floating trees, and in bench_batch's check).
TEST(Batch, HoapFloatingCompileTimeModelMatchesTheSingleStateCalls) {
  check_batch<double>(models::hoap3_floating::floating_model(), "floating27", 54);
}
#endif

TEST(Batch, ThreadCountAndEmptyBatches) {
  const Model<double> model = random_tree(5, spatial::testing::Shape::Branched, 61);
  Batch<double> all(model, 0);
  EXPECT_EQ(all.threads(), std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
  Batch<double> three(model, 3);
  EXPECT_EQ(three.threads(), 3);
  EXPECT_EQ(three.nv(), 5);
  // B = 0: nothing to do, nothing written.
  Eigen::MatrixXd Q(5, 0), tau(5, 0);
  three.rnea(Q, Q, Q, tau);
  // Fewer states than threads × lanes: the idle threads leave the results alone, and they are right.
  std::mt19937 rng(62);
  const Eigen::MatrixXd Q1 = spatial::testing::random_states<double>(5, 1, rng, 1.0);
  Eigen::MatrixXd t1(5, 1), t3(5, 1);
  Batch<double>(model, 1).rnea(Q1, Q1, Q1, t1);
  three.rnea(Q1, Q1, Q1, t3);
  EXPECT_TRUE(spatial::testing::same_bits(t1, t3));
}

TEST(Batch, InputsAsRowMajorMapsAndOutputsAsBlocks) {
  // The layout a Python or NumPy caller has: B × nv row-major, i.e. a column-major nv × B seen through a map.
  const Model<double> model = random_tree(6, spatial::testing::Shape::Chain, 71);
  Batch<double> batch(model, 2);
  std::mt19937 rng(72);
  const Eigen::MatrixXd Q = spatial::testing::random_states<double>(6, 9, rng, 1.5);
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Qt = Q.transpose();
  Eigen::MatrixXd want(6, 9), big = Eigen::MatrixXd::Constant(8, 12, -3.0);
  batch.gravity(Q, want);
  batch.gravity(Qt.transpose(), big.block(1, 2, 6, 9));
  EXPECT_TRUE(spatial::testing::same_bits(big.block(1, 2, 6, 9), want));
  EXPECT_EQ(big(0, 0), -3.0);
  EXPECT_EQ(big(7, 11), -3.0);
}

TEST(Batch, EveryMethodWithRowMajorAndNonDirectInputsAndOutputs) {
  // Inputs and outputs whose states are not contiguous columns get the same bits as plain matrices (staged and
  // written entry by entry instead of transposed in registers): row-major matrices (direct access, row stride ≠ 1)
  // and expressions without direct access (a product by 1 as an input, Eigen's reverse() as an output).
  const Model<double> model = random_tree(7, spatial::testing::Shape::Branched, 81);
  Batch<double> batch(model, 1);
  const int n = 7, B = 2 * Batch<double>::lanes + 1;
  std::mt19937 rng(82);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::MatrixXd Q = spatial::testing::random_states<double>(n, B, rng, 1.5),
                        V = spatial::testing::random_states<double>(n, B, rng, 1.5),
                        A = spatial::testing::random_states<double>(n, B, rng, 1.5);
  const RowMajor Qr = Q, Vr = V, Ar = A;
  const auto check = [&](const char* name, int rows, int cols, const auto& run) {
    Eigen::MatrixXd want = Eigen::MatrixXd::Constant(rows, cols, -5.0), rev = want, from_rows = want,
                    from_expr = want;
    RowMajor rm = RowMajor::Constant(rows, cols, -5.0);
    run(Q, V, A, want);
    run(Q, V, A, rm);
    run(Q, V, A, rev.reverse());
    run(Qr, Vr, Ar, from_rows);
    run(Q * 1.0, V * 1.0, A * 1.0, from_expr);
    EXPECT_FALSE((want.array() == -5.0).any()) << name << ": an entry left unwritten";
    EXPECT_TRUE(spatial::testing::same_bits(rm, want)) << name << ": into a row-major matrix";
    EXPECT_TRUE(spatial::testing::same_bits(rev.reverse(), want)) << name << ": into reverse()";
    EXPECT_TRUE(spatial::testing::same_bits(from_rows, want)) << name << ": from row-major matrices";
    EXPECT_TRUE(spatial::testing::same_bits(from_expr, want)) << name << ": from expressions";
  };
  check("rnea", n, B, [&](const auto& q, const auto& v, const auto& a, auto&& out) { batch.rnea(q, v, a, out); });
  check("gravity", n, B, [&](const auto& q, const auto&, const auto&, auto&& out) { batch.gravity(q, out); });
  check("bias", n, B, [&](const auto& q, const auto& v, const auto&, auto&& out) { batch.bias(q, v, out); });
  check("aba", n, B, [&](const auto& q, const auto& v, const auto& a, auto&& out) { batch.aba(q, v, a, out); });
  check("forward_dynamics_crba", n, B, [&](const auto& q, const auto& v, const auto& a, auto&& out) {
    batch.forward_dynamics_crba(q, v, a, out);
  });
  check("crba", n, n * B, [&](const auto& q, const auto&, const auto&, auto&& out) { batch.crba(q, out); });
  check("frame_placement", 3, 4 * B,
        [&](const auto& q, const auto&, const auto&, auto&& out) { batch.frame_placement(q, 1, out); });
  check("frame_jacobian", 6, n * B, [&](const auto& q, const auto&, const auto&, auto&& out) {
    batch.frame_jacobian(q, 1, ReferenceFrame::World, out);
  });
}

// The sine and cosine of the lanes (batch.hpp's `sincos_lanes`) against the C library in long double, in spacings
// of S at the reference value: float lanes are computed in float (sincos.hpp's `sincos_reduce_float`), double lanes
// in double. Lanes with |x| beyond the fast kernel's limit, Inf and NaN take the one-by-one path (in double, as
// the single-state calls): they give the single-state values, and the other lanes of their register keep the bits
// they have without them.
template <class S>
double lane_ulps(S value, long double reference) {
  constexpr int digits = std::numeric_limits<S>::digits;
  const long double spacing = std::ldexp(
      1.0L, std::max(std::ilogb(static_cast<S>(reference)), std::numeric_limits<S>::min_exponent - 1) - (digits - 1));
  return static_cast<double>(std::fabs(static_cast<long double>(value) - reference) / spacing);
}

template <class S>
void check_sincos_lanes(double range, double max_ulps, unsigned seed) {
  using L = Lanes<S>;
  constexpr std::size_t n = L::size;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-range, range);
  alignas(L::arch_type::alignment()) S x[n], s[n], c[n];
  double worst = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    for (std::size_t l = 0; l < n; ++l) x[l] = static_cast<S>(u(rng));
    L sl, cl;
    detail::SincosTraits<L>::sincos(L::load_aligned(x), sl, cl);
    sl.store_aligned(s);
    cl.store_aligned(c);
    for (std::size_t l = 0; l < n; ++l) {
      const long double xl = x[l];
      worst = std::max({worst, lane_ulps(s[l], std::sin(xl)), lane_ulps(c[l], std::cos(xl))});
    }
  }
  ::testing::Test::RecordProperty(std::string(sizeof(S) == 4 ? "float" : "double") + "_worst_ulps_" +
                                      std::to_string(static_cast<int>(range)),
                                  std::to_string(worst));
  EXPECT_LE(worst, max_ulps) << (sizeof(S) == 4 ? "float" : "double") << " lanes, range ±" << range;
}

TEST(Batch, SineAndCosineOfTheLanes) {
  check_sincos_lanes<float>(4.0, 2.0, 1);
  check_sincos_lanes<float>(4000.0, 2.0, 2);
  check_sincos_lanes<double>(4.0, 1.5, 3);
  check_sincos_lanes<double>(99999.0, 2.5, 4);
}

template <class S>
void check_sincos_special_lanes() {
  using L = Lanes<S>;
  constexpr std::size_t n = L::size;
  const S pi = static_cast<S>(3.14159265358979323846);
  // Quadrant boundaries, tiny and huge values, the limits of the fast kernels, Inf and NaN, a register at a time.
  const std::vector<S> values = {S(0), pi / 4, pi / 2, 3 * pi / 4, pi, -pi / 2, -pi, 2 * pi, S(1e-30), S(-1e-30),
                                 S(4095.5), S(4096), S(-4096.5), S(1e5), S(-2.5e7), S(1e30),
                                 std::numeric_limits<S>::infinity(), std::numeric_limits<S>::quiet_NaN()};
  alignas(L::arch_type::alignment()) S x[n], s[n], c[n], s_alone[n], c_alone[n];
  for (std::size_t v = 0; v < values.size(); ++v) {
    // lane v % n holds the special value, the others ordinary angles
    for (std::size_t l = 0; l < n; ++l) x[l] = S(0.25) * static_cast<S>(l + 1);
    const std::size_t lane = v % n;
    L sl, cl;
    detail::SincosTraits<L>::sincos(L::load_aligned(x), sl, cl);
    sl.store_aligned(s_alone);
    cl.store_aligned(c_alone);
    x[lane] = values[v];
    detail::SincosTraits<L>::sincos(L::load_aligned(x), sl, cl);
    sl.store_aligned(s);
    cl.store_aligned(c);
    for (std::size_t l = 0; l < n; ++l) {
      if (l == lane) continue;
      EXPECT_EQ(s[l], s_alone[l]) << "lane " << l << " beside " << values[v];
      EXPECT_EQ(c[l], c_alone[l]) << "lane " << l << " beside " << values[v];
    }
    if (std::isfinite(values[v])) {
      // the single-state calls' value within two spacings of S (for the angles beyond the fast kernels' limits,
      // the very value: both go through the same double computation)
      std::vector<S> q1 = {values[v]}, s1(1), c1(1);
      detail::sincos_all<S>(q1, c1, s1, 1);
      const long double xl = values[v];
      EXPECT_LE(lane_ulps(s[lane], std::sin(xl)), 2.0) << "sin " << values[v];
      EXPECT_LE(lane_ulps(c[lane], std::cos(xl)), 2.0) << "cos " << values[v];
      const double limit = std::is_same_v<S, float> ? double(detail::kSincosFloatFastLimit) : detail::kSincosFastLimit;
      if (!(std::abs(static_cast<double>(values[v])) < limit)) {
        EXPECT_EQ(s[lane], s1[0]) << values[v];
        EXPECT_EQ(c[lane], c1[0]) << values[v];
      }
    } else {
      EXPECT_TRUE(std::isnan(s[lane])) << values[v];
      EXPECT_TRUE(std::isnan(c[lane])) << values[v];
    }
  }
}

TEST(Batch, SineAndCosineOfSpecialValuesStayInTheirLanes) {
  check_sincos_special_lanes<float>();
  check_sincos_special_lanes<double>();
}

}  // namespace

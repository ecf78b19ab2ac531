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
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>
#endif

#include <gtest/gtest.h>

#include <thread>

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

}  // namespace

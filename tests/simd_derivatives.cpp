// The analytical derivatives (derivatives.hpp) in the translation unit built with -mavx2 -mfma, the only test
// binary where their AVX2 code runs: rnea_derivatives' forward pass (simd::derivatives_forward), its rows
// (simd::derivative_rows), the walk over the ancestors' lanes (simd::WalkRow, on trees deep enough for
// `walk_lanes`) or over their C matrices, and aba_derivatives' products with 4-wide packets (held in registers for
// 21 columns, not for 27). The other test binaries are compiled for generic x86-64, where none of it exists, and
// their 2-wide packets never keep the HOAP-3 products in registers.
//
// Reference: the same call on the model's general-axis twin (scalar_twin), which every algorithm runs on the scalar
// path. Compared on the HOAP-3 stance and floating models (compile-time trees and their run-time twins, which take
// the kernels too), a random tree with two roots (Rev9) and a chain deeper than any HOAP-3 branch (RevChain24, the
// lane walk), without and with external forces in both frames, and with no allocation. In the sanitizer build
// (SPATIAL_SIMD_TEST_ALL_TREES = 0) the HOAP-3 models run as run-time trees only, which take the same kernels over
// Data's per-body records, and Rev9 as compile-time trees: each compile-time instantiation here is the whole of
// both derivative algorithms unrolled, three times (the external-force cases).
#include "support/simd_compare.hpp"

#include <spatial/models/hoap3_floating.hpp>

#include <vector>

namespace {
using namespace spatial;
using namespace spatial::testing::simd;

/// max |a − b| ≤ tol · max(1, max |b|)
template <class A, class B>
void expect_close(const char* what, const A& a, const B& b, double tol, const std::string& where) {
  const double scale = std::max(1.0, double(b.cwiseAbs().maxCoeff()));
  const double diff = double((a - b).cwiseAbs().maxCoeff());
  EXPECT_LE(diff, tol * scale) << what << ", " << where << ": " << diff / scale << " of the largest entry";
}

/// rnea_derivatives and aba_derivatives on `model` (the kernels) and on `twin` (the scalar path) at the same state.
/// H⁻¹ amplifies the paths' different roundings by H's condition number, hence the looser bound on what it
/// multiplies (as for q̈ in simd_floating.cpp).
template <class M, class D, class DD, class Twin, class TD, class TDD, class Q, class V, class Ext>
void compare_once(const M& model, const Twin& twin, const Q& q, const V& v, const V& a, const V& tau,
                  const Ext& fext, ForceFrame frame, double tol, const std::string& where) {
  D ds(model);
  DD dds(model);
  TD dr(twin);
  TDD ddr(twin);
  Eigen::internal::set_is_malloc_allowed(false);
  rnea_derivatives(model, ds, dds, q, v, a, fext, frame);
  Eigen::internal::set_is_malloc_allowed(true);
  rnea_derivatives(twin, dr, ddr, q, v, a, fext, frame);
  expect_close("dtau_dq", dds.dtau_dq, ddr.dtau_dq, tol, where);
  expect_close("dtau_dv", dds.dtau_dv, ddr.dtau_dv, tol, where);
  expect_close("tau", ds.tau, dr.tau, tol, where);

  Eigen::internal::set_is_malloc_allowed(false);
  aba_derivatives(model, ds, dds, q, v, tau, fext, frame);
  Eigen::internal::set_is_malloc_allowed(true);
  aba_derivatives(twin, dr, ddr, q, v, tau, fext, frame);
  const double loose = 1e3 * tol;
  expect_close("qdd", ds.qdd, dr.qdd, loose, where);
  expect_close("dqdd_dtau", dds.dqdd_dtau, ddr.dqdd_dtau, loose, where);
  expect_close("dqdd_dq", dds.dqdd_dq, ddr.dqdd_dq, loose, where);
  expect_close("dqdd_dv", dds.dqdd_dv, ddr.dqdd_dv, loose, where);
  // data.tau: RNEA at the q̈ found (the kernels add q̈'s terms to a pass run at q̈ = 0, the root's too), which gives
  // back τ.
  expect_close("RNEA(q, v, qdd) after aba_derivatives", ds.tau, dr.tau, loose, where);
  expect_close("RNEA(q, v, qdd) = tau", ds.tau, tau, loose, where);
  // The products against Eigen's dense ones from this call's own H⁻¹ and ∂τ/∂x: only the order of the additions
  // differs, so each entry agrees to 2 n u times the sum of its terms' magnitudes (|H⁻¹| |∂τ/∂x|).
  const Eigen::MatrixXd Mi = dds.dqdd_dtau;
  auto expect_product = [&](const char* what, const auto& out, const auto& dtau) {
    const Eigen::MatrixXd bound = 2.0 * double(Mi.rows()) * std::numeric_limits<double>::epsilon() *
                                  (Mi.cwiseAbs() * dtau.cwiseAbs());
    const Eigen::MatrixXd diff = (out + Mi * dtau).cwiseAbs();
    EXPECT_TRUE((diff.array() <= bound.array()).all()) << what << ", " << where << ": worst "
                                                       << (diff.array() / bound.array()).maxCoeff() << " of the bound";
  };
  expect_product("dqdd_dq = −H⁻¹ ∂τ/∂q", dds.dqdd_dq, dds.dtau_dq);
  expect_product("dqdd_dv = −H⁻¹ ∂τ/∂v", dds.dqdd_dv, dds.dtau_dv);
}

/// Fixed base: `trials` random states, each without external forces, with body-frame and with base-frame ones.
template <class TreeT>
void compare_fixed(const Model<double, TreeT>& model, unsigned seed, int trials = 4) {
  const Model<double> twin = scalar_twin(model);
  const int n = model.size();
  const double tol = tolerance_of(model);
  std::mt19937 rng(seed);
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = spatial::testing::random_vector(n, rng, 3.0);
    const Eigen::VectorXd v = spatial::testing::random_vector(n, rng, 2.0);
    const Eigen::VectorXd a = spatial::testing::random_vector(n, rng, 2.0);
    const Eigen::VectorXd tau = spatial::testing::random_vector(n, rng, 2.0);
    const auto f = spatial::testing::random_forces(n, rng);
    auto both = [&](const auto& m, const char* kind) {
      using MT = std::decay_t<decltype(m)>;
      using D = Data<double, typename MT::tree_type>;
      using DD = DerivativeData<double, typename MT::tree_type>;
      const std::string where = std::string(kind) + " tree, trial " + std::to_string(trial);
      compare_once<MT, D, DD, Model<double>, Data<double>, DerivativeData<double>>(
          m, twin, q, v, a, tau, NoExternalForces{}, ForceFrame::Body, tol, where + ", no external forces");
      compare_once<MT, D, DD, Model<double>, Data<double>, DerivativeData<double>>(
          m, twin, q, v, a, tau, f, ForceFrame::Body, tol, where + ", body-frame forces");
      compare_once<MT, D, DD, Model<double>, Data<double>, DerivativeData<double>>(
          m, twin, q, v, a, tau, f, ForceFrame::Base, tol, where + ", base-frame forces");
    };
    if constexpr (is_static_tree_v<TreeT>) both(model, "compile-time");
    both(model.to_runtime(), "run-time");
  }
}

template <class TreeT>
void compare_floating(const FloatingModel<double, TreeT>& model, unsigned seed, int trials = 4) {
  const FloatingModel<double> twin = scalar_twin(model);
  const int n = model.njoints();
  const double tol = tolerance_of(model.tree());
  std::mt19937 rng(seed);
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(n, -3.2), hi = -lo;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::VectorXd q = random_configuration(twin, lo, hi, rng);
    const Eigen::VectorXd v = spatial::testing::random_vector(n + 6, rng, 2.0);
    const Eigen::VectorXd a = spatial::testing::random_vector(n + 6, rng, 2.0);
    const Eigen::VectorXd tau = spatial::testing::random_vector(n + 6, rng, 2.0);
    const auto f = spatial::testing::random_forces(n + 1, rng);
    auto both = [&](const auto& m, const char* kind) {
      using MT = std::decay_t<decltype(m)>;
      using D = FloatingData<double, typename MT::tree_type>;
      using DD = FloatingDerivativeData<double, typename MT::tree_type>;
      using TM = FloatingModel<double>;
      const std::string where = std::string(kind) + " tree, trial " + std::to_string(trial);
      compare_once<MT, D, DD, TM, FloatingData<double>, FloatingDerivativeData<double>>(
          m, twin, q, v, a, tau, NoExternalForces{}, ForceFrame::Body, tol, where + ", no external forces");
      compare_once<MT, D, DD, TM, FloatingData<double>, FloatingDerivativeData<double>>(
          m, twin, q, v, a, tau, f, ForceFrame::Body, tol, where + ", body-frame forces");
      compare_once<MT, D, DD, TM, FloatingData<double>, FloatingDerivativeData<double>>(
          m, twin, q, v, a, tau, f, ForceFrame::Base, tol, where + ", world-frame forces");
    };
    if constexpr (is_static_tree_v<TreeT>) both(model, "compile-time");
    both(model.to_runtime(), "run-time");
  }
}

// Which of the two walks each tree takes: the test covers both.
static_assert(detail::walk_lanes<models::hoap3_stance_right::Tree>() && detail::walk_lanes<RevChain24>());
static_assert(!detail::walk_lanes<Rev9>() && !detail::walk_lanes<models::hoap3_floating::Tree>());

#if SPATIAL_SIMD_TEST_ALL_TREES
TEST(SimdDerivatives, Hoap3Stance) { compare_fixed(models::hoap3_stance_right::model(), 80); }
TEST(SimdDerivatives, Hoap3Floating) { compare_floating(models::hoap3_floating::floating_model(), 84); }
#else
TEST(SimdDerivatives, Hoap3Stance) { compare_fixed(models::hoap3_stance_right::model().to_runtime(), 80); }
TEST(SimdDerivatives, Hoap3Floating) { compare_floating(models::hoap3_floating::floating_model().to_runtime(), 84); }
#endif
TEST(SimdDerivatives, RandomTrees) {
  for (unsigned seed = 81; seed < 83; ++seed) {
    compare_fixed(random_static<Rev9>(seed), seed);
#if SPATIAL_SIMD_TEST_ALL_TREES
    compare_fixed(random_static<RevChain24>(seed), seed);
#else
    compare_fixed(random_static<RevChain24>(seed).to_runtime(), seed);
#endif
  }
}
TEST(SimdDerivatives, FloatingRandomTree) {
  compare_floating(FloatingModel<double, Rev9>(random_static<Rev9>(85), test_root_inertia()), 85);
}

}  // namespace

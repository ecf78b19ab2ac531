// The analytical derivatives on the compile-time tree of hoap3_floating (free-flyer + 21 joints, nv = 27): against
// central finite differences on the manifold and the forward-mode AD oracle, with and without external forces; and
// the run-time twin the oracle differentiates against the compile-time tree (support/derivative_checks.hpp).
// Compile-time trees only: nothing here in the sanitizer build (support/compile_time_trees.hpp).
#include <spatial/models/hoap3_floating.hpp>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build
#include "support/derivative_checks.hpp"

namespace {

using namespace spatial;
using namespace spatial::testing::derivative_checks;
using spatial::testing::random_vector;

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(RneaDerivatives, Hoap3FloatingCompileTimeTreeAgainstFiniteDifferencesAndAD) {
  const auto model = models::hoap3_floating::floating_model();
  std::mt19937 rng(14);
  const Vec lo = Vec::Constant(model.njoints(), -1.0), hi = Vec::Constant(model.njoints(), 1.0);
  const Vec q = random_configuration(model, lo, hi, rng);
  const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
  const Forces f = random_forces(model.njoints() + 1, rng);
  check_floating<true>(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces");
  check_floating<true>(model, q, v, a, f, ForceFrame::Body, "body-frame forces");
  check_floating<true>(model, q, v, a, f, ForceFrame::Base, "world-frame forces");
}

// The AD oracle differentiates a compile-time model's run-time twin: both give the same τ and q̈.
TEST(RneaDerivatives, RuntimeTwinOfACompileTimeModelGivesTheSameDynamics) {
  const auto model = models::hoap3_floating::floating_model();
  const FloatingModel<double> twin = model.to_runtime();
  std::mt19937 rng(43);
  const Vec lo = Vec::Constant(model.njoints(), -1.0), hi = Vec::Constant(model.njoints(), 1.0);
  const Vec q = random_configuration(model, lo, hi, rng);
  const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
  FloatingData<double, models::hoap3_floating::Tree> d(model);
  FloatingData<double> dt(twin);
  const Vec tau = rnea(model, d, q, v, a);
  EXPECT_LT((Vec(rnea(twin, dt, q, v, a)) - tau).cwiseAbs().maxCoeff(), 1e-13 * (1 + tau.cwiseAbs().maxCoeff()));
  const Vec qdd = aba(model, d, q, v, a);
  EXPECT_LT((Vec(aba(twin, dt, q, v, a)) - qdd).cwiseAbs().maxCoeff(), 1e-12 * (1 + qdd.cwiseAbs().maxCoeff()));
}
#endif

}  // namespace

// Analytical derivatives of RNEA and forward dynamics (derivatives.hpp) against central finite differences (on the
// configuration manifold for floating bases), with and without external forces in both frames, on random run-time
// trees of every joint type; identities (∂q̈/∂τ H = I). The HOAP-3 compile-time models, also against the forward-mode
// AD oracle, are in test_derivatives_hoap3.cpp (fixed base) and test_derivatives_hoap3_floating.cpp (floating base);
// test_autodiff.cpp checks the oracle itself and the random trees against it. The checks are in
// support/derivative_checks.hpp.
#include "support/derivative_checks.hpp"

namespace {

using namespace spatial;
using namespace spatial::testing::derivative_checks;
using spatial::testing::random_vector;
using spatial::testing::random_floating;
using spatial::testing::random_model;
using spatial::testing::Shape;

TEST(RneaDerivatives, RandomFixedTreesEveryJointTypeAgainstFiniteDifferences) {
  struct Case {
    int n;
    Shape shape;
    unsigned seed;
  };
  for (const Case c : {Case{1, Shape::Chain, 1}, Case{6, Shape::Chain, 2}, Case{12, Shape::Branched, 3},
                       Case{20, Shape::Branched, 4}}) {
    const Model<double> model = random_model(c.n, c.shape, c.seed);
    std::mt19937 rng(c.seed);
    const Vec q = random_vector(c.n, rng, 2.0), v = random_vector(c.n, rng, 2.0), a = random_vector(c.n, rng, 2.0);
    const Forces f = random_forces(c.n, rng);
    check_fixed(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces");
    check_fixed(model, q, v, a, f, ForceFrame::Body, "body-frame forces");
    check_fixed(model, q, v, a, f, ForceFrame::Base, "base-frame forces");
  }
}

TEST(RneaDerivatives, RandomFloatingTreesOnTheManifoldAgainstFiniteDifferences) {
  struct Case {
    int n;
    Shape shape;
    unsigned seed;
  };
  for (const Case c : {Case{1, Shape::Chain, 5}, Case{5, Shape::Chain, 6}, Case{14, Shape::Branched, 7}}) {
    const FloatingModel<double> model = random_floating(c.n, c.shape, c.seed);
    std::mt19937 rng(c.seed);
    const Vec lo = Vec::Constant(c.n, -2.0), hi = Vec::Constant(c.n, 2.0);
    const Vec q = random_configuration(model, lo, hi, rng);
    const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
    const Forces f = random_forces(c.n + 1, rng);
    check_floating(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces");
    check_floating(model, q, v, a, f, ForceFrame::Body, "body-frame forces");
    check_floating(model, q, v, a, f, ForceFrame::Base, "world-frame forces");
  }
}

}  // namespace

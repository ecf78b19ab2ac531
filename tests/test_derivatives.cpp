// Analytical derivatives of RNEA and forward dynamics (derivatives.hpp) against central finite differences (on the
// configuration manifold for floating bases), with and without external forces in both frames, on random run-time
// trees of every joint type; identities (∂q̈/∂τ H = I). The HOAP-3 compile-time models, also against the forward-mode
// AD oracle, are in test_derivatives_hoap3.cpp (fixed base) and test_derivatives_hoap3_floating.cpp (floating base);
// test_autodiff.cpp checks the oracle itself and the random trees against it. The checks are in
// support/derivative_checks.hpp.
#include "support/derivative_checks.hpp"

#include <limits>
#include <string>
#include <tuple>
#include <type_traits>

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

// The RNEA derivatives carry W + Wᵀ (W = I (v×), summed over subtrees) as a symmetric 3 × 3 block and a 3-vector
// (detail::VelocityCoupling); its product with a motion and its sums must equal the dense 6 × 6 form.
TEST(RneaDerivatives, VelocityCouplingEqualsTheDenseSymmetricPart) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto motion = [&] { return Motion<double>(Vector3<double>(u(rng), u(rng), u(rng)), Vector3<double>(u(rng), u(rng), u(rng))); };
  auto inertia = [&] {
    const double m = 2.0 + u(rng);
    return Inertia<double>::from_com(m, Vector3<double>(u(rng), u(rng), u(rng)), spatial::testing::random_inertia_com(rng, m));
  };
  detail::VelocityCoupling<double> sum = detail::VelocityCoupling<double>::Zero();
  Matrix6<double> dense_sum = Matrix6<double>::Zero();
  for (int body = 0; body < 4; ++body) {
    const Inertia<double> I = inertia();
    const Motion<double> v = motion();
    const Matrix6<double> W = I.matrix() * cross_matrix(v);
    const Matrix6<double> dense = W + W.transpose();
    const auto c = detail::VelocityCoupling<double>::of(I, v);
    EXPECT_LT((c.A - c.A.transpose()).cwiseAbs().maxCoeff(), 1e-15) << "A is symmetric";
    sum += c;
    dense_sum += dense;
    for (int trial = 0; trial < 3; ++trial) {
      const Motion<double> x = motion();
      const Vector6<double> expect = dense * x.vector(), got = (c * x).vector();
      EXPECT_LT((expect - got).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + expect.cwiseAbs().maxCoeff()))
          << "body " << body << ": " << got.transpose() << " against " << expect.transpose();
    }
  }
  const Motion<double> x = motion();
  const Vector6<double> expect = dense_sum * x.vector(), got = (sum * x).vector();
  EXPECT_LT((expect - got).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + expect.cwiseAbs().maxCoeff())) << "the subtree sum";
}

// aba_derivatives' products ∂q̈/∂x = −H⁻¹ ∂τ/∂x over run-time trees go column by column in strips of Eigen's packets
// (detail::runtime_products): both products at once where they fit the registers, else one after the other in strips
// of up to eight packets and a rest. Every n from 1 to 40, fixed and floating, double and float, covers every number
// of packets and every rest on this build's packet size; the result must equal the dense product of the returned
// ∂q̈/∂τ and ∂τ/∂x within the rounding of an n-term sum.
template <class S, class M>
void expect_products(const M& model, unsigned seed, const std::string& what) {
  using V = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using X = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  std::mt19937 rng(seed);
  const int nv = model.nv();
  V q;
  if constexpr (std::is_same_v<M, Model<S>>) {
    q = random_vector(nv, rng, 1.0).template cast<S>();
  } else {
    const Vec lo = Vec::Constant(model.tree().size(), -1.0), hi = -lo;
    q = random_configuration(model.template cast<double>(), lo, hi, rng).template cast<S>();
  }
  const V v = random_vector(nv, rng, 2.0).template cast<S>(), tau = random_vector(nv, rng, 2.0).template cast<S>();
  typename std::conditional_t<std::is_same_v<M, Model<S>>, Data<S>, FloatingData<S>> data(model);
  typename std::conditional_t<std::is_same_v<M, Model<S>>, DerivativeData<S>, FloatingDerivativeData<S>> dd(model);
  aba_derivatives(model, data, dd, q, v, tau);
  const X& minv = dd.dqdd_dtau;
  for (const auto& [dtau, dqdd, name] : {std::tuple<const X&, const X&, const char*>{dd.dtau_dq, dd.dqdd_dq, "dqdd_dq"},
                                         std::tuple<const X&, const X&, const char*>{dd.dtau_dv, dd.dqdd_dv, "dqdd_dv"}}) {
    const X dense = -(minv * dtau);
    const X bound = minv.cwiseAbs() * dtau.cwiseAbs();
    const S tol = S(4 * nv) * std::numeric_limits<S>::epsilon();
    const auto over = ((dqdd - dense).cwiseAbs().array() > tol * bound.array() + std::numeric_limits<S>::min()).count();
    EXPECT_EQ(over, 0) << what << ", nv = " << nv << ", " << name << ": largest difference "
                       << (dqdd - dense).cwiseAbs().maxCoeff();
  }
}

TEST(AbaDerivatives, RunTimeTreeProductsEqualTheDenseProductsAtEverySize) {
  for (int n = 1; n <= 40; ++n) {
    const unsigned seed = 200 + static_cast<unsigned>(n);
    const Shape shape = n % 2 ? Shape::Chain : Shape::Branched;
    const Model<double> fixed = random_model(n, shape, seed);
    expect_products<double>(fixed, seed, "fixed, double");
    expect_products<float>(fixed.template cast<float>(), seed, "fixed, float");
    if (n <= 34) {
      const FloatingModel<double> floating = random_floating(n, shape, seed);
      expect_products<double>(floating, seed, "floating, double");
      expect_products<float>(floating.template cast<float>(), seed, "floating, float");
    }
  }
}

}  // namespace

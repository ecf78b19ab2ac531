// The iLQR example's solver (tools/ilqr.hpp) on the HOAP-3 torso's arms, shortened (0.8 s in 40 steps): the cost
// never increases and converges, the arms reach the target at rest, the torques stay within their limits and
// saturate, and the solver fed by finite differences of ABA reaches the same optimum as the one fed by the
// analytical derivatives (whose Jacobians agree with the finite differences to their accuracy).
#include "ilqr.hpp"

#include <spatial/models/hoap3_torso.hpp>

#include <gtest/gtest.h>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build

#if SPATIAL_TEST_COMPILE_TIME_TREES
namespace {

using namespace spatial;
namespace torso = spatial::models::hoap3_torso;
using spatial::ilqr::Mat;
using spatial::ilqr::Vec;
using T = torso::Tree;

ilqr::Problem problem() {
  ilqr::Problem p;
  p.n = torso::dof;
  p.steps = 40;
  p.dt = 0.02;
  p.q0 = Vec::Zero(p.n);
  p.v0 = Vec::Zero(p.n);
  p.q_target = (Vec(p.n) << 1.4, -0.4, 0.3, -1.2, -0.8, 0.6, -0.3, -0.9).finished();
  p.W_q = 1e3, p.W_v = 1e2, p.w_q = 10, p.r = 0.1;
  p.u_max = Vec::Constant(p.n, 3.0);
  return p;
}

TEST(Ilqr, TorsoArmsReachTheTargetWithinTheTorqueLimits) {
  const auto model = torso::model();
  Data<double, T> data(model);
  DerivativeData<double, T> dd(model);
  const ilqr::Problem p = problem();
  const std::vector<Vec> u0(static_cast<std::size_t>(p.steps), gravity_torques(model, data, p.q0));
  ilqr::Options opt;
  opt.max_iterations = 100;
  ilqr::AnalyticalLinearize<Model<double, T>, Data<double, T>, DerivativeData<double, T>> an{model, data, dd};
  const ilqr::Result a = ilqr::solve(model, data, p, u0, an, opt);
  ASSERT_GE(a.iterations.size(), 2u);
  EXPECT_TRUE(a.converged);
  for (std::size_t k = 1; k < a.iterations.size(); ++k) EXPECT_LE(a.iterations[k].cost, a.iterations[k - 1].cost);
  EXPECT_LT(a.iterations.back().cost, 1e-2 * a.iterations.front().cost);
  EXPECT_LT((a.x.back().head(p.n) - p.q_target).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT(a.x.back().tail(p.n).cwiseAbs().maxCoeff(), 1e-2);
  double peak = 0;
  for (const Vec& u : a.u) {
    EXPECT_LE(u.cwiseAbs().maxCoeff(), 3.0);
    peak = std::max(peak, u.cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(peak, 3.0) << "the limits should be active in this swing";
  // The rollout is the dynamics: the stored states follow from the stored controls.
  for (std::size_t k = 0; k < a.u.size(); ++k)
    EXPECT_LT((ilqr::step(model, data, p, a.x[k], a.u[k]) - a.x[k + 1]).cwiseAbs().maxCoeff(), 1e-12);

  ilqr::FiniteDifferenceLinearize<Model<double, T>, Data<double, T>> fd{model, data, 1e-7, Vec()};
  const ilqr::Result f = ilqr::solve(model, data, p, u0, fd, opt);
  EXPECT_TRUE(f.converged);
  EXPECT_NEAR(f.iterations.back().cost, a.iterations.back().cost, 1e-4 * a.iterations.back().cost);
}

TEST(Ilqr, FiniteDifferenceLinearizationAgreesWithTheAnalyticalOne) {
  const auto model = torso::model();
  Data<double, T> data(model);
  DerivativeData<double, T> dd(model);
  const int n = torso::dof;
  const Vec q = Vec::LinSpaced(n, -0.5, 0.7), v = Vec::LinSpaced(n, 1.0, -1.0), u = Vec::LinSpaced(n, -2.0, 2.0);
  Vec qa(n), qf(n);
  Mat A[3] = {Mat(n, n), Mat(n, n), Mat(n, n)}, F[3] = {Mat(n, n), Mat(n, n), Mat(n, n)};
  ilqr::AnalyticalLinearize<Model<double, T>, Data<double, T>, DerivativeData<double, T>> an{model, data, dd};
  ilqr::FiniteDifferenceLinearize<Model<double, T>, Data<double, T>> fd{model, data, 1e-7, Vec()};
  an(q, v, u, qa, A[0], A[1], A[2]);
  fd(q, v, u, qf, F[0], F[1], F[2]);
  // q̈ itself: aba_derivatives computes it as H⁻¹(τ − bias), the finite differences by ABA; equal to round-off.
  EXPECT_LT((qa - qf).cwiseAbs().maxCoeff(), 1e-12 * (1 + qf.cwiseAbs().maxCoeff()));
  for (int k = 0; k < 3; ++k)
    EXPECT_LT((A[k] - F[k]).cwiseAbs().maxCoeff(), 1e-4 * (1 + A[k].cwiseAbs().maxCoeff())) << k;
}

}  // namespace
#endif

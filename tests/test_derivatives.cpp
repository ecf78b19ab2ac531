// Analytical derivatives of RNEA and forward dynamics (derivatives.hpp) against central finite differences (on the
// configuration manifold for floating bases), with and without external forces in both frames, on random trees of
// every joint type and on the HOAP-3 models; identities (∂q̈/∂τ H = I); repeated calls. The HOAP-3 compile-time
// models are also checked against the forward-mode AD oracle here (test_autodiff.cpp checks the oracle itself and
// the random trees against it): one translation unit instantiates their derivatives, which is most of its compile.
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/autodiff.hpp"
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build

namespace {

using namespace spatial;
using spatial::testing::random_floating;
using spatial::testing::random_model;
using spatial::testing::random_vector;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using Forces = std::vector<Force<double>>;

// Central differences with step h have truncation error h²/6 |f'''| and rounding error ε |f| / h. With h = 1e-5 and
// the states below (|f| ≲ 1e3, |f'''| ≲ 1e3) both stay under 1e-7; the tolerance, 1e-6 relative to the largest
// entry, leaves a margin of ten and is still five orders of magnitude below a wrong term (≳ 0.1 relative).
constexpr double kStep = 1e-5;
constexpr double kTol = 1e-6;

double rel_err(const Mat& a, const Mat& b) { return (a - b).cwiseAbs().maxCoeff() / (1.0 + b.cwiseAbs().maxCoeff()); }

// Against the AD oracle: its bound and error measure (support/autodiff.hpp).
using spatial::testing::ad_rel_err;
using spatial::testing::kAdTolerance;
/// Compares the RNEA derivatives in dd with the AD oracle's; M is a Model or a FloatingModel.
template <class M, class DD, class Ext>
void expect_ad_rnea(const M& model, const DD& dd, const Vec& q, const Vec& v, const Vec& a, const Ext& fext,
                    ForceFrame frame) {
  const auto r = spatial::testing::ad_rnea_derivatives(model, q, v, a, fext, frame);
  EXPECT_LT(ad_rel_err(dd.dtau_dq, r.dtau_dq), kAdTolerance) << "analytic\n" << dd.dtau_dq << "\nAD\n" << r.dtau_dq;
  EXPECT_LT(ad_rel_err(dd.dtau_dv, r.dtau_dv), kAdTolerance) << "analytic\n" << dd.dtau_dv << "\nAD\n" << r.dtau_dv;
}
/// Compares the forward dynamics derivatives in dd (at τ = tau) with the AD oracle's.
template <class M, class DD, class Ext>
void expect_ad_aba(const M& model, const DD& dd, const Vec& q, const Vec& v, const Vec& tau, const Ext& fext,
                   ForceFrame frame) {
  const auto b = spatial::testing::ad_aba_derivatives(model, q, v, tau, fext, frame);
  EXPECT_LT(ad_rel_err(dd.dqdd_dq, b.dqdd_dq), kAdTolerance);
  EXPECT_LT(ad_rel_err(dd.dqdd_dv, b.dqdd_dv), kAdTolerance);
  EXPECT_LT(ad_rel_err(dd.dqdd_dtau, b.dqdd_dtau), kAdTolerance);
}

Forces random_forces(int n, std::mt19937& rng) {
  Forces f;
  for (int i = 0; i < n; ++i) f.emplace_back(Vector6<double>(random_vector(6, rng, 3.0)));
  return f;
}

/// Central differences of x ↦ f(x) (n outputs) in the m directions `step(x, k, h)` (x ⊕ h eₖ).
template <class F, class Step>
Mat central(const Vec& x, int m, F&& f, Step&& step) {
  const Vec f0 = f(x);
  Mat J(f0.size(), m);
  for (int k = 0; k < m; ++k) J.col(k) = (f(step(x, k, kStep)) - f(step(x, k, -kStep))) / (2 * kStep);
  return J;
}
Vec plus(const Vec& x, int k, double h) {
  Vec y = x;
  y[k] += h;
  return y;
}

// ---- fixed base --------------------------------------------------------------------------------------------------

/// Against central differences, and with AD also against the AD oracle.
template <bool AD = false, class T, class Ext>
void check_fixed(const Model<double, T>& model, const Vec& q, const Vec& v, const Vec& a, const Ext& fext,
                 ForceFrame frame, const char* what) {
  SCOPED_TRACE(what);
  const int n = model.size();
  Data<double, T> data(model), ref(model);
  DerivativeData<double, T> dd(model);
  rnea_derivatives(model, data, dd, q, v, a, fext, frame);
  const Vec tau = rnea(model, ref, q, v, a, fext, frame);
  EXPECT_LT((Vec(data.tau) - tau).cwiseAbs().maxCoeff(), 1e-12 * (1 + tau.cwiseAbs().maxCoeff()));
  const Mat dq = central(q, n, [&](const Vec& x) { return Vec(rnea(model, ref, x, v, a, fext, frame)); }, plus);
  const Mat dv = central(v, n, [&](const Vec& x) { return Vec(rnea(model, ref, q, x, a, fext, frame)); }, plus);
  EXPECT_LT(rel_err(dd.dtau_dq, dq), kTol) << "analytic\n" << dd.dtau_dq << "\nfinite differences\n" << dq;
  EXPECT_LT(rel_err(dd.dtau_dv, dv), kTol) << "analytic\n" << dd.dtau_dv << "\nfinite differences\n" << dv;
  if constexpr (AD) expect_ad_rnea(model, dd, q, v, a, fext, frame);

  // Forward dynamics: against central differences of ABA, and ∂q̈/∂τ = H⁻¹.
  std::mt19937 rng(static_cast<unsigned>(n));
  const Vec tau_in = random_vector(n, rng, 2.0);
  aba_derivatives(model, data, dd, q, v, tau_in, fext, frame);
  const Vec qdd = aba(model, ref, q, v, tau_in, fext, frame);
  EXPECT_LT((Vec(data.qdd) - qdd).cwiseAbs().maxCoeff(), 1e-12 * (1 + qdd.cwiseAbs().maxCoeff()));
  const auto fd = [&](const Vec& x, const Vec& y, const Vec& t) { return Vec(aba(model, ref, x, y, t, fext, frame)); };
  const Mat aq = central(q, n, [&](const Vec& x) { return fd(x, v, tau_in); }, plus);
  const Mat av = central(v, n, [&](const Vec& x) { return fd(q, x, tau_in); }, plus);
  const Mat at = central(tau_in, n, [&](const Vec& x) { return fd(q, v, x); }, plus);
  EXPECT_LT(rel_err(dd.dqdd_dq, aq), kTol);
  EXPECT_LT(rel_err(dd.dqdd_dv, av), kTol);
  EXPECT_LT(rel_err(dd.dqdd_dtau, at), kTol);
  if constexpr (AD) expect_ad_aba(model, dd, q, v, tau_in, fext, frame);
  const Mat H = crba(model, ref, q);
  EXPECT_TRUE(Mat(dd.dqdd_dtau) == Mat(dd.minv.Minv));  // H⁻¹ by inverse_inertia, kept in dd.minv
  EXPECT_LT((Mat(dd.dqdd_dtau) * H - Mat::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-10);
}

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

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(RneaDerivatives, Hoap3StanceCompileTimeTreeAgainstFiniteDifferencesAndAD) {
  const auto model = models::hoap3_stance_right::model();
  const int n = model.size();
  std::mt19937 rng(11);
  const Vec q = random_vector(n, rng, 1.0), v = random_vector(n, rng, 2.0), a = random_vector(n, rng, 2.0);
  const Forces f = random_forces(n, rng);
  check_fixed<true>(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces");
  check_fixed<true>(model, q, v, a, f, ForceFrame::Body, "body-frame forces");
  check_fixed<true>(model, q, v, a, f, ForceFrame::Base, "base-frame forces");
}
#endif

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(RneaDerivatives, RepeatedCallsAndOtherStatesLeaveNothingBehind) {
  const auto model = models::hoap3_stance_right::model();
  using T = models::hoap3_stance_right::Tree;
  const int n = model.size();
  std::mt19937 rng(12);
  Data<double, T> data(model);
  DerivativeData<double, T> dd(model);
  const Vec q1 = random_vector(n, rng), v1 = random_vector(n, rng), a1 = random_vector(n, rng);
  const Vec q2 = random_vector(n, rng), v2 = random_vector(n, rng), a2 = random_vector(n, rng);
  rnea_derivatives(model, data, dd, q1, v1, a1);
  const Mat first_q = dd.dtau_dq, first_v = dd.dtau_dv;
  rnea_derivatives(model, data, dd, q2, v2, a2, random_forces(n, rng), ForceFrame::Base);
  rnea_derivatives(model, data, dd, q1, v1, a1);
  EXPECT_EQ(Mat(dd.dtau_dq), first_q);
  EXPECT_EQ(Mat(dd.dtau_dv), first_v);
  // Entries between joints of different branches (neither an ancestor of the other) are structurally zero.
  const auto ancestor = [&](int i, int j) {  // j ⪯ i
    for (int k = i; k >= 0; k = model.parent(k))
      if (k == j) return true;
    return false;
  };
  int unrelated = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (!ancestor(i, j) && !ancestor(j, i)) {
        ++unrelated;
        EXPECT_EQ(dd.dtau_dq(i, j), 0.0) << i << ", " << j;
        EXPECT_EQ(dd.dtau_dv(i, j), 0.0) << i << ", " << j;
      }
  EXPECT_GT(unrelated, 0);
}
#endif

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(RneaDerivatives, FloatMatchesDouble) {
  const auto model = models::hoap3_stance_right::model();
  const auto mf = model.cast<float>();
  using T = models::hoap3_stance_right::Tree;
  const int n = model.size();
  std::mt19937 rng(13);
  const Vec q = random_vector(n, rng), v = random_vector(n, rng), a = random_vector(n, rng);
  Data<double, T> d(model);
  DerivativeData<double, T> dd(model);
  Data<float, T> df(mf);
  DerivativeData<float, T> ddf(mf);
  rnea_derivatives(model, d, dd, q, v, a);
  rnea_derivatives(mf, df, ddf, q.cast<float>(), v.cast<float>(), a.cast<float>());
  EXPECT_LT(rel_err(ddf.dtau_dq.cast<double>(), dd.dtau_dq), 1e-5);
  EXPECT_LT(rel_err(ddf.dtau_dv.cast<double>(), dd.dtau_dv), 1e-5);
}
#endif

// ---- floating base -----------------------------------------------------------------------------------------------

/// Against central differences on the manifold, and with AD also against the AD oracle.
template <bool AD = false, class T, class Ext>
void check_floating(const FloatingModel<double, T>& model, const Vec& q, const Vec& v, const Vec& a,
                    const Ext& fext, ForceFrame frame, const char* what) {
  SCOPED_TRACE(what);
  const int nv = model.nv();
  FloatingData<double, T> data(model), ref(model);
  FloatingDerivativeData<double, T> dd(model);
  const auto step = [&](const Vec& x, int k, double h) {
    Vec d = Vec::Zero(nv);
    d[k] = h;
    return Vec(integrate(model, x, d, 1.0));
  };
  rnea_derivatives(model, data, dd, q, v, a, fext, frame);
  const Vec tau = rnea(model, ref, q, v, a, fext, frame);
  EXPECT_LT((Vec(data.tau) - tau).cwiseAbs().maxCoeff(), 1e-12 * (1 + tau.cwiseAbs().maxCoeff()));
  const Mat dq = central(q, nv, [&](const Vec& x) { return Vec(rnea(model, ref, x, v, a, fext, frame)); }, step);
  const Mat dv = central(v, nv, [&](const Vec& x) { return Vec(rnea(model, ref, q, x, a, fext, frame)); }, plus);
  EXPECT_LT(rel_err(dd.dtau_dq, dq), kTol) << "analytic\n" << dd.dtau_dq << "\nfinite differences\n" << dq;
  EXPECT_LT(rel_err(dd.dtau_dv, dv), kTol) << "analytic\n" << dd.dtau_dv << "\nfinite differences\n" << dv;
  if constexpr (AD) expect_ad_rnea(model, dd, q, v, a, fext, frame);

  std::mt19937 rng(nv);
  const Vec tau_in = random_vector(nv, rng, 2.0);
  aba_derivatives(model, data, dd, q, v, tau_in, fext, frame);
  const auto fd = [&](const Vec& x, const Vec& y, const Vec& t) { return Vec(aba(model, ref, x, y, t, fext, frame)); };
  const Vec qdd = fd(q, v, tau_in);
  EXPECT_LT((Vec(data.qdd) - qdd).cwiseAbs().maxCoeff(), 1e-12 * (1 + qdd.cwiseAbs().maxCoeff()));
  EXPECT_LT(rel_err(dd.dqdd_dq, central(q, nv, [&](const Vec& x) { return fd(x, v, tau_in); }, step)), kTol);
  EXPECT_LT(rel_err(dd.dqdd_dv, central(v, nv, [&](const Vec& x) { return fd(q, x, tau_in); }, plus)), kTol);
  EXPECT_LT(rel_err(dd.dqdd_dtau, central(tau_in, nv, [&](const Vec& x) { return fd(q, v, x); }, plus)), kTol);
  if constexpr (AD) expect_ad_aba(model, dd, q, v, tau_in, fext, frame);
  const Mat H = crba(model, ref, q);
  EXPECT_TRUE(Mat(dd.dqdd_dtau) == Mat(dd.minv.Minv));  // H⁻¹ by inverse_inertia, kept in dd.minv
  EXPECT_LT((Mat(dd.dqdd_dtau) * H - Mat::Identity(nv, nv)).cwiseAbs().maxCoeff(), 1e-10);
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

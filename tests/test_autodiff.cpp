// The library on a forward-mode AD scalar (tests/support/autodiff.hpp), and the analytical derivatives of RNEA and
// forward dynamics (derivatives.hpp) against it: to 1e-12 relative to the largest entry, on random fixed and
// floating trees of every joint type with and without external forces in both frames (the HOAP-3 compile-time
// models: tests/test_derivatives_hoap3*.cpp). Also: the dual number's own derivatives against known
// formulas, the AD values against the double results, the AD oracle against central differences (so that a wrong
// oracle cannot pass), and integrate/difference differentiated at zero rotation.
#include <spatial/spatial.hpp>

#include "support/autodiff.hpp"
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::ad_aba_derivatives;
using spatial::testing::ad_rel_err;
using spatial::testing::ad_rnea_derivatives;
using spatial::testing::Dual;
using spatial::testing::random_floating;
using spatial::testing::random_model;
using spatial::testing::random_vector;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using Forces = std::vector<Force<double>>;

constexpr double kTol = spatial::testing::kAdTolerance;

/// The largest relative difference seen per quantity, printed at the end of each test (for the report).
struct Worst {
  double dtau_dq = 0, dtau_dv = 0, dqdd_dq = 0, dqdd_dv = 0, dqdd_dtau = 0;
  void print(const char* what) const {
    std::printf("[ AD max rel. diff ] %s: dtau_dq %.2e  dtau_dv %.2e  dqdd_dq %.2e  dqdd_dv %.2e  dqdd_dtau %.2e\n",
                what, dtau_dq, dtau_dv, dqdd_dq, dqdd_dv, dqdd_dtau);
  }
};

Forces random_forces(int n, std::mt19937& rng) {
  Forces f;
  for (int i = 0; i < n; ++i) f.emplace_back(Vector6<double>(random_vector(6, rng, 3.0)));
  return f;
}

/// Checks one value-and-derivative pair: |x.val − f| and |x.der − df| to 4 ulp-ish relative.
void expect_dual(const Dual& x, double f, double df, const char* what) {
  EXPECT_NEAR(x.val, f, 4e-16 * (1 + std::abs(f))) << what;
  EXPECT_NEAR(x.der, df, 4e-15 * (1 + std::abs(df))) << what;
}

// ---- the dual number itself ------------------------------------------------------------------------------------

TEST(Autodiff, DualNumberDerivativesOfElementaryFunctions) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  for (const double x0 : {-2.3, -0.7, 0.3, 1.1, 2.9}) {
    const Dual x(x0, 1.0);
    expect_dual(sin(x), std::sin(x0), std::cos(x0), "sin");
    expect_dual(cos(x), std::cos(x0), -std::sin(x0), "cos");
    expect_dual(tan(x), std::tan(x0), 1.0 / (std::cos(x0) * std::cos(x0)), "tan");
    expect_dual(atan(x), std::atan(x0), 1.0 / (1.0 + x0 * x0), "atan");
    expect_dual(exp(x), std::exp(x0), std::exp(x0), "exp");
    expect_dual(abs(x), std::abs(x0), x0 < 0 ? -1.0 : 1.0, "abs");
    expect_dual(x * x * x, x0 * x0 * x0, 3 * x0 * x0, "x^3");
    expect_dual(1.0 / x, 1.0 / x0, -1.0 / (x0 * x0), "1/x");
    expect_dual((x + 2.0) / (x - 5.0), (x0 + 2) / (x0 - 5), -7.0 / ((x0 - 5) * (x0 - 5)), "quotient");
    expect_dual(sin(x * x), std::sin(x0 * x0), 2 * x0 * std::cos(x0 * x0), "chain rule");
    const double ax = std::abs(x0);
    expect_dual(sqrt(abs(x)), std::sqrt(ax), (x0 < 0 ? -1.0 : 1.0) / (2 * std::sqrt(ax)), "sqrt");
    expect_dual(log(abs(x)), std::log(ax), 1.0 / x0, "log");
    expect_dual(pow(abs(x), 2.5), std::pow(ax, 2.5), (x0 < 0 ? -2.5 : 2.5) * std::pow(ax, 1.5), "pow");
    if (ax < 1) {
      expect_dual(asin(x), std::asin(x0), 1 / std::sqrt(1 - x0 * x0), "asin");
      expect_dual(acos(x), std::acos(x0), -1 / std::sqrt(1 - x0 * x0), "acos");
    }
    // atan2 in every quadrant, by each argument: ∂/∂y = x/(x² + y²), ∂/∂x = −y/(x² + y²).
    for (const double c : {-1.7, 0.4}) {
      const double r2 = x0 * x0 + c * c;
      expect_dual(atan2(x, Dual(c)), std::atan2(x0, c), c / r2, "atan2 by y");
      expect_dual(atan2(Dual(c), x), std::atan2(c, x0), -c / r2, "atan2 by x");
    }
  }
  // Comparisons see the value only; the derivative of a constant is 0; NaN derivatives are not finite.
  EXPECT_TRUE(Dual(1.0, 5.0) == Dual(1.0, -3.0));
  EXPECT_TRUE(Dual(1.0, 5.0) < 2.0);
  EXPECT_EQ(Dual(3.0).der, 0.0);
  EXPECT_FALSE(isfinite(sqrt(Dual(0.0, 1.0))));
  EXPECT_TRUE(isfinite(Dual(1.0, 2.0)));
  // Through Eigen: d/dt |x + t d|² = 2 x·d, d/dt (x + t d)/|x + t d| = (d − u (u·d)) / |x|.
  const Eigen::Vector3d x0(0.3, -1.2, 2.0), d(0.5, 0.1, -0.7);
  Eigen::Matrix<Dual, 3, 1> x;
  for (int i = 0; i < 3; ++i) x[i] = Dual(x0[i], d[i]);
  expect_dual(x.squaredNorm(), x0.squaredNorm(), 2 * x0.dot(d), "squaredNorm");
  const Eigen::Matrix<Dual, 3, 1> u = x.normalized();
  const Eigen::Vector3d u0 = x0.normalized(), du = (d - u0 * u0.dot(d)) / x0.norm();
  for (int i = 0; i < 3; ++i) expect_dual(u[i], u0[i], du[i], "normalized");
}

// ---- the library on duals: values ------------------------------------------------------------------------------

TEST(Autodiff, DualValuesEqualTheDoubleResults) {
  // The value part of every algorithm run on duals is the double computation (up to the order of rounding: Eigen
  // vectorises double but not Dual arithmetic, and the library's own sin/cos serve double, std::sin/cos duals).
  const auto close = [](const Vec& a, const Vec& b) {
    return (a - b).cwiseAbs().maxCoeff() / (1 + b.cwiseAbs().maxCoeff());
  };
  {
    const Model<double> model = random_model(12, Shape::Branched, 21);
    const Model<Dual> md = model.cast<Dual>();
    std::mt19937 rng(21);
    const Vec q = random_vector(12, rng, 2.0), v = random_vector(12, rng, 2.0), a = random_vector(12, rng, 2.0);
    const Forces f = random_forces(12, rng);
    Data<double> d(model);
    Data<Dual> dd(md);
    using spatial::testing::seeded;
    using spatial::testing::values;
    for (const ForceFrame frame : {ForceFrame::Body, ForceFrame::Base}) {
      const auto fd = spatial::testing::detail_ad::dual_forces(f);
      EXPECT_LT(close(values(rnea(md, dd, seeded(q), seeded(v), seeded(a), fd, frame)),
                      rnea(model, d, q, v, a, f, frame)), 1e-14);
      EXPECT_LT(close(values(aba(md, dd, seeded(q), seeded(v), seeded(a), fd, frame)),
                      aba(model, d, q, v, a, f, frame)), 1e-13);
    }
    const Eigen::Matrix<Dual, Eigen::Dynamic, Eigen::Dynamic> Hd = crba(md, dd, seeded(q));
    Mat H(12, 12);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) H(i, j) = Hd(i, j).val;
    EXPECT_LT((H - crba(model, d, q)).cwiseAbs().maxCoeff(), 1e-14 * (1 + H.cwiseAbs().maxCoeff()));
    // CRBA-based forward dynamics (Eigen's Cholesky on duals) and the analytical derivatives themselves on duals.
    EXPECT_LT(close(values(forward_dynamics_crba(md, dd, seeded(q), seeded(v), seeded(a))), aba(model, d, q, v, a)),
              1e-12);
    DerivativeData<Dual> ddd(md);
    DerivativeData<double> ddv(model);
    rnea_derivatives(md, dd, ddd, seeded(q), seeded(v), seeded(a));
    rnea_derivatives(model, d, ddv, q, v, a);
    Mat dq(12, 12);
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) dq(i, j) = ddd.dtau_dq(i, j).val;
    EXPECT_LT(ad_rel_err(dq, ddv.dtau_dq), 1e-14);
    // The AD oracle's value outputs.
    const auto r = ad_rnea_derivatives(model, q, v, a, f, ForceFrame::Base);
    EXPECT_LT(close(r.tau, rnea(model, d, q, v, a, f, ForceFrame::Base)), 1e-14);
    const auto b = ad_aba_derivatives(model, q, v, a);
    EXPECT_LT(close(b.qdd, aba(model, d, q, v, a)), 1e-13);
  }
  {
    const FloatingModel<double> model = random_floating(9, Shape::Branched, 22);
    const FloatingModel<Dual> md = model.cast<Dual>();
    std::mt19937 rng(22);
    const Vec q = random_configuration(model, Vec::Constant(9, -2.0), Vec::Constant(9, 2.0), rng);
    const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
    const Forces f = random_forces(10, rng);
    FloatingData<double> d(model);
    const auto r = ad_rnea_derivatives(model, q, v, a, f, ForceFrame::Base);
    EXPECT_LT(close(r.tau, rnea(model, d, q, v, a, f, ForceFrame::Base)), 1e-14);
    const auto b = ad_aba_derivatives(model, q, v, a, f, ForceFrame::Body);
    EXPECT_LT(close(b.qdd, aba(model, d, q, v, a, f, ForceFrame::Body)), 1e-13);
    // integrate and difference on duals: values as in double.
    using spatial::testing::seeded;
    using spatial::testing::values;
    const Vec dv = random_vector(model.nv(), rng, 1.0);
    EXPECT_LT(close(values(integrate(md, seeded(q), seeded(dv), Dual(0.5))), integrate(model, q, dv, 0.5)), 1e-15);
    const Vec q1 = integrate(model, q, dv);
    EXPECT_LT(close(values(difference(md, seeded(q), seeded(q1))), difference(model, q, q1)), 1e-14);
  }
}

// ---- integrate / difference at zero rotation ---------------------------------------------------------------------

TEST(Autodiff, IntegrateAndDifferenceDifferentiateThroughZeroRotation) {
  using spatial::testing::derivatives;
  using spatial::testing::seeded;
  const FloatingModel<double> model = random_floating(3, Shape::Chain, 23);
  const FloatingModel<Dual> md = model.cast<Dual>();
  std::mt19937 rng(23);
  const Vec q = random_configuration(model, Vec::Constant(3, -2.0), Vec::Constant(3, 2.0), rng);
  const int nv = model.nv();
  for (const double scale : {0.0, 1e-5, 1e-3, 0.5}) {  // the rotation about which we differentiate: 0, small, large
    SCOPED_TRACE(scale);
    const Vec w = scale * random_vector(nv, rng, 1.0);
    const Vec qw = integrate(model, q, w);
    for (int k = 0; k < nv; ++k) {
      // d/dε integrate(q, w + ε e_k), against central differences (step 1e-6: error ~1e-11).
      Eigen::Matrix<Dual, Eigen::Dynamic, 1> wd = seeded(w, k);
      const Vec ad = derivatives(integrate(md, seeded(q), wd, Dual(1.0)));
      Vec wp = w, wm = w;
      wp[k] += 1e-6;
      wm[k] -= 1e-6;
      const Vec fd = (integrate(model, q, wp) - integrate(model, q, wm)) / 2e-6;
      EXPECT_LT((ad - fd).cwiseAbs().maxCoeff(), 1e-8) << "integrate, column " << k;
      // difference(q, q ⊕ ε e_k) = ε e_k exactly, so its derivative is e_k (through integrate and difference).
      if (scale == 0.0) {
        const Vec dd = derivatives(difference(md, seeded(q), spatial::testing::detail_ad::moved(md, q, k)));
        EXPECT_LT((dd - Vec::Unit(nv, k)).cwiseAbs().maxCoeff(), 1e-14) << "difference, column " << k;
      }
      // d/dε difference(q, qw ⊕ ε e_k), against central differences.
      Eigen::Matrix<Dual, Eigen::Dynamic, 1> qe(model.nq());
      integrate(md, seeded(qw), seeded(Vec::Zero(nv), k), Dual(1.0), qe);
      const Vec ad2 = derivatives(difference(md, seeded(q), qe));
      const Vec fd2 = (difference(model, q, integrate(model, qw, Vec(1e-6 * Vec::Unit(nv, k)))) -
                       difference(model, q, integrate(model, qw, Vec(-1e-6 * Vec::Unit(nv, k))))) / 2e-6;
      EXPECT_LT((ad2 - fd2).cwiseAbs().maxCoeff(), 1e-7) << "difference, column " << k;
      EXPECT_TRUE(ad.allFinite() && ad2.allFinite());
    }
  }
}

// ---- the oracle against finite differences (it can fail) -------------------------------------------------------

TEST(Autodiff, OracleAgreesWithCentralDifferences) {
  const FloatingModel<double> model = random_floating(6, Shape::Branched, 24);
  std::mt19937 rng(24);
  const Vec q = random_configuration(model, Vec::Constant(6, -2.0), Vec::Constant(6, 2.0), rng);
  const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
  const Forces f = random_forces(7, rng);
  const auto r = ad_rnea_derivatives(model, q, v, a, f, ForceFrame::Base);
  FloatingData<double> d(model);
  const int nv = model.nv();
  Mat dq(nv, nv), dv(nv, nv);
  const double h = 1e-5;
  for (int k = 0; k < nv; ++k) {
    const Vec e = Vec::Unit(nv, k);
    // (rnea returns a reference to d.tau: copy each result before the next call)
    const auto tau = [&](const Vec& x, const Vec& y) { return Vec(rnea(model, d, x, y, a, f, ForceFrame::Base)); };
    dq.col(k) = (tau(integrate(model, q, Vec(h * e)), v) - tau(integrate(model, q, Vec(-h * e)), v)) / (2 * h);
    dv.col(k) = (tau(q, v + h * e) - tau(q, v - h * e)) / (2 * h);
  }
  EXPECT_LT(ad_rel_err(dq, r.dtau_dq), 1e-7);
  EXPECT_LT(ad_rel_err(dv, r.dtau_dv), 1e-7);
  // A wrong matrix is caught at the tolerance used below: one entry off by 1e-9 relative.
  Mat wrong = r.dtau_dq;
  wrong(nv - 1, 2) += 1e-9 * r.dtau_dq.cwiseAbs().maxCoeff();
  EXPECT_GT(ad_rel_err(wrong, r.dtau_dq), kTol);
}

// ---- analytical derivatives against AD ---------------------------------------------------------------------------

template <class T, class Ext>
void check_fixed(const Model<double, T>& model, const Vec& q, const Vec& v, const Vec& a, const Ext& fext,
                 ForceFrame frame, const char* what, Worst& worst) {
  SCOPED_TRACE(what);
  const int n = model.size();
  Data<double, T> data(model);
  DerivativeData<double, T> dd(model);
  rnea_derivatives(model, data, dd, q, v, a, fext, frame);
  const auto r = ad_rnea_derivatives(model, q, v, a, fext, frame);
  const double eq = ad_rel_err(dd.dtau_dq, r.dtau_dq), ev = ad_rel_err(dd.dtau_dv, r.dtau_dv);
  EXPECT_LT(eq, kTol) << "analytic\n" << dd.dtau_dq << "\nAD\n" << r.dtau_dq;
  EXPECT_LT(ev, kTol) << "analytic\n" << dd.dtau_dv << "\nAD\n" << r.dtau_dv;

  std::mt19937 rng(static_cast<unsigned>(n));
  const Vec tau = random_vector(n, rng, 2.0);
  aba_derivatives(model, data, dd, q, v, tau, fext, frame);
  const auto b = ad_aba_derivatives(model, q, v, tau, fext, frame);
  const double fq = ad_rel_err(dd.dqdd_dq, b.dqdd_dq), fv = ad_rel_err(dd.dqdd_dv, b.dqdd_dv);
  const double ft = ad_rel_err(dd.dqdd_dtau, b.dqdd_dtau);
  EXPECT_LT(fq, kTol);
  EXPECT_LT(fv, kTol);
  EXPECT_LT(ft, kTol);
  worst.dtau_dq = std::max(worst.dtau_dq, eq);
  worst.dtau_dv = std::max(worst.dtau_dv, ev);
  worst.dqdd_dq = std::max(worst.dqdd_dq, fq);
  worst.dqdd_dv = std::max(worst.dqdd_dv, fv);
  worst.dqdd_dtau = std::max(worst.dqdd_dtau, ft);
}

template <class T, class Ext>
void check_floating(const FloatingModel<double, T>& model, const Vec& q, const Vec& v, const Vec& a,
                    const Ext& fext, ForceFrame frame, const char* what, Worst& worst) {
  SCOPED_TRACE(what);
  const int nv = model.nv();
  FloatingData<double, T> data(model);
  FloatingDerivativeData<double, T> dd(model);
  rnea_derivatives(model, data, dd, q, v, a, fext, frame);
  const auto r = ad_rnea_derivatives(model, q, v, a, fext, frame);
  const double eq = ad_rel_err(dd.dtau_dq, r.dtau_dq), ev = ad_rel_err(dd.dtau_dv, r.dtau_dv);
  EXPECT_LT(eq, kTol) << "analytic\n" << dd.dtau_dq << "\nAD\n" << r.dtau_dq;
  EXPECT_LT(ev, kTol) << "analytic\n" << dd.dtau_dv << "\nAD\n" << r.dtau_dv;

  std::mt19937 rng(static_cast<unsigned>(nv));
  const Vec tau = random_vector(nv, rng, 2.0);
  aba_derivatives(model, data, dd, q, v, tau, fext, frame);
  const auto b = ad_aba_derivatives(model, q, v, tau, fext, frame);
  const double fq = ad_rel_err(dd.dqdd_dq, b.dqdd_dq), fv = ad_rel_err(dd.dqdd_dv, b.dqdd_dv);
  const double ft = ad_rel_err(dd.dqdd_dtau, b.dqdd_dtau);
  EXPECT_LT(fq, kTol);
  EXPECT_LT(fv, kTol);
  EXPECT_LT(ft, kTol);
  worst.dtau_dq = std::max(worst.dtau_dq, eq);
  worst.dtau_dv = std::max(worst.dtau_dv, ev);
  worst.dqdd_dq = std::max(worst.dqdd_dq, fq);
  worst.dqdd_dv = std::max(worst.dqdd_dv, fv);
  worst.dqdd_dtau = std::max(worst.dqdd_dtau, ft);
}

struct Case {
  int n;
  Shape shape;
  unsigned seed;
};

TEST(Autodiff, RandomFixedTreesEveryJointTypeAnalyticalMatchesAD) {
  Worst worst;
  std::set<JointType> types;
  for (const Case c : {Case{1, Shape::Chain, 31}, Case{7, Shape::Chain, 32}, Case{12, Shape::Branched, 33},
                       Case{20, Shape::Branched, 34}}) {
    const Model<double> model = random_model(c.n, c.shape, c.seed);
    for (int i = 0; i < c.n; ++i) types.insert(model.joint_type(i));
    std::mt19937 rng(c.seed);
    const Vec q = random_vector(c.n, rng, 2.0), v = random_vector(c.n, rng, 2.0), a = random_vector(c.n, rng, 2.0);
    const Forces f = random_forces(c.n, rng);
    check_fixed(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces", worst);
    check_fixed(model, q, v, a, f, ForceFrame::Body, "body-frame forces", worst);
    check_fixed(model, q, v, a, f, ForceFrame::Base, "base-frame forces", worst);
  }
  EXPECT_EQ(types.size(), 8u) << "every joint type (revolute and prismatic, X/Y/Z/axis) is covered";
  worst.print("random fixed trees");
}

TEST(Autodiff, RandomFloatingTreesEveryJointTypeAnalyticalMatchesAD) {
  Worst worst;
  std::set<JointType> types;
  for (const Case c : {Case{1, Shape::Chain, 35}, Case{6, Shape::Chain, 36}, Case{15, Shape::Branched, 37},
                       Case{20, Shape::Branched, 34}}) {
    const FloatingModel<double> model = random_floating(c.n, c.shape, c.seed);
    for (int i = 0; i < c.n; ++i) types.insert(model.tree().joint_type(i));
    std::mt19937 rng(c.seed);
    const Vec q = random_configuration(model, Vec::Constant(c.n, -2.0), Vec::Constant(c.n, 2.0), rng);
    const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
    const Forces f = random_forces(c.n + 1, rng);
    check_floating(model, q, v, a, NoExternalForces{}, ForceFrame::Body, "no external forces", worst);
    check_floating(model, q, v, a, f, ForceFrame::Body, "body-frame forces", worst);
    check_floating(model, q, v, a, f, ForceFrame::Base, "world-frame forces", worst);
  }
  // At the neutral configuration (identity orientation: the tangent directions leave from θ = 0 about the world
  // axes) and with zero velocity.
  const FloatingModel<double> model = random_floating(5, Shape::Branched, 38);
  std::mt19937 rng(38);
  const Vec q = neutral(model), v = Vec::Zero(model.nv()), a = random_vector(model.nv(), rng, 2.0);
  check_floating(model, q, v, a, random_forces(6, rng), ForceFrame::Base, "neutral configuration", worst);
  EXPECT_EQ(types.size(), 8u) << "every joint type (revolute and prismatic, X/Y/Z/axis) is covered";
  worst.print("random floating trees");
}

// The HOAP-3 compile-time models against this oracle: tests/test_derivatives_hoap3.cpp and
// tests/test_derivatives_hoap3_floating.cpp (Hoap3*AgainstFiniteDifferencesAndAD,
// RuntimeTwinOfACompileTimeModelGivesTheSameDynamics), where their derivatives are instantiated anyway.

}  // namespace

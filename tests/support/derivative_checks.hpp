#pragma once
// What the derivative tests share (test_derivatives.cpp: random trees; test_derivatives_hoap3*.cpp: the HOAP-3
// compile-time models): the finite-difference and AD comparisons of the RNEA and forward-dynamics derivatives.
// In one file (GCC 12, 2026-12-02) they compiled in 30 CPU-s on random run-time trees alone, but in 357 at -O3 and 204
// at -O1 with the compile-time HOAP-3 trees (every derivative algorithm unrolled over 21 and 27 coordinates, for two
// kinds of external forces and two scalar types), so those cases are split over two more files that the build
// compiles side by side.
#include <spatial/spatial.hpp>

#include "support/autodiff.hpp"
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace spatial::testing::derivative_checks {

using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using Forces = std::vector<Force<double>>;

// Central differences with step h have truncation error h²/6 |f'''| and rounding error ε |f| / h. With h = 1e-5 and
// the states below (|f| ≲ 1e3, |f'''| ≲ 1e3) both stay under 1e-7; the tolerance, 1e-6 relative to the largest
// entry, leaves a margin of ten and is still five orders of magnitude below a wrong term (≳ 0.1 relative).
constexpr double kStep = 1e-5;
constexpr double kTol = 1e-6;

inline double rel_err(const Mat& a, const Mat& b) {
  return (a - b).cwiseAbs().maxCoeff() / (1.0 + b.cwiseAbs().maxCoeff());
}

// Against the AD oracle: its bound and error measure are ad_rel_err and kAdTolerance (support/autodiff.hpp).
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

using spatial::testing::random_forces;

/// Central differences of x ↦ f(x) (n outputs) in the m directions `step(x, k, h)` (x ⊕ h eₖ).
template <class F, class Step>
Mat central(const Vec& x, int m, F&& f, Step&& step) {
  const Vec f0 = f(x);
  Mat J(f0.size(), m);
  for (int k = 0; k < m; ++k) J.col(k) = (f(step(x, k, kStep)) - f(step(x, k, -kStep))) / (2 * kStep);
  return J;
}
inline Vec plus(const Vec& x, int k, double h) {
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
  // ∂q̈/∂x = −H⁻¹ ∂τ/∂x as dense products (aba_derivatives sums only over ∂τ/∂x's structural non-zeros; dd.dtau_*
  // hold RNEA's derivatives at q̈ = FD(τ) on return).
  EXPECT_LT(rel_err(dd.dqdd_dq, Mat(-Mat(dd.minv.Minv) * Mat(dd.dtau_dq))), 1e-13);
  EXPECT_LT(rel_err(dd.dqdd_dv, Mat(-Mat(dd.minv.Minv) * Mat(dd.dtau_dv))), 1e-13);
}

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
  // ∂q̈/∂x = −H⁻¹ ∂τ/∂x as dense products (aba_derivatives sums only over ∂τ/∂x's structural non-zeros; dd.dtau_*
  // hold RNEA's derivatives at q̈ = FD(τ) on return).
  EXPECT_LT(rel_err(dd.dqdd_dq, Mat(-Mat(dd.minv.Minv) * Mat(dd.dtau_dq))), 1e-13);
  EXPECT_LT(rel_err(dd.dqdd_dv, Mat(-Mat(dd.minv.Minv) * Mat(dd.dtau_dv))), 1e-13);
}

}  // namespace spatial::testing::derivative_checks

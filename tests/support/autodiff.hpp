#pragma once
// Forward-mode automatic differentiation for the test suites (not part of the installed library): a dual number
// `Dual`, the Eigen and standard-library glue that lets the library's scalar-templated algorithms run on it, and
// the AD oracle of the analytical derivatives (derivatives.hpp):
//
//   ad_rnea_derivatives(model, q, v, a[, fext, frame])  → {dtau_dq, dtau_dv, tau}
//   ad_aba_derivatives(model, q, v, tau[, fext, frame]) → {dqdd_dq, dqdd_dv, dqdd_dtau, qdd}
//
// for fixed (`Model<double, T>`) and floating (`FloatingModel<double, T>`) bases. A floating base is differentiated
// in the tangent space, as the analytical derivatives are: column k is d/dε f(integrate(q, ε e_k)) at ε = 0, the
// dual number carrying ε through `integrate` itself. Compile-time trees are differentiated through their run-time
// twin (`to_runtime()`: the same joints, transforms, inertias and parents over a run-time tree), so that the oracle
// does not instantiate the unrolled compile-time algorithms a second time, for a scalar the optimiser knows nothing
// about.
//
// Why one derivative per dual number (value + one tangent, n passes for n columns) rather than a vector of
// derivatives carried along in one pass: the oracle must be obviously right, not fast. With one tangent every
// operation is a two-line rule (the chain rule of one function of one variable) that can be read against a calculus
// table; the type is two doubles, trivially copyable, needs no allocation and no size known at compile time (the
// models have 1 to 27 velocity coordinates), and Eigen treats it like any small scalar. The price, n + 1 runs of an
// O(n) algorithm per matrix instead of one run on n-wide scalars, is microseconds on the trees tested here.
// Derivatives are exact up to floating-point rounding (no step size), so the analytical derivatives can be held to
// ~1e-12 relative, six orders of magnitude tighter than finite differences allow.

#include <spatial/spatial.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <type_traits>
#include <utility>
#include <vector>

namespace spatial::testing {

/// A dual number x + x′ε (ε² = 0): `val` is the value, `der` the derivative along the one direction being seeded.
/// Comparisons look at the value only (so the library's branches are taken as for the double value; the derivative
/// is that of the branch taken).
struct Dual {
  double val = 0.0;
  double der = 0.0;

  constexpr Dual() = default;
  /// A constant (derivative 0) from any arithmetic value: lets the library write S(0), S(1e-4), S(q[i]) for a
  /// double q, and mix doubles into Dual expressions.
  template <class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
  constexpr Dual(T v) : val(static_cast<double>(v)) {}  // NOLINT(google-explicit-constructor): a scalar type
  constexpr Dual(double v, double d) : val(v), der(d) {}
  /// The value (explicit: dropping the derivative must be visible in the code).
  explicit constexpr operator double() const { return val; }

  constexpr Dual& operator+=(const Dual& o) {
    val += o.val;
    der += o.der;
    return *this;
  }
  constexpr Dual& operator-=(const Dual& o) {
    val -= o.val;
    der -= o.der;
    return *this;
  }
  constexpr Dual& operator*=(const Dual& o) {  // (uv)′ = u′v + uv′
    der = der * o.val + val * o.der;
    val *= o.val;
    return *this;
  }
  constexpr Dual& operator/=(const Dual& o) {  // (u/v)′ = (u′ − (u/v) v′)/v
    const double q = val / o.val;
    der = (der - q * o.der) / o.val;
    val = q;
    return *this;
  }

  friend constexpr Dual operator+(const Dual& a) { return a; }
  friend constexpr Dual operator-(const Dual& a) { return Dual(-a.val, -a.der); }
  friend constexpr Dual operator+(Dual a, const Dual& b) { return a += b; }
  friend constexpr Dual operator-(Dual a, const Dual& b) { return a -= b; }
  friend constexpr Dual operator*(Dual a, const Dual& b) { return a *= b; }
  friend constexpr Dual operator/(Dual a, const Dual& b) { return a /= b; }

  friend constexpr bool operator==(const Dual& a, const Dual& b) { return a.val == b.val; }
  friend constexpr bool operator!=(const Dual& a, const Dual& b) { return a.val != b.val; }
  friend constexpr bool operator<(const Dual& a, const Dual& b) { return a.val < b.val; }
  friend constexpr bool operator<=(const Dual& a, const Dual& b) { return a.val <= b.val; }
  friend constexpr bool operator>(const Dual& a, const Dual& b) { return a.val > b.val; }
  friend constexpr bool operator>=(const Dual& a, const Dual& b) { return a.val >= b.val; }

  friend std::ostream& operator<<(std::ostream& os, const Dual& a) {
    return os << a.val << (a.der < 0 ? " - " : " + ") << (a.der < 0 ? -a.der : a.der) << "ε";
  }
};

// ---- elementary functions (found by argument-dependent lookup after `using std::sin;` etc., as the library and
// Eigen call them). Each is f(x) + f′(x) x′ ε.

inline Dual sqrt(const Dual& x) {
  const double s = std::sqrt(x.val);
  return Dual(s, x.der / (2.0 * s));
}
inline Dual sin(const Dual& x) { return Dual(std::sin(x.val), std::cos(x.val) * x.der); }
inline Dual cos(const Dual& x) { return Dual(std::cos(x.val), -std::sin(x.val) * x.der); }
inline Dual tan(const Dual& x) {
  const double t = std::tan(x.val);
  return Dual(t, (1.0 + t * t) * x.der);
}
inline Dual asin(const Dual& x) { return Dual(std::asin(x.val), x.der / std::sqrt(1.0 - x.val * x.val)); }
inline Dual acos(const Dual& x) { return Dual(std::acos(x.val), -x.der / std::sqrt(1.0 - x.val * x.val)); }
inline Dual atan(const Dual& x) { return Dual(std::atan(x.val), x.der / (1.0 + x.val * x.val)); }
/// atan2(y, x) = the angle of (x, y): d = (x dy − y dx) / (x² + y²).
inline Dual atan2(const Dual& y, const Dual& x) {
  return Dual(std::atan2(y.val, x.val), (x.val * y.der - y.val * x.der) / (x.val * x.val + y.val * y.val));
}
inline Dual exp(const Dual& x) {
  const double e = std::exp(x.val);
  return Dual(e, e * x.der);
}
inline Dual log(const Dual& x) { return Dual(std::log(x.val), x.der / x.val); }
/// x^p for a constant exponent.
inline Dual pow(const Dual& x, double p) { return Dual(std::pow(x.val, p), p * std::pow(x.val, p - 1.0) * x.der); }
/// |x|: the derivative of the branch taken (+x at 0, as for a comparison x < 0).
inline Dual abs(const Dual& x) { return x.val < 0.0 ? -x : x; }
inline Dual fabs(const Dual& x) { return abs(x); }
/// Finite only when the value and the derivative are: a NaN derivative is as wrong as a NaN value.
inline bool isfinite(const Dual& x) { return std::isfinite(x.val) && std::isfinite(x.der); }
inline bool isnan(const Dual& x) { return std::isnan(x.val) || std::isnan(x.der); }
inline bool isinf(const Dual& x) { return std::isinf(x.val) || std::isinf(x.der); }

}  // namespace spatial::testing

// ---- the standard library's and Eigen's view of the type

namespace std {
template <>
struct numeric_limits<spatial::testing::Dual> {
 private:
  using D = std::numeric_limits<double>;
  using T = spatial::testing::Dual;

 public:
  static constexpr bool is_specialized = true;
  static constexpr bool is_signed = true;
  static constexpr bool is_integer = false;
  static constexpr bool is_exact = false;
  static constexpr bool has_infinity = D::has_infinity;
  static constexpr bool has_quiet_NaN = D::has_quiet_NaN;
  static constexpr int digits = D::digits;
  static constexpr int digits10 = D::digits10;
  static constexpr int max_digits10 = D::max_digits10;
  static constexpr int radix = D::radix;
  static constexpr T min() noexcept { return T(D::min()); }
  static constexpr T max() noexcept { return T(D::max()); }
  static constexpr T lowest() noexcept { return T(D::lowest()); }
  static constexpr T epsilon() noexcept { return T(D::epsilon()); }
  static constexpr T round_error() noexcept { return T(D::round_error()); }
  static constexpr T infinity() noexcept { return T(D::infinity()); }
  static constexpr T quiet_NaN() noexcept { return T(D::quiet_NaN()); }
  static constexpr T signaling_NaN() noexcept { return T(D::signaling_NaN()); }
  static constexpr T denorm_min() noexcept { return T(D::denorm_min()); }
};
}  // namespace std

namespace Eigen {
template <>
struct NumTraits<spatial::testing::Dual> : GenericNumTraits<spatial::testing::Dual> {
  using Real = spatial::testing::Dual;
  using NonInteger = spatial::testing::Dual;
  using Nested = spatial::testing::Dual;
  using Literal = double;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 0,  // trivially copyable: Eigen may leave dynamic storage unconstructed, as for double
    ReadCost = 2,
    AddCost = 2,
    MulCost = 3,
  };
  static inline Real epsilon() { return Real(NumTraits<double>::epsilon()); }
  static inline Real dummy_precision() { return Real(NumTraits<double>::dummy_precision()); }
  static inline Real highest() { return Real(NumTraits<double>::highest()); }
  static inline Real lowest() { return Real(NumTraits<double>::lowest()); }
  static inline int digits10() { return NumTraits<double>::digits10(); }
  static inline Real infinity() { return Real(NumTraits<double>::infinity()); }
  static inline Real quiet_NaN() { return Real(NumTraits<double>::quiet_NaN()); }
};
}  // namespace Eigen

namespace spatial::testing {

using VectorXdual = Eigen::Matrix<Dual, Eigen::Dynamic, 1>;

/// x as duals, with derivative 1 in entry k (k < 0: all derivatives 0).
template <class V>
VectorXdual seeded(const Eigen::MatrixBase<V>& x, int k = -1) {
  VectorXdual out(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) out[i] = Dual(static_cast<double>(x[i]), i == k ? 1.0 : 0.0);
  return out;
}
/// The values and the derivatives of a vector of duals.
template <class V>
Eigen::VectorXd values(const Eigen::MatrixBase<V>& x) {
  Eigen::VectorXd out(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) out[i] = x[i].val;
  return out;
}
template <class V>
Eigen::VectorXd derivatives(const Eigen::MatrixBase<V>& x) {
  Eigen::VectorXd out(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) out[i] = x[i].der;
  return out;
}

namespace detail_ad {
/// External forces as duals (constants); NoExternalForces stays as it is.
inline NoExternalForces dual_forces(NoExternalForces f) { return f; }
template <class Ext>
std::vector<Force<Dual>> dual_forces(const Ext& fext) {
  std::vector<Force<Dual>> out;
  for (const auto& f : fext) out.push_back(f.template cast<Dual>());
  return out;
}
/// The configuration integrate(q, ε e_k) of a floating model as duals (k < 0: q itself, constant).
inline VectorXdual moved(const FloatingModel<Dual>& model, const Eigen::VectorXd& q, int k) {
  VectorXdual out(model.nq());
  integrate(model, seeded(q), seeded(Eigen::VectorXd::Zero(model.nv()), k), Dual(1.0), out);
  return out;
}
}  // namespace detail_ad

struct AdRneaDerivatives {
  Eigen::MatrixXd dtau_dq, dtau_dv;
  Eigen::VectorXd tau;  ///< the values of τ (from the run with no derivative seeded)
};
struct AdAbaDerivatives {
  Eigen::MatrixXd dqdd_dq, dqdd_dv, dqdd_dtau;
  Eigen::VectorXd qdd;  ///< the values of q̈
};

/// The bound of analytical derivatives against this oracle. AD derivatives are exact up to rounding: the analytical
/// and AD matrices differ by the rounding of two different orders of operations, ~1e-15 relative; 1e-12 is issue
/// 13's bound, and three orders of magnitude below it a wrong term (≳ 1e-3 relative, typically O(1)) would still
/// stand out.
inline constexpr double kAdTolerance = 1e-12;

/// max |a − b| / max |b| (b: the AD matrix), the denominator at least 1: a matrix that vanishes identically (∂τ/∂v
/// of a single prismatic joint) is compared absolutely, where the analytical one may hold rounding of order 1e-17.
inline double ad_rel_err(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double scale = std::max(b.cwiseAbs().maxCoeff(), 1.0);
  return (a - b).cwiseAbs().maxCoeff() / scale;
}

/// ∂τ/∂q and ∂τ/∂v of RNEA on a fixed base by forward-mode AD (one pass per column).
template <class T, class Ext = NoExternalForces>
AdRneaDerivatives ad_rnea_derivatives(const Model<double, T>& model, const Eigen::VectorXd& q,
                                      const Eigen::VectorXd& v, const Eigen::VectorXd& a, const Ext& fext = Ext(),
                                      ForceFrame frame = ForceFrame::Body) {
  const Model<Dual> m = model.to_runtime().template cast<Dual>();
  Data<Dual> data(m);
  const auto f = detail_ad::dual_forces(fext);
  const int n = m.size();
  AdRneaDerivatives out{Eigen::MatrixXd(n, n), Eigen::MatrixXd(n, n), Eigen::VectorXd()};
  const VectorXdual q0 = seeded(q), v0 = seeded(v), a0 = seeded(a);
  out.tau = values(rnea(m, data, q0, v0, a0, f, frame));
  for (int k = 0; k < n; ++k) {
    out.dtau_dq.col(k) = derivatives(rnea(m, data, seeded(q, k), v0, a0, f, frame));
    out.dtau_dv.col(k) = derivatives(rnea(m, data, q0, seeded(v, k), a0, f, frame));
  }
  return out;
}

/// ∂q̈/∂q, ∂q̈/∂v and ∂q̈/∂τ of ABA on a fixed base by forward-mode AD.
template <class T, class Ext = NoExternalForces>
AdAbaDerivatives ad_aba_derivatives(const Model<double, T>& model, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& v, const Eigen::VectorXd& tau, const Ext& fext = Ext(),
                                    ForceFrame frame = ForceFrame::Body) {
  const Model<Dual> m = model.to_runtime().template cast<Dual>();
  Data<Dual> data(m);
  const auto f = detail_ad::dual_forces(fext);
  const int n = m.size();
  AdAbaDerivatives out{Eigen::MatrixXd(n, n), Eigen::MatrixXd(n, n), Eigen::MatrixXd(n, n), Eigen::VectorXd()};
  const VectorXdual q0 = seeded(q), v0 = seeded(v), t0 = seeded(tau);
  out.qdd = values(aba(m, data, q0, v0, t0, f, frame));
  for (int k = 0; k < n; ++k) {
    out.dqdd_dq.col(k) = derivatives(aba(m, data, seeded(q, k), v0, t0, f, frame));
    out.dqdd_dv.col(k) = derivatives(aba(m, data, q0, seeded(v, k), t0, f, frame));
    out.dqdd_dtau.col(k) = derivatives(aba(m, data, q0, v0, seeded(tau, k), f, frame));
  }
  return out;
}

/// ∂τ/∂q (tangent space: through integrate(q, ε e_k)) and ∂τ/∂v of RNEA on a floating base by forward-mode AD.
template <class T, class Ext = NoExternalForces>
AdRneaDerivatives ad_rnea_derivatives(const FloatingModel<double, T>& model, const Eigen::VectorXd& q,
                                      const Eigen::VectorXd& v, const Eigen::VectorXd& a, const Ext& fext = Ext(),
                                      ForceFrame frame = ForceFrame::Body) {
  const FloatingModel<Dual> m = model.to_runtime().template cast<Dual>();
  FloatingData<Dual> data(m);
  const auto f = detail_ad::dual_forces(fext);
  const int nv = m.nv();
  AdRneaDerivatives out{Eigen::MatrixXd(nv, nv), Eigen::MatrixXd(nv, nv), Eigen::VectorXd()};
  const VectorXdual q0 = seeded(q), v0 = seeded(v), a0 = seeded(a);
  out.tau = values(rnea(m, data, q0, v0, a0, f, frame));
  for (int k = 0; k < nv; ++k) {
    out.dtau_dq.col(k) = derivatives(rnea(m, data, detail_ad::moved(m, q, k), v0, a0, f, frame));
    out.dtau_dv.col(k) = derivatives(rnea(m, data, q0, seeded(v, k), a0, f, frame));
  }
  return out;
}

/// ∂q̈/∂q (tangent space), ∂q̈/∂v and ∂q̈/∂τ of ABA on a floating base by forward-mode AD.
template <class T, class Ext = NoExternalForces>
AdAbaDerivatives ad_aba_derivatives(const FloatingModel<double, T>& model, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& v, const Eigen::VectorXd& tau, const Ext& fext = Ext(),
                                    ForceFrame frame = ForceFrame::Body) {
  const FloatingModel<Dual> m = model.to_runtime().template cast<Dual>();
  FloatingData<Dual> data(m);
  const auto f = detail_ad::dual_forces(fext);
  const int nv = m.nv();
  AdAbaDerivatives out{Eigen::MatrixXd(nv, nv), Eigen::MatrixXd(nv, nv), Eigen::MatrixXd(nv, nv),
                       Eigen::VectorXd()};
  const VectorXdual q0 = seeded(q), v0 = seeded(v), t0 = seeded(tau);
  out.qdd = values(aba(m, data, q0, v0, t0, f, frame));
  for (int k = 0; k < nv; ++k) {
    out.dqdd_dq.col(k) = derivatives(aba(m, data, detail_ad::moved(m, q, k), v0, t0, f, frame));
    out.dqdd_dv.col(k) = derivatives(aba(m, data, q0, seeded(v, k), t0, f, frame));
    out.dqdd_dtau.col(k) = derivatives(aba(m, data, q0, v0, seeded(tau, k), f, frame));
  }
  return out;
}

}  // namespace spatial::testing

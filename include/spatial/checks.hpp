#pragma once
/// \file checks.hpp
/// Cheap validation of the algorithms' inputs, and checked entry points that refuse bad input instead of computing.
///
/// The algorithms themselves never check their inputs (a check per call would cost as much as a small tree's
/// arithmetic). What they do with bad numbers, by IEEE 754 propagation:
///  - a NaN or ±Inf in qᵢ makes ⁱX_λ(i) NaN, so every result that depends on body i or its subtree is NaN
///    (RNEA: τ of joint i, of its descendants and of its ancestors; CRBA: H(a, k) for every strict ancestor a of i
///    and every k related to i, since ⁱX_λ(i) carries the subtree's inertia up; forward dynamics: in general all);
///  - a NaN or ±Inf in q̇ᵢ, q̈ᵢ or τᵢ spreads the same way through the bodies it reaches; ±Inf usually turns into
///    NaN on the way (Inf − Inf, 0 · Inf);
///  - nothing crashes, throws or allocates, the model is never written (it is `const`), and `Data` is overwritten
///    on the next call: a call with good input after a bad one returns exactly what it returns on a fresh `Data`.
/// These functions tell, without allocating or throwing, which argument and which index is bad, and the name of
/// the joint there. Cost: one pass over the vectors (n comparisons each).

#include "spatial/algorithms.hpp"
#include "spatial/model.hpp"

#include <cmath>
#include <cstdint>
#include <ostream>
#include <sstream>
#include <string>

namespace spatial {

/// Result of an input check. `ok()` when every value is finite and every vector has the model's size; otherwise
/// `argument` names the first bad argument ("q", "qd", "qdd", "tau" or "result"), `index` is the first bad entry
/// (or the vector's actual size when the size is wrong), `joint` the name of that joint in the model (or nullptr),
/// and `reason` says what is wrong. Pointers refer to string literals or into the model: they stay valid as long as
/// the model does.
struct InputCheck {
  const char* argument = nullptr;
  int index = -1;
  const char* joint = nullptr;
  const char* reason = nullptr;
  double value = 0.0;  ///< the offending value (NaN, ±Inf, or the wrong size)
  int expected = -1;   ///< on a wrong size: the size the model expects (its number of joints), otherwise -1

  bool ok() const { return argument == nullptr; }
  explicit operator bool() const { return ok(); }
};

/// One line for people: "ok", "qd[3] (joint 'R_LFE_R_KN_joint'): NaN (value nan)", "result[20] (joint 'L_EB_L_WR_joint'):
/// articulated inertia pivot is zero, … (value 0)" or "q: wrong size: 20 entries, the model has 21 joints".
inline std::string to_string(const InputCheck& c) {
  if (c.ok()) return "ok";
  std::ostringstream os;
  os.precision(17);
  if (c.expected >= 0) {
    os << c.argument << ": wrong size: " << c.index << " entries, the model has " << c.expected << " joints";
    return os.str();
  }
  os << c.argument << "[" << c.index << "]";
  if (c.joint != nullptr) os << " (joint '" << c.joint << "')";
  os << ": " << (c.reason != nullptr ? c.reason : "bad") << " (value " << c.value << ")";
  return os.str();
}
inline std::ostream& operator<<(std::ostream& os, const InputCheck& c) { return os << to_string(c); }

namespace detail {
template <class S, class T, class V>
bool check_vector(const Model<S, T>& model, const Eigen::MatrixBase<V>& v, const char* name, InputCheck& out) {
  const int n = model.size();
  if (static_cast<int>(v.size()) != n) {
    out.argument = name;
    out.index = static_cast<int>(v.size());
    out.reason = "wrong size (index holds the size given; the model has size() entries)";
    out.value = static_cast<double>(v.size());
    out.expected = n;
    return false;
  }
  for (int i = 0; i < n; ++i) {
    using std::isfinite;
    using std::isnan;
    const auto x = v[i];
    if (!isfinite(x)) {
      out.argument = name;
      out.index = i;
      out.joint = model.joint_name(i).c_str();
      out.reason = isnan(x) ? "NaN" : (x > 0 ? "+Inf" : "-Inf");
      out.value = static_cast<double>(x);
      return false;
    }
  }
  return true;
}
}  // namespace detail

/// Checks that q has one finite entry per joint.
template <class S, class T, class Q>
InputCheck check_finite(const Model<S, T>& model, const Eigen::MatrixBase<Q>& q) {
  InputCheck r;
  detail::check_vector(model, q, "q", r);
  return r;
}

/// Checks q and q̇.
template <class S, class T, class Q, class QD>
InputCheck check_finite(const Model<S, T>& model, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd) {
  InputCheck r;
  if (detail::check_vector(model, q, "q", r)) detail::check_vector(model, qd, "qd", r);
  return r;
}

/// Checks q, q̇ and a third vector, named `third` in the result: "qdd" for inverse dynamics (the default), "tau"
/// for forward dynamics.
template <class S, class T, class Q, class QD, class X>
InputCheck check_finite(const Model<S, T>& model, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                        const Eigen::MatrixBase<X>& x, const char* third = "qdd") {
  InputCheck r;
  if (detail::check_vector(model, q, "q", r) && detail::check_vector(model, qd, "qd", r))
    detail::check_vector(model, x, third, r);
  return r;
}

/// `rnea` when q, q̇ and q̈ are good; otherwise nothing is computed (`data` is not touched) and the check says why.
template <class S, class T, class Q, class QD, class QDD>
InputCheck rnea_checked(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                        const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd) {
  const InputCheck r = check_finite(model, q, qd, qdd, "qdd");
  if (r.ok()) rnea(model, data, q, qd, qdd);
  return r;
}

/// `aba` when q, q̇ and τ are good; the result is in `data.qdd`. Besides the inputs it checks the articulated
/// inertias' pivots Dᵢ = Sᵢᵀ Iᴬᵢ Sᵢ: a joint whose subtree moves no inertia gives Dᵢ = 0, and then `argument` is
/// "result", `index` the first such joint (searched from the leaves) and `data.qdd` is not finite.
template <class S, class T, class Q, class QD, class Tau>
InputCheck aba_checked(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                       const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau) {
  InputCheck r = check_finite(model, q, qd, tau, "tau");
  if (!r.ok()) return r;
  aba(model, data, q, qd, tau);
  for (int i = model.size() - 1; i >= 0; --i) {
    using std::isfinite;
    const S dinv = data.Dinv[static_cast<std::size_t>(i)];
    if (!(isfinite(dinv) && dinv > S(0))) {
      r.argument = "result";
      r.index = i;
      r.joint = model.joint_name(i).c_str();
      r.reason = "articulated inertia pivot is zero, negative or not finite (the joint moves no inertia)";
      r.value = static_cast<double>(dinv);
      return r;
    }
  }
  return r;
}

/// `forward_dynamics_crba` when q, q̇ and τ are good; the result is in `data.qdd`. Also checks the pivots of the
/// LTDL factorisation (the diagonal D of H = Lᵀ D L): a pivot that is not positive and finite means H is singular
/// (or not positive definite) and is reported as argument "result" at that joint.
template <class S, class T, class Q, class QD, class Tau>
InputCheck forward_dynamics_crba_checked(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                         const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau) {
  InputCheck r = check_finite(model, q, qd, tau, "tau");
  if (!r.ok()) return r;
  forward_dynamics_crba(model, data, q, qd, tau);
  for (int i = model.size() - 1; i >= 0; --i) {
    using std::isfinite;
    const S d = data.L(i, i);
    if (!(isfinite(d) && d > S(0))) {
      r.argument = "result";
      r.index = i;
      r.joint = model.joint_name(i).c_str();
      r.reason = "pivot of H = L^T D L is zero, negative or not finite (H is singular)";
      r.value = static_cast<double>(d);
      return r;
    }
  }
  return r;
}

}  // namespace spatial

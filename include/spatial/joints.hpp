#pragma once
/// \file joints.hpp
/// One-degree-of-freedom joints (RBDA §4.4, Table 4.1). Each joint model gives
///  - `transform(q)`: the joint transform X_J(q) from the joint's predecessor frame to the successor (body) frame;
///  - `compose(q, cos q, sin q, X_T)`: X_J(q) X_T, specialised per joint (the sines and cosines of all joints are
///    computed together beforehand, see sincos.hpp);
///  - `motion(qd)`: S q̇, the joint velocity in body coordinates (S is constant in body coordinates, so Ṡ = v × S);
///  - `project(f)`: Sᵀ f, the component of a body-coordinate force along the joint's motion subspace;
///  - `apply_inertia(I)`: I S for a rigid-body or articulated inertia I (a column of I for axis-aligned joints);
///  - `subspace_inverse(X)`: X⁻¹ S, the motion subspace in the coordinates of the frame X maps from (CRBA uses it
///    with X = ⁱX_0 to express every joint axis in base coordinates);
///  - `rotate(c, s, v)` and `shift_moment(q, h, m)`: with X_J = (E_J, r_J), E_J v (v a 3-vector or a 3×3 matrix)
///    and h + m E_J r_J (gravity torques compose only the rotation E_J E_T of X_J X_T and move first moments with
///    these; see `gravity_impl`).
/// The axis-aligned joints are separate types so that each costs only what its axis needs: a revolute joint
/// about z is one sine, one cosine and a few multiplies, and its S q̇ has one non-zero entry.

#include "spatial/algebra.hpp"

#include <cstdint>
#include <string_view>
#include <type_traits>
#include <utility>

namespace spatial {

enum class JointType : std::uint8_t {
  RevoluteX,
  RevoluteY,
  RevoluteZ,
  RevoluteAxis,
  PrismaticX,
  PrismaticY,
  PrismaticZ,
  PrismaticAxis,
};

constexpr std::string_view joint_type_name(JointType t) {
  switch (t) {
    case JointType::RevoluteX: return "RevoluteX";
    case JointType::RevoluteY: return "RevoluteY";
    case JointType::RevoluteZ: return "RevoluteZ";
    case JointType::RevoluteAxis: return "RevoluteAxis";
    case JointType::PrismaticX: return "PrismaticX";
    case JointType::PrismaticY: return "PrismaticY";
    case JointType::PrismaticZ: return "PrismaticZ";
    case JointType::PrismaticAxis: return "PrismaticAxis";
  }
  return "?";
}
constexpr bool is_revolute(JointType t) {
  return t == JointType::RevoluteX || t == JointType::RevoluteY || t == JointType::RevoluteZ ||
         t == JointType::RevoluteAxis;
}
constexpr bool has_axis(JointType t) { return t == JointType::RevoluteAxis || t == JointType::PrismaticAxis; }

/// Joint model for a compile-time joint type. `axis` is used only by the *Axis types (a unit vector in the joint
/// frame, which for these joints is also the body frame's direction of the axis).
template <class S, JointType T>
struct Joint;

namespace detail {
// Revolute about coordinate axis K (0 = x, 1 = y, 2 = z).
template <class S, int K>
struct RevoluteAxisAligned {
  /// ABA: the articulated inertia passed to the parent, Iᴬ − U Uᵀ / D, maps S = e_K (angular) to zero.
  static constexpr int null_angular = K;
  static SPATIAL_INLINE Transform<S> transform(S q) {
    if constexpr (K == 0) return rotx(q);
    else if constexpr (K == 1) return roty(q);
    else return rotz(q);
  }
  static SPATIAL_INLINE Motion<S> motion(S qd) {
    Motion<S> m = Motion<S>::Zero();
    m.w[K] = qd;
    return m;
  }
  static SPATIAL_INLINE S project(const Force<S>& f) { return f.n[K]; }
  /// Add S q̈ to a.
  static SPATIAL_INLINE void add_motion(Motion<S>& a, S qdd) { a.w[K] += qdd; }
  /// v × (S q̇) for this joint.
  /// v × (S q̇) = [ω × e_K; v_O × e_K] q̇.
  static SPATIAL_INLINE Motion<S> cross_motion(const Motion<S>& v, S qd) {
    return Motion<S>(cross_axis(v.w, qd), cross_axis(v.v, qd));
  }
  /// X_J(q) X_T from c = cos q, s = sin q: rotating the tree transform's rows K+1, K+2 (mod 3) by the joint
  /// angle; r is unchanged.
  static SPATIAL_INLINE Transform<S> compose(S /*q*/, S c, S s, const Transform<S>& XT) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Transform<S> X = XT;
    SPATIAL_UNROLL for (int col = 0; col < 3; ++col) {
      X.E(i, col) = c * XT.E(i, col) + s * XT.E(j, col);
      X.E(j, col) = c * XT.E(j, col) - s * XT.E(i, col);
    }
    return X;
  }
  /// I S = [Ī e_K; e_K × h]: column K of the rigid-body inertia.
  static SPATIAL_INLINE Force<S> apply_inertia(const Inertia<S>& I) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Vector3<S> f;
    f[K] = S(0);
    f[i] = -I.h[j];
    f[j] = I.h[i];
    return Force<S>(I.I.col(K), f);
  }
  /// Iᴬ S = [A e_K; Bᵀ e_K].
  static SPATIAL_INLINE Force<S> apply_inertia(const ArticulatedInertia<S>& I) {
    return Force<S>(I.A.col(K), I.B.row(K).transpose());
  }
  /// X⁻¹ S for a transform X = ᴮX_A into this body's frame B: the joint's motion subspace in A coordinates,
  /// [Eᵀ e_K; r × Eᵀ e_K] (Eᵀ e_K is row K of E).
  static SPATIAL_INLINE Motion<S> subspace_inverse(const Transform<S>& X) {
    const Vector3<S> w(X.E(K, 0), X.E(K, 1), X.E(K, 2));
    return Motion<S>(w, detail::cross3(X.r, w));
  }
  /// E_J v: rows K+1, K+2 (mod 3) of v rotated by the joint angle (as in `compose`).
  static SPATIAL_INLINE Vector3<S> rotate(S c, S s, const Vector3<S>& v) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Vector3<S> out;
    out[K] = v[K];
    out[i] = c * v[i] + s * v[j];
    out[j] = c * v[j] - s * v[i];
    return out;
  }
  /// E_J M, column by column.
  static SPATIAL_INLINE Matrix3<S> rotate(S c, S s, const Matrix3<S>& M) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Matrix3<S> out;
    SPATIAL_UNROLL for (int col = 0; col < 3; ++col) {
      out(K, col) = M(K, col);
      out(i, col) = c * M(i, col) + s * M(j, col);
      out(j, col) = c * M(j, col) - s * M(i, col);
    }
    return out;
  }
  /// h + m E_J r_J = h (r_J = 0).
  static SPATIAL_INLINE Vector3<S> shift_moment(S /*q*/, const Vector3<S>& h, S /*m*/) { return h; }
  /// a × e_K s
  static SPATIAL_INLINE Vector3<S> cross_axis(const Vector3<S>& a, S s) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Vector3<S> out;
    out[K] = S(0);
    out[i] = a[j] * s;
    out[j] = -a[i] * s;
    return out;
  }
};
template <class S, int K>
struct PrismaticAxisAligned {
  static SPATIAL_INLINE Transform<S> transform(S q) {
    Vector3<S> r = Vector3<S>::Zero();
    r[K] = q;
    return xlt(r);
  }
  static SPATIAL_INLINE Motion<S> motion(S qd) {
    Motion<S> m = Motion<S>::Zero();
    m.v[K] = qd;
    return m;
  }
  static SPATIAL_INLINE S project(const Force<S>& f) { return f.f[K]; }
  static SPATIAL_INLINE void add_motion(Motion<S>& a, S qdd) { a.v[K] += qdd; }
  /// v × (S q̇) = [0; ω × e_K] q̇.
  static SPATIAL_INLINE Motion<S> cross_motion(const Motion<S>& v, S qd) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Vector3<S> lin;
    lin[K] = S(0);
    lin[i] = v.w[j] * qd;
    lin[j] = -v.w[i] * qd;
    return Motion<S>(Vector3<S>::Zero(), lin);
  }
  /// I S = [h × e_K; m e_K].
  static SPATIAL_INLINE Force<S> apply_inertia(const Inertia<S>& I) {
    constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
    Vector3<S> n, f = Vector3<S>::Zero();
    n[K] = S(0);
    n[i] = I.h[j];
    n[j] = -I.h[i];
    f[K] = I.m;
    return Force<S>(n, f);
  }
  /// Iᴬ S = [B e_K; C e_K].
  static SPATIAL_INLINE Force<S> apply_inertia(const ArticulatedInertia<S>& I) {
    return Force<S>(I.B.col(K), I.C.col(K));
  }
  /// X⁻¹ S = [0; Eᵀ e_K] (row K of E).
  static SPATIAL_INLINE Motion<S> subspace_inverse(const Transform<S>& X) {
    return Motion<S>(Vector3<S>::Zero(), Vector3<S>(X.E(K, 0), X.E(K, 1), X.E(K, 2)));
  }
  /// E_J v = v, E_J M = M (no rotation).
  static SPATIAL_INLINE Vector3<S> rotate(S /*c*/, S /*s*/, const Vector3<S>& v) { return v; }
  static SPATIAL_INLINE Matrix3<S> rotate(S /*c*/, S /*s*/, const Matrix3<S>& M) { return M; }
  /// h + m E_J r_J = h + m q e_K.
  static SPATIAL_INLINE Vector3<S> shift_moment(S q, const Vector3<S>& h, S m) {
    Vector3<S> out = h;
    out[K] += m * q;
    return out;
  }
  /// X_J(q) X_T = xlt(q e_K) X_T: r = r_T + q E_Tᵀ e_K (row K of E_T); E unchanged.
  static SPATIAL_INLINE Transform<S> compose(S q, S /*c*/, S /*s*/, const Transform<S>& XT) {
    Transform<S> X = XT;
    SPATIAL_UNROLL for (int col = 0; col < 3; ++col) X.r[col] += q * XT.E(K, col);
    return X;
  }
};
/// K when a joint's articulated-inertia update leaves angular coordinate K null (see
/// ArticulatedInertia::subtract_outer), −1 for joints without that structure (and run-time joints).
template <class J, class = void>
struct NullAngular : std::integral_constant<int, -1> {};
template <class J>
struct NullAngular<J, std::void_t<decltype(J::null_angular)>> : std::integral_constant<int, J::null_angular> {};
}  // namespace detail

#define SPATIAL_AXIS_ALIGNED_JOINT(TYPE, BASE, K)                             \
  template <class S>                                                          \
  struct Joint<S, JointType::TYPE> : detail::BASE<S, K> {                     \
    static constexpr JointType type = JointType::TYPE;                        \
    Joint() = default;                                                        \
    explicit Joint(const Vector3<S>& /*axis*/) {}                             \
  };
SPATIAL_AXIS_ALIGNED_JOINT(RevoluteX, RevoluteAxisAligned, 0)
SPATIAL_AXIS_ALIGNED_JOINT(RevoluteY, RevoluteAxisAligned, 1)
SPATIAL_AXIS_ALIGNED_JOINT(RevoluteZ, RevoluteAxisAligned, 2)
SPATIAL_AXIS_ALIGNED_JOINT(PrismaticX, PrismaticAxisAligned, 0)
SPATIAL_AXIS_ALIGNED_JOINT(PrismaticY, PrismaticAxisAligned, 1)
SPATIAL_AXIS_ALIGNED_JOINT(PrismaticZ, PrismaticAxisAligned, 2)
#undef SPATIAL_AXIS_ALIGNED_JOINT

/// Revolute joint about an arbitrary unit axis a: X_J = rot(E(a, q)), S = [a; 0].
template <class S>
struct Joint<S, JointType::RevoluteAxis> {
  static constexpr JointType type = JointType::RevoluteAxis;
  Vector3<S> axis;
  Joint() = default;
  explicit Joint(const Vector3<S>& a) : axis(a) {}
  SPATIAL_INLINE Transform<S> transform(S q) const { return Transform<S>(rot_axis_matrix(axis, q), Vector3<S>::Zero()); }
  SPATIAL_INLINE Motion<S> motion(S qd) const { return Motion<S>(axis * qd, Vector3<S>::Zero()); }
  SPATIAL_INLINE S project(const Force<S>& f) const { return axis.dot(f.n); }
  template <class In>
  SPATIAL_INLINE Force<S> apply_inertia(const In& I) const { return I * motion(S(1)); }
  SPATIAL_INLINE Transform<S> compose(S /*q*/, S c, S s, const Transform<S>& XT) const {
    return Transform<S>(rot_axis_matrix_cs(axis, c, s), Vector3<S>::Zero()) * XT;
  }
  SPATIAL_INLINE Motion<S> subspace_inverse(const Transform<S>& X) const { return X.apply_inverse(motion(S(1))); }
  SPATIAL_INLINE Vector3<S> rotate(S c, S s, const Vector3<S>& v) const {
    return detail::mul(rot_axis_matrix_cs(axis, c, s), v);
  }
  SPATIAL_INLINE Matrix3<S> rotate(S c, S s, const Matrix3<S>& M) const {
    return detail::mul(rot_axis_matrix_cs(axis, c, s), M);
  }
  SPATIAL_INLINE Vector3<S> shift_moment(S /*q*/, const Vector3<S>& h, S /*m*/) const { return h; }
  SPATIAL_INLINE void add_motion(Motion<S>& a, S qdd) const { a.w += axis * qdd; }
  SPATIAL_INLINE Motion<S> cross_motion(const Motion<S>& v, S qd) const {
    const Vector3<S> e = axis * qd;
    return Motion<S>(v.w.cross(e), v.v.cross(e));
  }
};

/// Prismatic joint along an arbitrary unit axis a: X_J = xlt(a q), S = [0; a].
template <class S>
struct Joint<S, JointType::PrismaticAxis> {
  static constexpr JointType type = JointType::PrismaticAxis;
  Vector3<S> axis;
  Joint() = default;
  explicit Joint(const Vector3<S>& a) : axis(a) {}
  SPATIAL_INLINE Transform<S> transform(S q) const { return xlt<S>(axis * q); }
  SPATIAL_INLINE Motion<S> motion(S qd) const { return Motion<S>(Vector3<S>::Zero(), axis * qd); }
  SPATIAL_INLINE S project(const Force<S>& f) const { return axis.dot(f.f); }
  template <class In>
  SPATIAL_INLINE Force<S> apply_inertia(const In& I) const { return I * motion(S(1)); }
  SPATIAL_INLINE Transform<S> compose(S q, S /*c*/, S /*s*/, const Transform<S>& XT) const {
    return xlt<S>(axis * q) * XT;
  }
  SPATIAL_INLINE Motion<S> subspace_inverse(const Transform<S>& X) const { return X.apply_inverse(motion(S(1))); }
  SPATIAL_INLINE Vector3<S> rotate(S /*c*/, S /*s*/, const Vector3<S>& v) const { return v; }
  SPATIAL_INLINE Matrix3<S> rotate(S /*c*/, S /*s*/, const Matrix3<S>& M) const { return M; }
  SPATIAL_INLINE Vector3<S> shift_moment(S q, const Vector3<S>& h, S m) const {
    return detail::add3(h, detail::scale3(m * q, axis));
  }
  SPATIAL_INLINE void add_motion(Motion<S>& a, S qdd) const { a.v += axis * qdd; }
  SPATIAL_INLINE Motion<S> cross_motion(const Motion<S>& v, S qd) const {
    return Motion<S>(Vector3<S>::Zero(), v.w.cross(axis * qd));
  }
};

/// A joint whose type is known only at run time (models loaded from files). Same interface; each call switches
/// once on the type and then runs exactly the code of the compile-time joint, so both give the same numbers.
template <class S>
struct RuntimeJoint {
  JointType type;
  Vector3<S> axis;

  template <class F>
  decltype(auto) visit(F&& f) const {
    switch (type) {
      case JointType::RevoluteX: return f(Joint<S, JointType::RevoluteX>());
      case JointType::RevoluteY: return f(Joint<S, JointType::RevoluteY>());
      case JointType::RevoluteZ: return f(Joint<S, JointType::RevoluteZ>());
      case JointType::RevoluteAxis: return f(Joint<S, JointType::RevoluteAxis>(axis));
      case JointType::PrismaticX: return f(Joint<S, JointType::PrismaticX>());
      case JointType::PrismaticY: return f(Joint<S, JointType::PrismaticY>());
      case JointType::PrismaticZ: return f(Joint<S, JointType::PrismaticZ>());
      case JointType::PrismaticAxis: break;
    }
    return f(Joint<S, JointType::PrismaticAxis>(axis));
  }
  SPATIAL_INLINE Transform<S> transform(S q) const { return visit([&](const auto& j) { return j.transform(q); }); }
  SPATIAL_INLINE Transform<S> compose(S q, S c, S s, const Transform<S>& XT) const {
    return visit([&](const auto& j) { return j.compose(q, c, s, XT); });
  }
  SPATIAL_INLINE Motion<S> motion(S qd) const { return visit([&](const auto& j) { return j.motion(qd); }); }
  SPATIAL_INLINE Motion<S> subspace_inverse(const Transform<S>& X) const {
    return visit([&](const auto& j) { return j.subspace_inverse(X); });
  }
  SPATIAL_INLINE S project(const Force<S>& f) const { return visit([&](const auto& j) { return j.project(f); }); }
  SPATIAL_INLINE Vector3<S> rotate(S c, S s, const Vector3<S>& v) const {
    return visit([&](const auto& j) { return j.rotate(c, s, v); });
  }
  SPATIAL_INLINE Matrix3<S> rotate(S c, S s, const Matrix3<S>& M) const {
    return visit([&](const auto& j) { return j.rotate(c, s, M); });
  }
  SPATIAL_INLINE Vector3<S> shift_moment(S q, const Vector3<S>& h, S m) const {
    return visit([&](const auto& j) { return j.shift_moment(q, h, m); });
  }
  template <class In>
  SPATIAL_INLINE Force<S> apply_inertia(const In& I) const {
    return visit([&](const auto& j) { return j.apply_inertia(I); });
  }
  SPATIAL_INLINE void add_motion(Motion<S>& a, S qdd) const { visit([&](const auto& j) { j.add_motion(a, qdd); }); }
  SPATIAL_INLINE Motion<S> cross_motion(const Motion<S>& v, S qd) const {
    return visit([&](const auto& j) { return j.cross_motion(v, qd); });
  }
};

namespace detail {
/// f(joint) with the joint's compile-time type: a `RuntimeJoint` switches once on its type (`visit`), so that
/// several joint operations in f cost one switch instead of one each; a compile-time joint is passed as it is.
template <class S, class F>
SPATIAL_INLINE decltype(auto) visit_joint(const RuntimeJoint<S>& j, F&& f) {
  return j.visit(std::forward<F>(f));
}
template <class S, JointType T, class F>
SPATIAL_INLINE decltype(auto) visit_joint(const Joint<S, T>& j, F&& f) {
  return f(j);
}
}  // namespace detail

}  // namespace spatial

#pragma once
/// \file algebra.hpp
/// Spatial vector algebra (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 2) on fixed-size Eigen types.
///
/// Conventions, fixed once for the whole library:
///  - Plücker coordinates, **angular first**: a motion vector is [ω; v_O], a force vector is [n_O; f], both measured
///    at the origin O of the frame they are expressed in.
///  - Motion and force are different types; the only scalar product is `dot(Motion, Force)`.
///  - Transforms are **passive**: `Transform X` standing for ᴮX_A maps motion coordinates from frame A to frame B.
///    It is stored as the rotation E = ᴮE_A (3D coordinates from A to B) and the translation r = position of B's
///    origin relative to A's origin, expressed in A: X = rot(E) · xlt(r)  (RBDA eq. 2.24 and Table 2.5).
///  - Forces transform with X* = X⁻ᵀ.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <type_traits>

namespace spatial {

template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;
template <class S>
using Vector6 = Eigen::Matrix<S, 6, 1>;
template <class S>
using Matrix6 = Eigen::Matrix<S, 6, 6>;

/// The 3×3 matrix r̃ with r̃ p = r × p (RBDA eq. 2.9).
template <class S>
Matrix3<S> skew(const Vector3<S>& r) {
  Matrix3<S> m;
  m << S(0), -r.z(), r.y(),  //
      r.z(), S(0), -r.x(),   //
      -r.y(), r.x(), S(0);
  return m;
}

/// A spatial motion vector (velocity, acceleration, motion subspace column): [ω; v_O], angular first.
template <class S>
struct Motion {
  using Scalar = S;
  Vector3<S> w;  ///< angular part ω
  Vector3<S> v;  ///< linear part v_O: velocity of the body-fixed point at the frame origin O

  Motion() = default;
  Motion(const Vector3<S>& angular, const Vector3<S>& linear) : w(angular), v(linear) {}
  /// From the six Plücker coordinates [ω; v].
  explicit Motion(const Vector6<S>& m) : w(m.template head<3>()), v(m.template tail<3>()) {}
  static Motion Zero() { return Motion(Vector3<S>::Zero(), Vector3<S>::Zero()); }

  const Vector3<S>& angular() const { return w; }
  const Vector3<S>& linear() const { return v; }
  Vector6<S> vector() const {
    Vector6<S> out;
    out << w, v;
    return out;
  }
  template <class T>
  Motion<T> cast() const {
    return Motion<T>(w.template cast<T>(), v.template cast<T>());
  }
  Motion& operator+=(const Motion& o) { w += o.w; v += o.v; return *this; }
  Motion& operator-=(const Motion& o) { w -= o.w; v -= o.v; return *this; }
  friend Motion operator+(const Motion& a, const Motion& b) { return Motion(a.w + b.w, a.v + b.v); }
  friend Motion operator-(const Motion& a, const Motion& b) { return Motion(a.w - b.w, a.v - b.v); }
  friend Motion operator-(const Motion& a) { return Motion(-a.w, -a.v); }
  friend Motion operator*(S s, const Motion& a) { return Motion(s * a.w, s * a.v); }
  friend Motion operator*(const Motion& a, S s) { return Motion(s * a.w, s * a.v); }
};

/// A spatial force vector (force, momentum, impulse): [n_O; f], moment about the frame origin O first.
template <class S>
struct Force {
  using Scalar = S;
  Vector3<S> n;  ///< moment about the frame origin O
  Vector3<S> f;  ///< linear force

  Force() = default;
  Force(const Vector3<S>& moment, const Vector3<S>& linear) : n(moment), f(linear) {}
  /// From the six Plücker coordinates [n; f].
  explicit Force(const Vector6<S>& x) : n(x.template head<3>()), f(x.template tail<3>()) {}
  static Force Zero() { return Force(Vector3<S>::Zero(), Vector3<S>::Zero()); }

  const Vector3<S>& angular() const { return n; }
  const Vector3<S>& linear() const { return f; }
  Vector6<S> vector() const {
    Vector6<S> out;
    out << n, f;
    return out;
  }
  template <class T>
  Force<T> cast() const {
    return Force<T>(n.template cast<T>(), f.template cast<T>());
  }
  Force& operator+=(const Force& o) { n += o.n; f += o.f; return *this; }
  Force& operator-=(const Force& o) { n -= o.n; f -= o.f; return *this; }
  friend Force operator+(const Force& a, const Force& b) { return Force(a.n + b.n, a.f + b.f); }
  friend Force operator-(const Force& a, const Force& b) { return Force(a.n - b.n, a.f - b.f); }
  friend Force operator-(const Force& a) { return Force(-a.n, -a.f); }
  friend Force operator*(S s, const Force& a) { return Force(s * a.n, s * a.f); }
  friend Force operator*(const Force& a, S s) { return Force(s * a.n, s * a.f); }
};

/// The scalar product m · f (power, work): the only product between the two spaces (RBDA §2.6).
template <class S>
S dot(const Motion<S>& m, const Force<S>& f) {
  return m.w.dot(f.n) + m.v.dot(f.f);
}
template <class S>
S dot(const Force<S>& f, const Motion<S>& m) {
  return dot(m, f);
}

/// Motion cross product a × b = [ω̃ 0; ṽ ω̃] b (RBDA eq. 2.31): the rate of change of the motion vector b
/// moving with velocity a.
template <class S>
Motion<S> cross(const Motion<S>& a, const Motion<S>& b) {
  return Motion<S>(a.w.cross(b.w), a.w.cross(b.v) + a.v.cross(b.w));
}

/// Force cross product a ×* f = [ω̃ ṽ; 0 ω̃] f = −(a×)ᵀ f (RBDA eq. 2.32).
template <class S>
Force<S> cross(const Motion<S>& a, const Force<S>& f) {
  return Force<S>(a.w.cross(f.n) + a.v.cross(f.f), a.w.cross(f.f));
}

/// 6×6 matrix of `a ×` (tests and diagnostics only).
template <class S>
Matrix6<S> cross_matrix(const Motion<S>& a) {
  Matrix6<S> m = Matrix6<S>::Zero();
  m.template topLeftCorner<3, 3>() = skew(a.w);
  m.template bottomLeftCorner<3, 3>() = skew(a.v);
  m.template bottomRightCorner<3, 3>() = skew(a.w);
  return m;
}

/// 6×6 matrix of `a ×*` = −(a×)ᵀ (tests and diagnostics only).
template <class S>
Matrix6<S> cross_force_matrix(const Motion<S>& a) {
  return -cross_matrix(a).transpose();
}

/// Plücker transform ᴮX_A = rot(E) xlt(r), passive (RBDA §2.8, Table 2.5).
///  - E: rotation taking 3D coordinates from A to B (ᴮE_A).
///  - r: position of B's origin relative to A's origin, in A coordinates.
template <class S>
struct Transform {
  using Scalar = S;
  Matrix3<S> E;
  Vector3<S> r;

  Transform() = default;
  Transform(const Matrix3<S>& rotation, const Vector3<S>& translation) : E(rotation), r(translation) {}
  static Transform Identity() { return Transform(Matrix3<S>::Identity(), Vector3<S>::Zero()); }

  /// ᴮm = X ᴬm: [E ω; E (v − r × ω)].
  Motion<S> apply(const Motion<S>& m) const { return Motion<S>(E * m.w, E * (m.v - r.cross(m.w))); }
  /// ᴬm = X⁻¹ ᴮm: [Eᵀ ω; Eᵀ v + r × Eᵀ ω].
  Motion<S> apply_inverse(const Motion<S>& m) const {
    Vector3<S> w = E.transpose() * m.w;
    return Motion<S>(w, E.transpose() * m.v + r.cross(w));
  }
  /// ᴮf = X* ᴬf: [E (n − r × f); E f].
  Force<S> apply_force(const Force<S>& f) const { return Force<S>(E * (f.n - r.cross(f.f)), E * f.f); }
  /// ᴬf = Xᵀ ᴮf (the inverse of X*): [Eᵀ n + r × Eᵀ f; Eᵀ f].
  Force<S> apply_force_inverse(const Force<S>& f) const {
    Vector3<S> lin = E.transpose() * f.f;
    return Force<S>(E.transpose() * f.n + r.cross(lin), lin);
  }

  /// ᴬX_B.
  Transform inverse() const { return Transform(E.transpose(), -(E * r)); }

  /// Composition: (ᶜX_B)(ᴮX_A) = ᶜX_A.  With X1 = (E1, r1), X2 = (E2, r2): E = E1 E2, r = r2 + E2ᵀ r1.
  Transform operator*(const Transform& x2) const { return Transform(E * x2.E, x2.r + x2.E.transpose() * r); }
  Motion<S> operator*(const Motion<S>& m) const { return apply(m); }
  Force<S> operator*(const Force<S>& f) const { return apply_force(f); }

  /// 6×6 motion transform [E 0; −E r̃ E] (tests and diagnostics only).
  Matrix6<S> matrix() const {
    Matrix6<S> x;
    x.template topLeftCorner<3, 3>() = E;
    x.template topRightCorner<3, 3>().setZero();
    x.template bottomLeftCorner<3, 3>() = -E * skew(r);
    x.template bottomRightCorner<3, 3>() = E;
    return x;
  }
  /// 6×6 force transform X* = X⁻ᵀ = [E −E r̃; 0 E] (tests and diagnostics only).
  Matrix6<S> force_matrix() const {
    Matrix6<S> x;
    x.template topLeftCorner<3, 3>() = E;
    x.template topRightCorner<3, 3>() = -E * skew(r);
    x.template bottomLeftCorner<3, 3>().setZero();
    x.template bottomRightCorner<3, 3>() = E;
    return x;
  }
  template <class T>
  Transform<T> cast() const {
    return Transform<T>(E.template cast<T>(), r.template cast<T>());
  }
};

/// Passive rotation matrices: coordinates of a vector in a frame rotated by θ about x, y, z (RBDA eq. 2.20).
template <class S>
Matrix3<S> rotx_matrix(S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  Matrix3<S> e;
  e << S(1), S(0), S(0), S(0), c, s, S(0), -s, c;
  return e;
}
template <class S>
Matrix3<S> roty_matrix(S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  Matrix3<S> e;
  e << c, S(0), -s, S(0), S(1), S(0), s, S(0), c;
  return e;
}
template <class S>
Matrix3<S> rotz_matrix(S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  Matrix3<S> e;
  e << c, s, S(0), -s, c, S(0), S(0), S(0), S(1);
  return e;
}
/// Passive rotation by θ about the unit axis a: E = cosθ·1 + (1 − cosθ) a aᵀ − sinθ ã  (transpose of Rodrigues).
template <class S>
Matrix3<S> rot_axis_matrix(const Vector3<S>& a, S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  return c * Matrix3<S>::Identity() + (S(1) - c) * a * a.transpose() - s * skew(a);
}

/// The frame rotated by θ about x (RBDA eq. 2.20, `rotx` in spatial_v2).
template <class S>
Transform<S> rotx(S theta) { return Transform<S>(rotx_matrix(theta), Vector3<S>::Zero()); }
template <class S>
Transform<S> roty(S theta) { return Transform<S>(roty_matrix(theta), Vector3<S>::Zero()); }
template <class S>
Transform<S> rotz(S theta) { return Transform<S>(rotz_matrix(theta), Vector3<S>::Zero()); }
/// The frame translated by r (coordinates of the new origin in the old frame) (RBDA eq. 2.21, `xlt`).
template <class S>
Transform<S> xlt(const Vector3<S>& r) { return Transform<S>(Matrix3<S>::Identity(), r); }

/// Spatial rigid-body inertia, stored compactly (RBDA §2.13, eq. 2.63): mass m, first moment h = m c and the
/// rotational inertia Ī about the frame origin. As a 6×6 it is [Ī h̃; h̃ᵀ m1].
template <class S>
struct Inertia {
  using Scalar = S;
  S m;
  Vector3<S> h;
  Matrix3<S> I;  ///< rotational inertia about the frame origin (symmetric)

  Inertia() = default;
  Inertia(S mass, const Vector3<S>& first_moment, const Matrix3<S>& rot_inertia_origin)
      : m(mass), h(first_moment), I(rot_inertia_origin) {}
  static Inertia Zero() { return Inertia(S(0), Vector3<S>::Zero(), Matrix3<S>::Zero()); }

  /// From mass, centre of mass c and rotational inertia I_c about the centre of mass, all in this frame:
  /// Ī = I_c + m c̃ c̃ᵀ (parallel-axis theorem, RBDA eq. 2.63).
  static Inertia from_com(S mass, const Vector3<S>& com, const Matrix3<S>& inertia_com) {
    const Matrix3<S> cx = skew(com);
    return Inertia(mass, mass * com, inertia_com + mass * cx * cx.transpose());
  }

  /// Centre of mass (undefined for m = 0).
  Vector3<S> com() const { return h / m; }
  /// Rotational inertia about the centre of mass: Ī − m c̃ c̃ᵀ.
  Matrix3<S> inertia_com() const {
    const Matrix3<S> hx = skew(h);
    return I - hx * hx.transpose() / m;
  }

  /// I v = [Ī ω + h × v; m v − h × ω]  (momentum of a body moving with v).
  Force<S> operator*(const Motion<S>& v) const { return Force<S>(I * v.w + h.cross(v.v), m * v.v - h.cross(v.w)); }

  Inertia& operator+=(const Inertia& o) { m += o.m; h += o.h; I += o.I; return *this; }
  friend Inertia operator+(const Inertia& a, const Inertia& b) { return Inertia(a.m + b.m, a.h + b.h, a.I + b.I); }

  /// This inertia, given in A coordinates, expressed in B coordinates for X = ᴮX_A: X* I X⁻¹ (RBDA Table 2.8):
  /// (m, E(h − m r), E(Ī + r̃ h̃ + (h − m r)~ r̃) Eᵀ).
  Inertia transformed(const Transform<S>& X) const {
    const Vector3<S> hmr = h - m * X.r;
    const Matrix3<S> rx = skew(X.r);
    const Matrix3<S> J = I + rx * skew(h) + skew(hmr) * rx;
    return Inertia(m, X.E * hmr, X.E * J * X.E.transpose());
  }
  /// This inertia, given in B coordinates, expressed in A coordinates for X = ᴮX_A: Xᵀ I X (RBDA eq. 2.66),
  /// the step by which CRBA and ABA pass a child's inertia to its parent.
  Inertia transformed_inverse(const Transform<S>& X) const {
    // Rotate into A's orientation, then shift the origin by -r: (m, h' + m r, Ī' − r̃ h̃' − (h' + m r)~ r̃) ...
    // written via the forward formula with the inverse transform.
    return transformed(X.inverse());
  }

  /// [Ī h̃; h̃ᵀ m1] (tests, diagnostics and ABA's articulated inertias).
  Matrix6<S> matrix() const {
    Matrix6<S> M;
    const Matrix3<S> hx = skew(h);
    M.template topLeftCorner<3, 3>() = I;
    M.template topRightCorner<3, 3>() = hx;
    M.template bottomLeftCorner<3, 3>() = hx.transpose();
    M.template bottomRightCorner<3, 3>() = m * Matrix3<S>::Identity();
    return M;
  }
  template <class T>
  Inertia<T> cast() const {
    return Inertia<T>(T(m), h.template cast<T>(), I.template cast<T>());
  }
};

/// A general symmetric 6×6 inertia (articulated-body inertia, RBDA §7.1), as the blocks [A B; Bᵀ C] with A = Aᵀ
/// and C = Cᵀ: maps motion to force.
template <class S>
struct ArticulatedInertia {
  using Scalar = S;
  Matrix3<S> A, B, C;

  ArticulatedInertia() = default;
  ArticulatedInertia(const Matrix3<S>& a, const Matrix3<S>& b, const Matrix3<S>& c) : A(a), B(b), C(c) {}
  explicit ArticulatedInertia(const Inertia<S>& I) : A(I.I), B(skew(I.h)), C(I.m * Matrix3<S>::Identity()) {}

  Force<S> operator*(const Motion<S>& v) const {
    return Force<S>(A * v.w + B * v.v, B.transpose() * v.w + C * v.v);
  }
  ArticulatedInertia& operator+=(const ArticulatedInertia& o) { A += o.A; B += o.B; C += o.C; return *this; }
  /// Subtract the rank-one term U Uᵀ / d (U a force vector).
  void subtract_outer(const Force<S>& U, S inv_d) {
    A.noalias() -= (inv_d * U.n) * U.n.transpose();
    B.noalias() -= (inv_d * U.n) * U.f.transpose();
    C.noalias() -= (inv_d * U.f) * U.f.transpose();
  }
  /// Xᵀ M X for X = ᴮX_A, M given in B coordinates: the same inertia in A coordinates.
  ArticulatedInertia transformed_inverse(const Transform<S>& X) const {
    // Rotate: M' = diag(E,E)ᵀ M diag(E,E); then shift by xlt(r): [1 r̃; 0 1] M' [1 0; −r̃ 1].
    const Matrix3<S> Et = X.E.transpose();
    const Matrix3<S> a = Et * A * X.E, b = Et * B * X.E, c = Et * C * X.E;
    const Matrix3<S> rx = skew(X.r);
    const Matrix3<S> bl = b.transpose() - c * rx;  // lower-left block of the result
    ArticulatedInertia out;
    out.A = a - b * rx + rx * bl;
    out.B = b + rx * c;
    out.C = c;
    return out;
  }
  Matrix6<S> matrix() const {
    Matrix6<S> M;
    M.template topLeftCorner<3, 3>() = A;
    M.template topRightCorner<3, 3>() = B;
    M.template bottomLeftCorner<3, 3>() = B.transpose();
    M.template bottomRightCorner<3, 3>() = C;
    return M;
  }
};

}  // namespace spatial

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
#include <utility>

/// Forces inlining of the small algebra operations: GCC otherwise keeps some out of line, and returning spatial
/// vectors through memory from many small calls costs more than the arithmetic itself. SPATIAL_NO_FORCED_INLINE
/// turns it off (here and for the AVX2 kernels' lambdas, SPATIAL_LAMBDA_INLINE): the same code, compiled faster
/// unoptimised or at -O1, where the forced inlining only makes every unrolled function larger (the test programs
/// define it).
/// SPATIAL_LAMBDA_INLINE does the same for a lambda's body (GCC otherwise keeps some per-body lambdas out of line).
#if (defined(__GNUC__) || defined(__clang__)) && !defined(SPATIAL_NO_FORCED_INLINE)
#define SPATIAL_INLINE __attribute__((always_inline)) inline
#define SPATIAL_LAMBDA_INLINE __attribute__((always_inline))
#else
#define SPATIAL_INLINE inline
#define SPATIAL_LAMBDA_INLINE
#endif

/// Fully unrolls the fixed 3-trip loops of the 3×3 kernels (GCC does not always do it by itself).
#if defined(__clang__) || defined(__GNUC__)
#define SPATIAL_UNROLL _Pragma("GCC unroll 3")
#else
#define SPATIAL_UNROLL
#endif

namespace spatial {

template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <class S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;
template <class S>
using Vector6 = Eigen::Matrix<S, 6, 1>;
template <class S>
using Matrix6 = Eigen::Matrix<S, 6, 6>;

namespace detail {
/// Whether Motion, Force, Transform and ArticulatedInertia build, copy and move their parts by assignment, element
/// by element, rather than by Eigen's copy construction: so for scalars that are SIMD registers (batch.hpp's lanes)
/// and other class types. GCC 12 copy-constructs and moves an Eigen vector of registers as a block of memory,
/// through the general-purpose registers eight bytes at a time or `rep movs`; assigned, each element is one vector
/// move. That took a batched RNEA on stance21 from 11 500 to 7 950 instructions per call of four lanes (AVX2,
/// callgrind, bench/callgrind_batch.cpp). For float and double the parts are copy-constructed as before (the same
/// code; with assignments GCC's scalar CRBA on a compile-time tree ran 3 % more instructions).
template <class S>
inline constexpr bool kAssignParts = !std::is_arithmetic_v<S>;

/// dst = src element by element, with no call left to Eigen's assignment: GCC keeps that out of line in some large
/// functions (with it, the batched gravity ran 11 % more instructions; callgrind_batch.cpp).
template <class M, std::size_t... I>
SPATIAL_INLINE void copy_elements(M& dst, const M& src, std::index_sequence<I...>) {
  ((dst.data()[I] = src.data()[I]), ...);
}
template <class M>
SPATIAL_INLINE void copy_elements(M& dst, const M& src) {
  copy_elements(dst, src, std::make_index_sequence<M::SizeAtCompileTime>());
}

// The data members of Motion, Force, Transform, Inertia and ArticulatedInertia (their bases): for float and double a plain
// struct; for kAssignParts scalars the same struct wrapped in AssignedCopy, which builds and copies it through the
// struct's `assign` overloads (from the parts, or from another one).
template <class S>
struct MotionPlain {
  Vector3<S> w;  ///< angular part ω
  Vector3<S> v;  ///< linear part v_O: velocity of the body-fixed point at the frame origin O
  MotionPlain() = default;
  SPATIAL_INLINE MotionPlain(const Vector3<S>& w_, const Vector3<S>& v_) : w(w_), v(v_) {}
  SPATIAL_INLINE void assign(const Vector3<S>& w_, const Vector3<S>& v_) {
    copy_elements(w, w_);
    copy_elements(v, v_);
  }
  SPATIAL_INLINE void assign(const MotionPlain& o) { assign(o.w, o.v); }
};
template <class S>
struct ForcePlain {
  Vector3<S> n;  ///< moment about the frame origin O
  Vector3<S> f;  ///< linear force
  ForcePlain() = default;
  SPATIAL_INLINE ForcePlain(const Vector3<S>& n_, const Vector3<S>& f_) : n(n_), f(f_) {}
  SPATIAL_INLINE void assign(const Vector3<S>& n_, const Vector3<S>& f_) {
    copy_elements(n, n_);
    copy_elements(f, f_);
  }
  SPATIAL_INLINE void assign(const ForcePlain& o) { assign(o.n, o.f); }
};
template <class S>
struct TransformPlain {
  Matrix3<S> E;  ///< rotation ᴮE_A (see Transform)
  Vector3<S> r;  ///< translation (see Transform)
  TransformPlain() = default;
  SPATIAL_INLINE TransformPlain(const Matrix3<S>& E_, const Vector3<S>& r_) : E(E_), r(r_) {}
  SPATIAL_INLINE void assign(const Matrix3<S>& E_, const Vector3<S>& r_) {
    copy_elements(E, E_);
    copy_elements(r, r_);
  }
  SPATIAL_INLINE void assign(const TransformPlain& o) { assign(o.E, o.r); }
};
template <class S>
struct ArticulatedInertiaPlain {
  Matrix3<S> A, B, C;  ///< the blocks [A B; Bᵀ C] (see ArticulatedInertia)
  ArticulatedInertiaPlain() = default;
  template <class X, class Y, class Z>  // any 3×3 expressions
  SPATIAL_INLINE ArticulatedInertiaPlain(const X& a, const Y& b, const Z& c) : A(a), B(b), C(c) {}
  template <class X, class Y, class Z>
  SPATIAL_INLINE void assign(const X& a, const Y& b, const Z& c) {
    A = a;
    B = b;
    C = c;
  }
  SPATIAL_INLINE void assign(const ArticulatedInertiaPlain& o) {
    copy_elements(A, o.A);
    copy_elements(B, o.B);
    copy_elements(C, o.C);
  }
};

template <class S>
struct InertiaPlain {
  S m;
  Vector3<S> h;
  Matrix3<S> I;
  InertiaPlain() = default;
  SPATIAL_INLINE InertiaPlain(const S& m_, const Vector3<S>& h_, const Matrix3<S>& I_) : m(m_), h(h_), I(I_) {}
  SPATIAL_INLINE void assign(const S& m_, const Vector3<S>& h_, const Matrix3<S>& I_) {
    m = m_;
    copy_elements(h, h_);
    copy_elements(I, I_);
  }
  SPATIAL_INLINE void assign(const InertiaPlain& o) { assign(o.m, o.h, o.I); }
};
/// Plain, built and copied by assignment: default-initialized, then `Plain::assign` from the parts or from the other
/// one. A user-declared copy constructor and no move: a move copies the same way.
template <class Plain>
struct AssignedCopy : Plain {
  SPATIAL_INLINE AssignedCopy() {}  // user-provided: delegating to it default-initializes, never zero-fills
  template <class... Parts, std::enable_if_t<(sizeof...(Parts) >= 2), int> = 0>
  SPATIAL_INLINE AssignedCopy(const Parts&... parts) : AssignedCopy() {
    this->assign(parts...);
  }
  SPATIAL_INLINE AssignedCopy(const AssignedCopy& o) : AssignedCopy() { this->assign(static_cast<const Plain&>(o)); }
  SPATIAL_INLINE AssignedCopy& operator=(const AssignedCopy& o) {
    this->assign(static_cast<const Plain&>(o));
    return *this;
  }
};

template <class Plain, class S>
using PartsOf = std::conditional_t<kAssignParts<S>, AssignedCopy<Plain>, Plain>;
template <class S>
using MotionParts = PartsOf<MotionPlain<S>, S>;
template <class S>
using ForceParts = PartsOf<ForcePlain<S>, S>;
template <class S>
using TransformParts = PartsOf<TransformPlain<S>, S>;
template <class S>
using ArticulatedInertiaParts = PartsOf<ArticulatedInertiaPlain<S>, S>;
template <class S>
using InertiaParts = PartsOf<InertiaPlain<S>, S>;
}  // namespace detail

/// The 3×3 matrix r̃ with r̃ p = r × p (RBDA eq. 2.9).
template <class S>
SPATIAL_INLINE Matrix3<S> skew(const Vector3<S>& r) {
  Matrix3<S> m;
  m << S(0), -r.z(), r.y(),  //
      r.z(), S(0), -r.x(),   //
      -r.y(), r.x(), S(0);
  return m;
}

namespace detail {
// Hand-written 3D kernels for the hot paths. Eigen's expression templates give the same arithmetic, but inside the
// large unrolled functions of a compile-time tree GCC stops inlining them and the cost doubles; these are small
// enough to be inlined always.
template <class S>
SPATIAL_INLINE Vector3<S> mul(const Matrix3<S>& E, const Vector3<S>& x) {
  return Vector3<S>(E(0, 0) * x[0] + E(0, 1) * x[1] + E(0, 2) * x[2],  //
                    E(1, 0) * x[0] + E(1, 1) * x[1] + E(1, 2) * x[2],  //
                    E(2, 0) * x[0] + E(2, 1) * x[1] + E(2, 2) * x[2]);
}
/// Eᵀ x
template <class S>
SPATIAL_INLINE Vector3<S> mul_t(const Matrix3<S>& E, const Vector3<S>& x) {
  return Vector3<S>(E(0, 0) * x[0] + E(1, 0) * x[1] + E(2, 0) * x[2],  //
                    E(0, 1) * x[0] + E(1, 1) * x[1] + E(2, 1) * x[2],  //
                    E(0, 2) * x[0] + E(1, 2) * x[1] + E(2, 2) * x[2]);
}
template <class S>
SPATIAL_INLINE Vector3<S> cross3(const Vector3<S>& a, const Vector3<S>& b) {
  return Vector3<S>(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}
template <class S>
SPATIAL_INLINE Vector3<S> add3(const Vector3<S>& a, const Vector3<S>& b) {
  return Vector3<S>(a[0] + b[0], a[1] + b[1], a[2] + b[2]);
}
template <class S>
SPATIAL_INLINE Vector3<S> sub3(const Vector3<S>& a, const Vector3<S>& b) {
  return Vector3<S>(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}
template <class S>
SPATIAL_INLINE Vector3<S> scale3(S s, const Vector3<S>& a) {
  return Vector3<S>(s * a[0], s * a[1], s * a[2]);
}
template <class S>
SPATIAL_INLINE S dot3(const Vector3<S>& a, const Vector3<S>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/// A B
template <class S>
SPATIAL_INLINE Matrix3<S> mul(const Matrix3<S>& A, const Matrix3<S>& B) {
  Matrix3<S> C;
  SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
    SPATIAL_UNROLL for (int j = 0; j < 3; ++j) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j) + A(i, 2) * B(2, j);
  return C;
}
/// Aᵀ B
template <class S>
SPATIAL_INLINE Matrix3<S> mul_tn(const Matrix3<S>& A, const Matrix3<S>& B) {
  Matrix3<S> C;
  SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
    SPATIAL_UNROLL for (int j = 0; j < 3; ++j) C(i, j) = A(0, i) * B(0, j) + A(1, i) * B(1, j) + A(2, i) * B(2, j);
  return C;
}
/// Eᵀ M E for symmetric M (the result is exactly symmetric).
template <class S>
SPATIAL_INLINE Matrix3<S> sym_congruence(const Matrix3<S>& E, const Matrix3<S>& M) {
  const Matrix3<S> T = mul(M, E);
  Matrix3<S> C;
  SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
    SPATIAL_UNROLL for (int j = i; j < 3; ++j) {
      C(i, j) = E(0, i) * T(0, j) + E(1, i) * T(1, j) + E(2, i) * T(2, j);
      C(j, i) = C(i, j);
    }
  return C;
}
/// M r̃: row i is (row i of M) × r.
template <class S>
SPATIAL_INLINE Matrix3<S> mul_skew(const Matrix3<S>& M, const Vector3<S>& r) {
  Matrix3<S> C;
  SPATIAL_UNROLL for (int i = 0; i < 3; ++i) {
    C(i, 0) = M(i, 1) * r[2] - M(i, 2) * r[1];
    C(i, 1) = M(i, 2) * r[0] - M(i, 0) * r[2];
    C(i, 2) = M(i, 0) * r[1] - M(i, 1) * r[0];
  }
  return C;
}
/// r̃ M: column j is r × (column j of M).
template <class S>
SPATIAL_INLINE Matrix3<S> skew_mul(const Vector3<S>& r, const Matrix3<S>& M) {
  Matrix3<S> C;
  SPATIAL_UNROLL for (int j = 0; j < 3; ++j) {
    C(0, j) = r[1] * M(2, j) - r[2] * M(1, j);
    C(1, j) = r[2] * M(0, j) - r[0] * M(2, j);
    C(2, j) = r[0] * M(1, j) - r[1] * M(0, j);
  }
  return C;
}
/// a bᵀ + b aᵀ
template <class S>
SPATIAL_INLINE Matrix3<S> sym_outer(const Vector3<S>& a, const Vector3<S>& b) {
  Matrix3<S> C;
  SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
    SPATIAL_UNROLL for (int j = 0; j < 3; ++j) C(i, j) = a[i] * b[j] + b[i] * a[j];
  return C;
}
}  // namespace detail

/// A spatial motion vector (velocity, acceleration, motion subspace column): [ω; v_O], angular first.
template <class S>
struct Motion : detail::MotionParts<S> {
  using Scalar = S;
  using Parts = detail::MotionParts<S>;
  using Parts::w;  ///< angular part ω
  using Parts::v;  ///< linear part v_O: velocity of the body-fixed point at the frame origin O

  Motion() = default;
  SPATIAL_INLINE Motion(const Vector3<S>& angular, const Vector3<S>& linear) : Parts(angular, linear) {}
  /// From the six Plücker coordinates [ω; v].
  explicit Motion(const Vector6<S>& m) : Parts(m.template head<3>(), m.template tail<3>()) {}
  static SPATIAL_INLINE Motion Zero() { return Motion(Vector3<S>::Zero(), Vector3<S>::Zero()); }

  const Vector3<S>& angular() const { return w; }
  const Vector3<S>& linear() const { return v; }
  Vector6<S> vector() const {
    Vector6<S> out;
    out << w, v;
    return out;
  }
  template <class T>
  SPATIAL_INLINE Motion<T> cast() const {
    return Motion<T>(w.template cast<T>(), v.template cast<T>());
  }
  SPATIAL_INLINE Motion& operator+=(const Motion& o) { w = detail::add3(w, o.w); v = detail::add3(v, o.v); return *this; }
  SPATIAL_INLINE Motion& operator-=(const Motion& o) { w = detail::sub3(w, o.w); v = detail::sub3(v, o.v); return *this; }
  friend SPATIAL_INLINE Motion operator+(const Motion& a, const Motion& b) { return Motion(detail::add3(a.w, b.w), detail::add3(a.v, b.v)); }
  friend SPATIAL_INLINE Motion operator-(const Motion& a, const Motion& b) { return Motion(detail::sub3(a.w, b.w), detail::sub3(a.v, b.v)); }
  friend SPATIAL_INLINE Motion operator-(const Motion& a) { return Motion(-a.w, -a.v); }
  friend SPATIAL_INLINE Motion operator*(S s, const Motion& a) { return Motion(detail::scale3(s, a.w), detail::scale3(s, a.v)); }
  friend SPATIAL_INLINE Motion operator*(const Motion& a, S s) { return s * a; }
};

/// A spatial force vector (force, momentum, impulse): [n_O; f], moment about the frame origin O first.
template <class S>
struct Force : detail::ForceParts<S> {
  using Scalar = S;
  using Parts = detail::ForceParts<S>;
  using Parts::n;  ///< moment about the frame origin O
  using Parts::f;  ///< linear force

  Force() = default;
  SPATIAL_INLINE Force(const Vector3<S>& moment, const Vector3<S>& linear) : Parts(moment, linear) {}
  /// From the six Plücker coordinates [n; f].
  explicit Force(const Vector6<S>& x) : Parts(x.template head<3>(), x.template tail<3>()) {}
  static SPATIAL_INLINE Force Zero() { return Force(Vector3<S>::Zero(), Vector3<S>::Zero()); }

  const Vector3<S>& angular() const { return n; }
  const Vector3<S>& linear() const { return f; }
  Vector6<S> vector() const {
    Vector6<S> out;
    out << n, f;
    return out;
  }
  template <class T>
  SPATIAL_INLINE Force<T> cast() const {
    return Force<T>(n.template cast<T>(), f.template cast<T>());
  }
  SPATIAL_INLINE Force& operator+=(const Force& o) { n = detail::add3(n, o.n); f = detail::add3(f, o.f); return *this; }
  SPATIAL_INLINE Force& operator-=(const Force& o) { n = detail::sub3(n, o.n); f = detail::sub3(f, o.f); return *this; }
  friend SPATIAL_INLINE Force operator+(const Force& a, const Force& b) { return Force(detail::add3(a.n, b.n), detail::add3(a.f, b.f)); }
  friend SPATIAL_INLINE Force operator-(const Force& a, const Force& b) { return Force(detail::sub3(a.n, b.n), detail::sub3(a.f, b.f)); }
  friend SPATIAL_INLINE Force operator-(const Force& a) { return Force(-a.n, -a.f); }
  friend SPATIAL_INLINE Force operator*(S s, const Force& a) { return Force(detail::scale3(s, a.n), detail::scale3(s, a.f)); }
  friend SPATIAL_INLINE Force operator*(const Force& a, S s) { return s * a; }
};

/// The scalar product m · f (power, work): the only product between the two spaces (RBDA §2.6).
template <class S>
SPATIAL_INLINE S dot(const Motion<S>& m, const Force<S>& f) {
  return detail::dot3(m.w, f.n) + detail::dot3(m.v, f.f);
}
template <class S>
SPATIAL_INLINE S dot(const Force<S>& f, const Motion<S>& m) {
  return dot(m, f);
}

/// Motion cross product a × b = [ω̃ 0; ṽ ω̃] b (RBDA eq. 2.31): the rate of change of the motion vector b
/// moving with velocity a.
template <class S>
SPATIAL_INLINE Motion<S> cross(const Motion<S>& a, const Motion<S>& b) {
  using namespace detail;
  return Motion<S>(cross3(a.w, b.w), add3(cross3(a.w, b.v), cross3(a.v, b.w)));
}

/// Force cross product a ×* f = [ω̃ ṽ; 0 ω̃] f = −(a×)ᵀ f (RBDA eq. 2.32).
template <class S>
SPATIAL_INLINE Force<S> cross(const Motion<S>& a, const Force<S>& f) {
  using namespace detail;
  return Force<S>(add3(cross3(a.w, f.n), cross3(a.v, f.f)), cross3(a.w, f.f));
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
struct Transform : detail::TransformParts<S> {
  using Scalar = S;
  using Parts = detail::TransformParts<S>;
  using Parts::E;
  using Parts::r;

  Transform() = default;
  SPATIAL_INLINE Transform(const Matrix3<S>& rotation, const Vector3<S>& translation) : Parts(rotation, translation) {}
  static SPATIAL_INLINE Transform Identity() { return Transform(Matrix3<S>::Identity(), Vector3<S>::Zero()); }

  /// ᴮm = X ᴬm: [E ω; E (v − r × ω)].
  SPATIAL_INLINE Motion<S> apply(const Motion<S>& m) const {
    using namespace detail;
    return Motion<S>(mul(E, m.w), mul(E, sub3(m.v, cross3(r, m.w))));
  }
  /// ᴬm = X⁻¹ ᴮm: [Eᵀ ω; Eᵀ v + r × Eᵀ ω].
  SPATIAL_INLINE Motion<S> apply_inverse(const Motion<S>& m) const {
    using namespace detail;
    const Vector3<S> w = mul_t(E, m.w);
    return Motion<S>(w, add3(mul_t(E, m.v), cross3(r, w)));
  }
  /// ᴮf = X* ᴬf: [E (n − r × f); E f].
  SPATIAL_INLINE Force<S> apply_force(const Force<S>& f) const {
    using namespace detail;
    return Force<S>(mul(E, sub3(f.n, cross3(r, f.f))), mul(E, f.f));
  }
  /// ᴬf = Xᵀ ᴮf (the inverse of X*): [Eᵀ n + r × Eᵀ f; Eᵀ f].
  SPATIAL_INLINE Force<S> apply_force_inverse(const Force<S>& f) const {
    using namespace detail;
    const Vector3<S> lin = mul_t(E, f.f);
    return Force<S>(add3(mul_t(E, f.n), cross3(r, lin)), lin);
  }

  /// ᴬX_B.
  SPATIAL_INLINE Transform inverse() const { return Transform(E.transpose(), -(E * r)); }

  /// Composition: (ᶜX_B)(ᴮX_A) = ᶜX_A.  With X1 = (E1, r1), X2 = (E2, r2): E = E1 E2, r = r2 + E2ᵀ r1.
  SPATIAL_INLINE Transform operator*(const Transform& x2) const {
    return Transform(detail::mul(E, x2.E), detail::add3(x2.r, detail::mul_t(x2.E, r)));
  }
  SPATIAL_INLINE Motion<S> operator*(const Motion<S>& m) const { return apply(m); }
  SPATIAL_INLINE Force<S> operator*(const Force<S>& f) const { return apply_force(f); }

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
  SPATIAL_INLINE Transform<T> cast() const {
    return Transform<T>(E.template cast<T>(), r.template cast<T>());
  }
};

/// Passive rotation matrices: coordinates of a vector in a frame rotated by θ about x, y, z (RBDA eq. 2.20).
template <class S>
SPATIAL_INLINE Matrix3<S> rotx_matrix(S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  Matrix3<S> e;
  e << S(1), S(0), S(0), S(0), c, s, S(0), -s, c;
  return e;
}
template <class S>
SPATIAL_INLINE Matrix3<S> roty_matrix(S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  Matrix3<S> e;
  e << c, S(0), -s, S(0), S(1), S(0), s, S(0), c;
  return e;
}
template <class S>
SPATIAL_INLINE Matrix3<S> rotz_matrix(S theta) {
  using std::cos;
  using std::sin;
  const S c = cos(theta), s = sin(theta);
  Matrix3<S> e;
  e << c, s, S(0), -s, c, S(0), S(0), S(0), S(1);
  return e;
}
/// Passive rotation by θ about the unit axis a: E = cosθ·1 + (1 − cosθ) a aᵀ − sinθ ã  (transpose of Rodrigues),
/// from c = cos θ and s = sin θ.
template <class S>
SPATIAL_INLINE Matrix3<S> rot_axis_matrix_cs(const Vector3<S>& a, S c, S s) {
  const S t = S(1) - c;
  Matrix3<S> E;
  E << c + t * a[0] * a[0], t * a[0] * a[1] + s * a[2], t * a[0] * a[2] - s * a[1],  //
      t * a[1] * a[0] - s * a[2], c + t * a[1] * a[1], t * a[1] * a[2] + s * a[0],   //
      t * a[2] * a[0] + s * a[1], t * a[2] * a[1] - s * a[0], c + t * a[2] * a[2];
  return E;
}
template <class S>
SPATIAL_INLINE Matrix3<S> rot_axis_matrix(const Vector3<S>& a, S theta) {
  using std::cos;
  using std::sin;
  return rot_axis_matrix_cs(a, S(cos(theta)), S(sin(theta)));
}

/// The frame rotated by θ about x (RBDA eq. 2.20, `rotx` in spatial_v2).
template <class S>
SPATIAL_INLINE Transform<S> rotx(S theta) { return Transform<S>(rotx_matrix(theta), Vector3<S>::Zero()); }
template <class S>
SPATIAL_INLINE Transform<S> roty(S theta) { return Transform<S>(roty_matrix(theta), Vector3<S>::Zero()); }
template <class S>
SPATIAL_INLINE Transform<S> rotz(S theta) { return Transform<S>(rotz_matrix(theta), Vector3<S>::Zero()); }
/// The frame translated by r (coordinates of the new origin in the old frame) (RBDA eq. 2.21, `xlt`).
template <class S>
SPATIAL_INLINE Transform<S> xlt(const Vector3<S>& r) { return Transform<S>(Matrix3<S>::Identity(), r); }

/// Spatial rigid-body inertia, stored compactly (RBDA §2.13, eq. 2.63): mass m, first moment h = m c and the
/// rotational inertia Ī about the frame origin. As a 6×6 it is [Ī h̃; h̃ᵀ m1].
template <class S>
struct Inertia : detail::InertiaParts<S> {
  using Scalar = S;
  using Parts = detail::InertiaParts<S>;
  using Parts::m;  ///< mass
  using Parts::h;  ///< first moment m c about the frame origin
  using Parts::I;  ///< rotational inertia about the frame origin (symmetric)

  Inertia() = default;
  Inertia(S mass, const Vector3<S>& first_moment, const Matrix3<S>& rot_inertia_origin)
      : Parts(mass, first_moment, rot_inertia_origin) {}
  static SPATIAL_INLINE Inertia Zero() { return Inertia(S(0), Vector3<S>::Zero(), Matrix3<S>::Zero()); }

  /// From mass, centre of mass c and rotational inertia I_c about the centre of mass, all in this frame:
  /// Ī = I_c + m c̃ c̃ᵀ (parallel-axis theorem, RBDA eq. 2.63).
  static SPATIAL_INLINE Inertia from_com(S mass, const Vector3<S>& com, const Matrix3<S>& inertia_com) {
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
  SPATIAL_INLINE Force<S> operator*(const Motion<S>& v) const {
    using namespace detail;
    return Force<S>(add3(mul(I, v.w), cross3(h, v.v)), sub3(scale3(m, v.v), cross3(h, v.w)));
  }

  SPATIAL_INLINE Inertia& operator+=(const Inertia& o) { m += o.m; h += o.h; I += o.I; return *this; }
  friend SPATIAL_INLINE Inertia operator+(const Inertia& a, const Inertia& b) { return Inertia(a.m + b.m, a.h + b.h, a.I + b.I); }

  /// This inertia, given in A coordinates, expressed in B coordinates for X = ᴮX_A: X* I X⁻¹ (RBDA Table 2.8):
  /// (m, E(h − m r), E(Ī + r̃ h̃ + (h − m r)~ r̃) Eᵀ).
  SPATIAL_INLINE Inertia transformed(const Transform<S>& X) const {
    const Vector3<S> hmr = h - m * X.r;
    const Matrix3<S> rx = skew(X.r);
    const Matrix3<S> J = I + rx * skew(h) + skew(hmr) * rx;
    return Inertia(m, X.E * hmr, X.E * J * X.E.transpose());
  }
  /// This inertia, given in B coordinates, expressed in A coordinates for X = ᴮX_A: Xᵀ I X (RBDA eq. 2.66),
  /// the step by which CRBA passes a child's inertia to its parent. Rotate into A's axes (h′ = Eᵀh,
  /// Ī′ = Eᵀ Ī E), then move the origin by −r: h = h′ + m r and, from Ī = Σ −mₖ p̃ₖ p̃ₖ with pₖ → pₖ + r,
  /// Ī = Ī′ − (r̃ h̃′ + h̃′ r̃) − m r̃ r̃ = Ī′ − (r h′ᵀ + h′ rᵀ) + 2 (h′·r) 1 − m (r rᵀ − (r·r) 1)
  ///   = Ī′ − (r gᵀ + g rᵀ) + 2 (g·r) 1  with g = h′ + (m/2) r  (only the upper triangle is computed).
  SPATIAL_INLINE Inertia transformed_inverse(const Transform<S>& X) const {
    using namespace detail;
    const Vector3<S> hp = mul_t(X.E, h);
    const Vector3<S>& r = X.r;
    const Vector3<S> g = add3(hp, scale3(m / S(2), r));
    const S d = S(2) * dot3(g, r);
    Matrix3<S> J = sym_congruence(X.E, I);
    SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
      SPATIAL_UNROLL for (int j = i; j < 3; ++j) {
        J(i, j) -= r[i] * g[j] + g[i] * r[j];
        if (i == j) J(i, j) += d;
        J(j, i) = J(i, j);
      }
    return Inertia(m, add3(hp, scale3(m, r)), J);
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
  SPATIAL_INLINE Inertia<T> cast() const {
    return Inertia<T>(T(m), h.template cast<T>(), I.template cast<T>());
  }
};

/// A general symmetric 6×6 inertia (articulated-body inertia, RBDA §7.1), as the blocks [A B; Bᵀ C] with A = Aᵀ
/// and C = Cᵀ: maps motion to force.
template <class S>
struct ArticulatedInertia : detail::ArticulatedInertiaParts<S> {
  using Scalar = S;
  using Parts = detail::ArticulatedInertiaParts<S>;
  using Parts::A;
  using Parts::B;
  using Parts::C;

  ArticulatedInertia() = default;
  SPATIAL_INLINE ArticulatedInertia(const Matrix3<S>& a, const Matrix3<S>& b, const Matrix3<S>& c) : Parts(a, b, c) {}
  explicit ArticulatedInertia(const Inertia<S>& I) : Parts(I.I, skew(I.h), I.m * Matrix3<S>::Identity()) {}

  SPATIAL_INLINE Force<S> operator*(const Motion<S>& v) const {
    using namespace detail;
    return Force<S>(add3(mul(A, v.w), mul(B, v.v)), add3(mul_t(B, v.w), mul(C, v.v)));
  }
  /// M c for K ≥ 0 when row and column K of A and row K of B are zero (see subtract_outer) and c has zero
  /// components K in both halves (c = v × S q̇ for a revolute joint about axis K): the zero terms are skipped.
  /// K = −1: the full product.
  template <int K>
  SPATIAL_INLINE Force<S> mul_null(const Motion<S>& c) const {
    if constexpr (K < 0) {
      return *this * c;
    } else {
      constexpr int k1 = (K + 1) % 3, k2 = (K + 2) % 3;
      Vector3<S> n, f;
      n[K] = S(0);
      n[k1] = A(k1, k1) * c.w[k1] + A(k1, k2) * c.w[k2] + B(k1, k1) * c.v[k1] + B(k1, k2) * c.v[k2];
      n[k2] = A(k2, k1) * c.w[k1] + A(k2, k2) * c.w[k2] + B(k2, k1) * c.v[k1] + B(k2, k2) * c.v[k2];
      SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
        f[i] = B(k1, i) * c.w[k1] + B(k2, i) * c.w[k2] + C(i, k1) * c.v[k1] + C(i, k2) * c.v[k2];
      return Force<S>(n, f);
    }
  }
  SPATIAL_INLINE ArticulatedInertia& operator+=(const ArticulatedInertia& o) {
    SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
      SPATIAL_UNROLL for (int j = 0; j < 3; ++j) {
        A(i, j) += o.A(i, j);
        B(i, j) += o.B(i, j);
        C(i, j) += o.C(i, j);
      }
    return *this;
  }
  /// Subtract the rank-one term U Uᵀ / d (U a force vector). With K ≥ 0, U = Iᴬ e_K (e_K: angular coordinate K,
  /// a revolute joint about axis K) and d = U_K: the result then maps e_K to zero, so row and column K of A and
  /// row K of B are set to exactly zero instead of being computed as round-off. Only upper triangles of the
  /// symmetric blocks are computed.
  template <int K = -1>
  SPATIAL_INLINE void subtract_outer(const Force<S>& U, S inv_d) {
    SPATIAL_UNROLL for (int i = 0; i < 3; ++i) {
      const S ni = inv_d * U.n[i], fi = inv_d * U.f[i];
      SPATIAL_UNROLL for (int j = 0; j < 3; ++j) {
        if (i == K) {
          A(i, j) = S(0);
          A(j, i) = S(0);
          B(i, j) = S(0);
        } else {
          if (j >= i && j != K) {
            A(i, j) -= ni * U.n[j];
            A(j, i) = A(i, j);
          }
          B(i, j) -= ni * U.f[j];
        }
        if (j >= i) {
          C(i, j) -= fi * U.f[j];
          C(j, i) = C(i, j);
        }
      }
    }
  }
  /// Xᵀ M X for X = ᴮX_A, M given in B coordinates: the same inertia in A coordinates.
  /// Rotate, M′ = diag(E, E)ᵀ M diag(E, E) = [a b; bᵀ c], then shift by xlt(r):
  /// [1 r̃; 0 1] M′ [1 0; −r̃ 1] = [a − b r̃ − (b r̃)ᵀ − r̃ c r̃,  b + r̃ c;  …,  c], using r̃ᵀ = −r̃ and c = cᵀ;
  /// with B′ = b + r̃ c the top-left block is a − B′ r̃ + r̃ bᵀ (symmetric: upper triangle computed).
  /// With K ≥ 0, row and column K of A and row K of B are known to be zero (see subtract_outer) and skipped.
  template <int K = -1>
  SPATIAL_INLINE ArticulatedInertia transformed_inverse(const Transform<S>& X) const {
    const Matrix3<S>& E = X.E;
    const Vector3<S>& r = X.r;
    Matrix3<S> AE, BE, CE, a, b, c;
    // AE = A E, BE = B E (rows K skipped), CE = C E.
    SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
      SPATIAL_UNROLL for (int j = 0; j < 3; ++j) {
        if (i != K) {
          S sa = S(0), sb = S(0);
          bool first = true;
          SPATIAL_UNROLL for (int k = 0; k < 3; ++k) {
            if (k == K) continue;
            sa = first ? A(i, k) * E(k, j) : sa + A(i, k) * E(k, j);
            first = false;
          }
          sb = B(i, 0) * E(0, j) + B(i, 1) * E(1, j) + B(i, 2) * E(2, j);
          AE(i, j) = sa;
          BE(i, j) = sb;
        }
        CE(i, j) = C(i, 0) * E(0, j) + C(i, 1) * E(1, j) + C(i, 2) * E(2, j);
      }
    // a = Eᵀ A E, b = Eᵀ B E (sums over k ≠ K), c = Eᵀ C E.
    SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
      SPATIAL_UNROLL for (int j = 0; j < 3; ++j) {
        S sa = S(0), sb = S(0);
        bool first = true;
        SPATIAL_UNROLL for (int k = 0; k < 3; ++k) {
          if (k == K) continue;
          if (j >= i) sa = first ? E(k, i) * AE(k, j) : sa + E(k, i) * AE(k, j);
          sb = first ? E(k, i) * BE(k, j) : sb + E(k, i) * BE(k, j);
          first = false;
        }
        b(i, j) = sb;
        if (j >= i) {
          a(i, j) = sa;
          c(i, j) = E(0, i) * CE(0, j) + E(1, i) * CE(1, j) + E(2, i) * CE(2, j);
          c(j, i) = c(i, j);
        }
      }
    ArticulatedInertia out;
    out.C = c;
    // B′ = b + r̃ c: column j is b_j + r × c_j.
    SPATIAL_UNROLL for (int j = 0; j < 3; ++j) {
      out.B(0, j) = b(0, j) + (r[1] * c(2, j) - r[2] * c(1, j));
      out.B(1, j) = b(1, j) + (r[2] * c(0, j) - r[0] * c(2, j));
      out.B(2, j) = b(2, j) + (r[0] * c(1, j) - r[1] * c(0, j));
    }
    // A′ = a − B′ r̃ + r̃ bᵀ: (B′ r̃)(i, j) = (row i of B′ × r)_j, (r̃ bᵀ)(i, j) = (r × row j of b)_i.
    SPATIAL_UNROLL for (int i = 0; i < 3; ++i)
      SPATIAL_UNROLL for (int j = i; j < 3; ++j) {
        const int j1 = (j + 1) % 3, j2 = (j + 2) % 3, i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        const S bpr = out.B(i, j1) * r[j2] - out.B(i, j2) * r[j1];
        const S rbt = r[i1] * b(j, i2) - r[i2] * b(j, i1);
        out.A(i, j) = a(i, j) - bpr + rbt;
        out.A(j, i) = out.A(i, j);
      }
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

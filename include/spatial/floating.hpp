#pragma once
/// \file floating.hpp
/// Floating-base trees (RBDA ch. 9.3–9.5): a free-flying root body — the **free-flyer joint** `floating_base` —
/// carrying a tree of one-DoF joints, and the algorithms on it.
///
/// `FloatingModel<S, TreeT>` is a `Model<S, TreeT>` whose base (body −1) moves: its spatial inertia is the root
/// body's (`root_inertia()`), and the tree's bodies 0 … n−1 hang from it exactly as they hang from the fixed base of
/// a fixed-base model. Body −1 is the root body throughout (frames attached to −1 ride on it).
///
/// Configuration, velocity and force vectors (nq = n + 7, nv = n + 6), Pinocchio's `JointModelFreeFlyer` order:
///
///   q = [x y z  qx qy qz qw  q₀ … qₙ₋₁]   position of the root frame's origin in the world, and the unit
///                                          quaternion of its orientation (root axes → world axes, Eigen's
///                                          (x, y, z, w) coefficient order), then the joints
///   v = [vx vy vz  wx wy wz  q̇₀ … q̇ₙ₋₁]   linear velocity of the root origin and angular velocity, **both in
///                                          root (body) coordinates**, then the joint rates
///   v̇ = [ax ay az  αx αy αz  q̈₀ …]        the time derivative of v: the root's *spatial* acceleration in root
///                                          coordinates (linear part: not the classical acceleration of the origin,
///                                          which is a + ω × v)
///   τ = [fx fy fz  nx ny nz  τ₀ …]         the wrench applied to the root (force, then moment about the root
///                                          origin), in root coordinates, then the joint forces; τᵀv is power.
///
/// So the six free-flyer entries are **linear first**, while `Motion`/`Force` objects are angular first (algebra.hpp):
/// `root_motion(v)` and `root_wrench(τ)` convert. Conversions to other libraries:
///  - Pinocchio (`JointModelFreeFlyer`, `pin.buildModelFromUrdf(f, pin.JointModelFreeFlyer())`): identical q, v, a, τ.
///  - MuJoCo (free joint): qpos = [x y z qw qx qy qz] (scalar first); qvel = [world-frame linear velocity of the
///    origin, body-frame angular velocity]: v_mj[0:3] = R v[0:3], v_mj[3:6] = v[3:6], with R the root's rotation.
///  - RBDL (`JointTypeFloatingBase` = translation + spherical): q = [x y z  qx qy qz  q₀ … qw] (w stored last, after
///    the joints), q̇ = [world-frame velocity of the origin, body-frame angular velocity].
///
/// Gravity is the model's `gravity()` in **world** coordinates; the algorithms turn it into root coordinates from
/// the quaternion. Per-body outputs in `data.tree` are in body coordinates as for fixed bases, with "base
/// coordinates" (`data.tree.X_base`) now meaning root coordinates; `data.X0` = ⁰X_w maps world → root.

#include "spatial/algorithms.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <type_traits>
#include <utility>

namespace spatial {

/// The name of the free-flyer joint in names, CSV columns and the URDF loader (`LoadOptions::floating`).
inline constexpr const char* kFreeFlyerName = "floating_base";

template <class S, class TreeT = DynamicTree>
class FloatingModel {
 public:
  using Scalar = S;
  using tree_type = TreeT;
  using TreeModel = Model<S, TreeT>;
  static constexpr bool is_static = TreeModel::is_static;
  /// Joints of the tree (compile-time trees), Eigen::Dynamic otherwise.
  static constexpr int NJ = TreeModel::NB;
  static constexpr int NQ = is_static ? NJ + 7 : int(Eigen::Dynamic);
  static constexpr int NV = is_static ? NJ + 6 : int(Eigen::Dynamic);
  using ConfigVector = Eigen::Matrix<S, NQ, 1>;
  using TangentVector = Eigen::Matrix<S, NV, 1>;

  FloatingModel() = default;
  /// The tree of joints hanging from the root body (its base frame is the root body's frame), the root body's
  /// spatial inertia (root coordinates) and the root link's name. Gravity is taken from `tree.gravity()`, read as
  /// world coordinates. Throws `ModelError` for an unphysical root inertia.
  FloatingModel(TreeModel tree, const Inertia<S>& root_inertia, std::string root_name = "root")
      : tree_(std::move(tree)), I0_(root_inertia), root_name_(std::move(root_name)) {
    const std::string bad = detail::inertia_problem(I0_).error;
    if (!bad.empty()) throw ModelError("root body '" + root_name_ + "': " + bad);
  }

  const TreeModel& tree() const { return tree_; }
  const Inertia<S>& root_inertia() const { return I0_; }
  const std::string& root_name() const { return root_name_; }
  /// The same model over a run-time tree (see `Model::to_runtime`).
  FloatingModel<S, DynamicTree> to_runtime() const {
    return FloatingModel<S, DynamicTree>(tree_.to_runtime(), I0_, root_name_);
  }
  /// Gravity in world coordinates.
  const Vector3<S>& gravity() const { return tree_.gravity(); }
  /// Joints of the tree (without the free-flyer).
  int njoints() const { return tree_.size(); }
  int nq() const { return tree_.size() + 7; }
  int nv() const { return tree_.size() + 6; }
  /// Index look-ups by name, as on `Model`: a joint or body of the tree (q index 7 + i, v index 6 + i), a fixed
  /// frame of `tree().frames()`; −1 when there is none (the root body is `root_name()`, body −1; the free-flyer is
  /// `kFreeFlyerName`).
  int joint_index(const std::string& name) const { return tree_.joint_index(name); }
  int body_index(const std::string& name) const { return tree_.body_index(name); }
  int frame_index(const std::string& name) const { return tree_.frame_index(name); }
  /// Mass of the whole robot: the root body and every body of the tree.
  S total_mass() const { return I0_.m + tree_.total_mass(); }

  /// The same model with another gravity vector (world coordinates).
  FloatingModel with_gravity(const Vector3<S>& g) const {
    FloatingModel m = *this;
    m.tree_ = tree_.with_gravity(g);
    return m;
  }
  /// The same model in another scalar type.
  template <class T>
  FloatingModel<T, TreeT> cast() const {
    FloatingModel<T, TreeT> out;
    out.tree_ = tree_.template cast<T>();
    out.I0_ = I0_.template cast<T>();
    out.root_name_ = root_name_;
    return out;
  }

 private:
  template <class, class>
  friend class FloatingModel;
  TreeModel tree_{};
  Inertia<S> I0_ = Inertia<S>::Zero();
  std::string root_name_ = "root";
};

/// Per-call buffers of the floating-base algorithms, allocated once here and never again.
template <class S, class TreeT = DynamicTree>
struct FloatingData {
  using ModelType = FloatingModel<S, TreeT>;
  static constexpr int NV = ModelType::NV;
  static constexpr int NM = detail::matrix_dim(NV);
  using VectorV = Eigen::Matrix<S, NV, 1>;
  using MatrixV = Eigen::Matrix<S, NM, NM>;

  explicit FloatingData(const ModelType& model) : tree(model.tree()) {
    const int nv = model.nv();
    tau = VectorV::Zero(nv);
    qdd = VectorV::Zero(nv);
    tmp = VectorV::Zero(nv);
    H = MatrixV::Zero(nv, nv);
    L = MatrixV::Zero(nv, nv);
    J = decltype(J)::Zero(6, nv), dJ = J;
  }

  Data<S, TreeT> tree;       ///< the tree's per-body buffers (body coordinates; "base" = root coordinates)
  Transform<S> X0 = Transform<S>::Identity();  ///< ⁰X_w: world → root coordinates (from q's position, quaternion)
  Motion<S> v0 = Motion<S>::Zero();  ///< root velocity (root coordinates)
  Motion<S> a0 = Motion<S>::Zero();  ///< RNEA/ABA: root acceleration minus gravity, a − a_g (root coordinates)
  Force<S> f0 = Force<S>::Zero();    ///< RNEA: the wrench the root needs (= τ's first six entries, angular first)
  Inertia<S> Ic0 = Inertia<S>::Zero();  ///< CRBA: composite inertia of the whole robot (root coordinates)
  ArticulatedInertia<S> IA0{};       ///< ABA: articulated inertia of the whole robot at the root
  Force<S> pA0 = Force<S>::Zero();   ///< ABA: its bias force
  VectorV tau;  ///< RNEA output (nv)
  VectorV qdd;  ///< forward dynamics output (nv)
  VectorV tmp;  ///< scratch: τ − C of forward dynamics by CRBA
  MatrixV H;    ///< joint-space inertia (nv × nv); entries coupling joints on different branches stay zero
  MatrixV L;    ///< LTDL factor of H (D on the diagonal)
  Eigen::Matrix<S, 6, NM> J, dJ;  ///< kinematics.hpp: Jacobians (World, 6 × nv, free-flyer first) and their J̇
  /// centroidal.hpp: centre of mass, its velocity and acceleration (world coordinates)
  Vector3<S> com = Vector3<S>::Zero(), vcom = Vector3<S>::Zero(), acom = Vector3<S>::Zero();
};

// ---------------------------------------------------------------------------------------------------------------
// Argument sizes (sizes.hpp for floating bases): q has nq = n + 7 entries, v, v̇ and τ nv = n + 6
// ---------------------------------------------------------------------------------------------------------------

namespace detail {
[[noreturn]] inline void floating_size_assertion_failed(const char* function, const char* argument, long long given,
                                                        bool config, long long expected, long long joints) {
  std::fprintf(stderr,
               "spatial: %s: argument '%s' has %lld entries, the floating model has %s = %lld (%d free-flyer %s + %lld "
               "joints)\n",
               function, argument, given, config ? "nq" : "nv", expected, config ? 7 : 6,
               config ? "coordinates" : "velocities", joints);
  std::fflush(stderr);
  std::abort();
}

/// The check of one argument of a floating-base entry point: `Config` = true for q (nq entries), false for v, v̇,
/// τ (nv). A fixed-size argument on a compile-time tree is checked by `static_assert`; otherwise a run-time
/// assertion as in sizes.hpp (SPATIAL_CHECK_SIZES, on without NDEBUG).
template <bool Config, class S, class T, class Vec>
inline void check_floating_size(const FloatingModel<S, T>& model, const Eigen::MatrixBase<Vec>& x,
                                const char* function, const char* argument) {
  constexpr int fixed = int(Vec::SizeAtCompileTime);
  if constexpr (FloatingModel<S, T>::is_static && fixed != int(Eigen::Dynamic)) {
    static_assert(fixed == (Config ? FloatingModel<S, T>::NQ : FloatingModel<S, T>::NV),
                  "spatial: a fixed-size vector argument of a floating-base model does not have nq = n + 7 (q) or "
                  "nv = n + 6 (v, a, tau) entries");
  }
#if SPATIAL_CHECK_SIZES
  const long long expected = Config ? model.nq() : model.nv();
  if (static_cast<long long>(x.size()) != expected)
    floating_size_assertion_failed(function, argument, static_cast<long long>(x.size()), Config, expected,
                                   model.njoints());
#else
  (void)model, (void)x, (void)function, (void)argument;
#endif
}
template <class S, class T, class Q>
inline void check_q(const FloatingModel<S, T>& model, const Eigen::MatrixBase<Q>& q, const char* function,
                    const char* argument = "q") {
  check_floating_size<true>(model, q, function, argument);
}
template <class S, class T, class V>
inline void check_v(const FloatingModel<S, T>& model, const Eigen::MatrixBase<V>& v, const char* function,
                    const char* argument) {
  check_floating_size<false>(model, v, function, argument);
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------------------------
// The free-flyer's blocks of q, v and τ
// ---------------------------------------------------------------------------------------------------------------

/// The root's velocity (or acceleration) as a `Motion` (angular first) from the first six entries of v (linear first).
template <class V>
Motion<typename V::Scalar> root_motion(const Eigen::MatrixBase<V>& v) {
  using S = typename V::Scalar;
  return Motion<S>(Vector3<S>(v[3], v[4], v[5]), Vector3<S>(v[0], v[1], v[2]));
}
/// The root's wrench as a `Force` (moment first) from the first six entries of τ (force first).
template <class V>
Force<typename V::Scalar> root_wrench(const Eigen::MatrixBase<V>& tau) {
  using S = typename V::Scalar;
  return Force<S>(Vector3<S>(tau[3], tau[4], tau[5]), Vector3<S>(tau[0], tau[1], tau[2]));
}
namespace detail {
/// The quaternion stored at q[k … k+3] in Eigen's (x, y, z, w) coefficient order (a free-flyer's at k = 3, a
/// spherical joint's at its first entry, general.hpp).
template <class S, class Q>
Eigen::Quaternion<S> quaternion_at(const Eigen::MatrixBase<Q>& q, int k) {
  return Eigen::Quaternion<S>(S(q[k + 3]), S(q[k]), S(q[k + 1]), S(q[k + 2]));
}
}  // namespace detail

/// The root's orientation (root axes → world axes) from q.
template <class Q>
Eigen::Quaternion<typename Q::Scalar> root_quaternion(const Eigen::MatrixBase<Q>& q) {
  return detail::quaternion_at<typename Q::Scalar>(q, 3);
}

namespace detail {
/// A force (angular first) as a linear-first 6-vector, the free-flyer's order (`root_wrench`'s inverse). By
/// fixed-size halves: a comma initializer's blocks have run-time sizes (a generic Eigen loop: H⁻¹ on hoap3_floating
/// took 12.8 % more instructions under clang with it, and g++ 12 warned -Warray-bounds).
template <class S>
SPATIAL_INLINE Vector6<S> linear_first(const Force<S>& f) {
  Vector6<S> out;
  out.template head<3>() = f.f;
  out.template tail<3>() = f.n;
  return out;
}
/// The joints' block of a floating-base vector (q: offset 7, v and τ: offset 6); fixed-size for compile-time trees.
template <int NJ, class Vec>
auto joint_block(Eigen::MatrixBase<Vec>& x, int offset, int n) {
  if constexpr (NJ != Eigen::Dynamic) {
    (void)n;
    return x.template segment<NJ>(offset);
  } else {
    return x.segment(offset, n);
  }
}
template <int NJ, class Vec>
auto joint_block(const Eigen::MatrixBase<Vec>& x, int offset, int n) {
  if constexpr (NJ != Eigen::Dynamic) {
    (void)n;
    return x.template segment<NJ>(offset);
  } else {
    return x.segment(offset, n);
  }
}

/// ⁰X_w from q: E = Rᵀ (R = the quaternion's rotation, root → world), r = the root origin in the world.
template <class S, class Q>
Transform<S> root_transform(const Eigen::MatrixBase<Q>& q) {
  const Eigen::Quaternion<S> rot = quaternion_at<S>(q, 3);
  Transform<S> X;
  X.E = rot.toRotationMatrix().transpose();
  X.r = Vector3<S>(S(q[0]), S(q[1]), S(q[2]));
  return X;
}

/// External forces of a floating model (n + 1 entries: [0] the root, [i + 1] body i) as the tree's per-body
/// container (body i ↦ entry i + 1).
template <class Ext>
struct TreeForces {
  const Ext& ext;
  decltype(auto) operator[](std::size_t k) const { return ext[k + 1]; }
};
/// The same, turned from world into root coordinates (for the tree's `ForceFrame::Base`, which is root coordinates).
template <class S, class Ext>
struct TreeForcesFromWorld {
  const Ext& ext;
  Transform<S> X0;
  Force<S> operator[](std::size_t k) const { return X0.apply_force(ext[k + 1]); }
};

/// True for the built-in floating-point types. Other scalars (automatic-differentiation types: dual numbers, Eigen's
/// AutoDiffScalar) take small-angle branches that are smooth in θ² — no √θ², whose derivative at θ = 0 is 0/0 — and
/// carry one more Taylor term, so that derivatives too stay accurate near θ = 0; float and double keep their code.
template <class S>
inline constexpr bool is_builtin_float_v = std::is_floating_point_v<S>;

/// Small-angle-safe coefficients of the SO(3)/SE(3) exponential: with θ = |ω|,
/// a = sin θ / θ, b = (1 − cos θ)/θ², c = (θ − sin θ)/θ³ (Taylor series below θ² < 1e-6 · 60; for scalars other
/// than the built-in floating-point types to one more term, whose derivative in θ² is then accurate to ~1e-16).
template <class S>
void exp_coefficients(S th2, S& a, S& b, S& c) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (th2 < S(1e-4)) {
    if constexpr (is_builtin_float_v<S>) {
      a = S(1) - th2 / S(6) * (S(1) - th2 / S(20));
      b = S(0.5) - th2 / S(24) * (S(1) - th2 / S(30));
      c = S(1) / S(6) - th2 / S(120) * (S(1) - th2 / S(42));
    } else {
      a = S(1) - th2 / S(6) * (S(1) - th2 / S(20) * (S(1) - th2 / S(42)));
      b = S(0.5) - th2 / S(24) * (S(1) - th2 / S(30) * (S(1) - th2 / S(56)));
      c = S(1) / S(6) - th2 / S(120) * (S(1) - th2 / S(42) * (S(1) - th2 / S(72)));
    }
  } else {
    const S th = sqrt(th2);
    const S s = sin(th), co = cos(th);
    a = s / th;
    b = (S(1) - co) / th2;
    c = (th - s) / (th2 * th);
  }
}

/// exp(ω̂) as a unit quaternion: (cos θ/2, sin(θ/2)/θ · ω) with θ = |ω|, sin(θ/2)/θ = a(θ/2) / 2.
template <class S>
Eigen::Quaternion<S> quaternion_exp(const Vector3<S>& w) {
  S ah, bh, ch;
  exp_coefficients(w.squaredNorm() / S(4), ah, bh, ch);
  using std::cos;
  using std::sqrt;
  // cos(θ/2); for AD scalars as 1 − (θ/2)² b(θ/2), smooth in θ² (cos √θ² has no derivative at θ = 0).
  S ch2;
  if constexpr (is_builtin_float_v<S>) ch2 = cos(sqrt(w.squaredNorm()) / S(2));
  else ch2 = S(1) - w.squaredNorm() / S(4) * bh;
  return Eigen::Quaternion<S>(ch2, ah / S(2) * w[0], ah / S(2) * w[1], ah / S(2) * w[2]);
}

/// The rotation vector ω (in r0's axes) with r0 exp(ω̂) = r1, the shorter of the two quaternion paths; r0 and r1
/// are normalised first.
template <class S>
Vector3<S> quaternion_log_between(const Eigen::Quaternion<S>& q0, const Eigen::Quaternion<S>& q1) {
  using std::atan2;
  const Eigen::Quaternion<S> r0 = q0.normalized();
  const Eigen::Quaternion<S> r1 = q1.normalized();
  Eigen::Quaternion<S> d = r0.conjugate() * r1;
  if (d.w() < S(0)) d.coeffs() = -d.coeffs();
  const Vector3<S> xyz = d.vec();
  // ω = θ · axis with θ = 2 atan2(|xyz|, w): the factor θ / |xyz|, by its series for small angles. For AD scalars
  // the series is taken in |xyz|² (|xyz| = √|xyz|² has no derivative at 0) with one more term.
  S k;
  if constexpr (is_builtin_float_v<S>) {
    const S sn = xyz.norm();
    k = sn < S(1e-6) ? S(2) / d.w() * (S(1) - sn * sn / (S(3) * d.w() * d.w())) : S(2) * atan2(sn, d.w()) / sn;
  } else {
    using std::sqrt;
    const S sn2 = xyz.squaredNorm();
    const S x2 = sn2 / (d.w() * d.w());  // tan²(θ/2); atan(x)/x = 1 − x²/3 + x⁴/5 − …
    k = sn2 < S(1e-12) ? S(2) / d.w() * (S(1) - x2 / S(3) * (S(1) - S(3) * x2 / S(5)))
                       : S(2) * atan2(sqrt(sn2), d.w()) / sqrt(sn2);
  }
  return k * xyz;
}

/// A free-flyer's q ⊕ v dt on its own entries (q, out: 7 = position, quaternion (x, y, z, w); v: 6 = body linear
/// and angular velocity): (R, p) ← (R exp(ω̂ dt), p + R V(ω dt) v dt), V the SE(3) left Jacobian; the quaternion
/// is renormalised. `out` may be `q`.
template <class S, class Q, class V, class Out>
void free_flyer_integrate(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, S dt,
                          const Eigen::MatrixBase<Out>& out_) {
  auto& out = const_cast<Eigen::MatrixBase<Out>&>(out_);
  const Vector3<S> w = Vector3<S>(S(v[3]), S(v[4]), S(v[5])) * dt;
  const Vector3<S> u = Vector3<S>(S(v[0]), S(v[1]), S(v[2])) * dt;
  S a, b, c;
  exp_coefficients(w.squaredNorm(), a, b, c);
  const Vector3<S> wxu = w.cross(u);
  const Vector3<S> dp = u + b * wxu + c * w.cross(wxu);  // V(ω) u
  const Eigen::Quaternion<S> dq = quaternion_exp(w);
  const Eigen::Quaternion<S> q0 = quaternion_at<S>(q, 3);
  const Vector3<S> p0 = Vector3<S>(S(q[0]), S(q[1]), S(q[2]));
  const Vector3<S> p1 = p0 + q0 * dp;
  Eigen::Quaternion<S> q1 = q0 * dq;
  q1.normalize();
  out[0] = p1[0], out[1] = p1[1], out[2] = p1[2];
  out[3] = q1.x(), out[4] = q1.y(), out[5] = q1.z(), out[6] = q1.w();
}

/// A free-flyer's q₁ ⊖ q₀ on its own entries (7, 7 → 6): the logarithm of the relative pose, in q₀'s body
/// coordinates (linear first).
template <class S, class Q0, class Q1, class Out>
void free_flyer_difference(const Eigen::MatrixBase<Q0>& q0, const Eigen::MatrixBase<Q1>& q1,
                           const Eigen::MatrixBase<Out>& out_) {
  auto& out = const_cast<Eigen::MatrixBase<Out>&>(out_);
  const Eigen::Quaternion<S> r0 = quaternion_at<S>(q0, 3);
  const Eigen::Quaternion<S> r1 = quaternion_at<S>(q1, 3);
  const Vector3<S> w = quaternion_log_between(r0, r1);
  const Vector3<S> dp = r0.normalized().conjugate() * Vector3<S>(S(q1[0] - q0[0]), S(q1[1] - q0[1]), S(q1[2] - q0[2]));
  // u = V(ω)⁻¹ dp, V⁻¹ = 1 − ½ ω̂ + e ω̂², e = (1 − θ sin θ / (2 (1 − cos θ))) / θ² (series: 1/12 + θ²/720).
  const S th2 = w.squaredNorm();
  S e;
  if (th2 < S(1e-4)) {
    if constexpr (is_builtin_float_v<S>) e = S(1) / S(12) + th2 / S(720);
    else e = S(1) / S(12) + th2 / S(720) * (S(1) + th2 / S(42));  // + θ⁴/30240
  } else {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const S th = sqrt(th2);
    e = (S(1) - th * sin(th) / (S(2) * (S(1) - cos(th)))) / th2;
  }
  const Vector3<S> wxp = w.cross(dp);
  const Vector3<S> u = dp - wxp / S(2) + e * w.cross(wxp);
  out[0] = u[0], out[1] = u[1], out[2] = u[2];
  out[3] = w[0], out[4] = w[1], out[5] = w[2];
}

/// A rotation drawn uniformly (Shoemake's method) as quaternion coefficients (x, y, z, w) written to out[0 … 3].
template <class S, class Out, class Rng>
void random_unit_quaternion(Rng& rng, Out&& out) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const S u1 = S(unit(rng)), u2 = S(unit(rng)), u3 = S(unit(rng));
  const S two_pi = S(2) * S(EIGEN_PI);
  const S a = sqrt(S(1) - u1), b = sqrt(u1);
  out[0] = a * sin(two_pi * u2);
  out[1] = a * cos(two_pi * u2);
  out[2] = b * sin(two_pi * u3);
  out[3] = b * cos(two_pi * u3);
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------------------------
// The configuration space (a Lie group for the free-flyer, a vector space for the joints)
// ---------------------------------------------------------------------------------------------------------------

/// q ⊕ v dt: the free-flyer moves by the exponential of the body twist v dt, (R, p) ← (R exp(ω̂ dt),
/// p + R V(ω dt) v dt) with V the SE(3) left Jacobian; the quaternion is renormalised; the joints move by q̇ dt.
/// Writes `out` (nq), which may be `q` itself. No allocation.
template <class S, class T, class Q, class V, class Out>
void integrate(const FloatingModel<S, T>& model, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, S dt,
               const Eigen::MatrixBase<Out>& out_) {
  detail::check_q(model, q, "integrate");
  detail::check_v(model, v, "integrate", "v");
  detail::check_q(model, out_, "integrate", "out");
  auto& out = const_cast<Eigen::MatrixBase<Out>&>(out_);
  const int n = model.njoints();
  for (int i = 0; i < n; ++i) out[7 + i] = q[7 + i] + v[6 + i] * dt;
  detail::free_flyer_integrate<S>(q.template head<7>(), v.template head<6>(), dt, out.template head<7>());
}
/// q ⊕ v dt, returned.
template <class S, class T, class Q, class V>
typename FloatingModel<S, T>::ConfigVector integrate(const FloatingModel<S, T>& model, const Eigen::MatrixBase<Q>& q,
                                                     const Eigen::MatrixBase<V>& v, S dt = S(1)) {
  typename FloatingModel<S, T>::ConfigVector out(model.nq());
  integrate(model, q, v, dt, out);
  return out;
}

/// q₁ ⊖ q₀: the velocity v (nv) with q₀ ⊕ v = q₁ (the logarithm of the relative pose of the root, in q₀'s root
/// coordinates; the shorter of the two quaternion paths), joints q₁ − q₀. Writes `out`.
template <class S, class T, class Q0, class Q1, class Out>
void difference(const FloatingModel<S, T>& model, const Eigen::MatrixBase<Q0>& q0, const Eigen::MatrixBase<Q1>& q1,
                const Eigen::MatrixBase<Out>& out_) {
  detail::check_q(model, q0, "difference", "q0");
  detail::check_q(model, q1, "difference", "q1");
  detail::check_v(model, out_, "difference", "out");
  auto& out = const_cast<Eigen::MatrixBase<Out>&>(out_);
  const int n = model.njoints();
  detail::free_flyer_difference<S>(q0.template head<7>(), q1.template head<7>(), out.template head<6>());
  for (int i = 0; i < n; ++i) out[6 + i] = q1[7 + i] - q0[7 + i];
}
/// q₁ ⊖ q₀, returned.
template <class S, class T, class Q0, class Q1>
typename FloatingModel<S, T>::TangentVector difference(const FloatingModel<S, T>& model,
                                                       const Eigen::MatrixBase<Q0>& q0,
                                                       const Eigen::MatrixBase<Q1>& q1) {
  typename FloatingModel<S, T>::TangentVector out(model.nv());
  difference(model, q0, q1, out);
  return out;
}

/// Scales the quaternion of q to unit length (in place).
template <class S, class T, class Q>
void normalize(const FloatingModel<S, T>&, Eigen::MatrixBase<Q>& q) {
  q.template segment<4>(3).normalize();
}
/// True when q's quaternion has unit length to `tol`.
template <class S, class T, class Q>
bool is_normalized(const FloatingModel<S, T>&, const Eigen::MatrixBase<Q>& q, S tol = S(1e-10)) {
  using std::abs;
  return abs(q.template segment<4>(3).norm() - S(1)) <= tol;
}
/// The neutral configuration: root at the world origin with the identity orientation, every joint at 0.
template <class S, class T>
typename FloatingModel<S, T>::ConfigVector neutral(const FloatingModel<S, T>& model) {
  typename FloatingModel<S, T>::ConfigVector q = FloatingModel<S, T>::ConfigVector::Zero(model.nq());
  q[6] = S(1);
  return q;
}
/// A random configuration: root position uniform in the box [pmin, pmax], orientation uniform over the rotations
/// (Shoemake's method), joint i uniform in [lower[i], upper[i]] (an infinite bound is replaced by ∓π).
template <class S, class T, class L, class U, class Rng>
typename FloatingModel<S, T>::ConfigVector random_configuration(const FloatingModel<S, T>& model,
                                                                const Eigen::MatrixBase<L>& lower,
                                                                const Eigen::MatrixBase<U>& upper, Rng& rng,
                                                                const Vector3<S>& pmin = Vector3<S>::Constant(-1),
                                                                const Vector3<S>& pmax = Vector3<S>::Constant(1)) {
  using std::isfinite;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  typename FloatingModel<S, T>::ConfigVector q(model.nq());
  for (int k = 0; k < 3; ++k) q[k] = pmin[k] + S(unit(rng)) * (pmax[k] - pmin[k]);
  detail::random_unit_quaternion<S>(rng, q.template segment<4>(3));
  for (int i = 0; i < model.njoints(); ++i) {
    const S lo = isfinite(double(lower[i])) ? S(lower[i]) : -S(EIGEN_PI);
    const S hi = isfinite(double(upper[i])) ? S(upper[i]) : S(EIGEN_PI);
    q[7 + i] = lo + S(unit(rng)) * (hi - lo);
  }
  return q;
}

// ---------------------------------------------------------------------------------------------------------------
// Algorithms
// ---------------------------------------------------------------------------------------------------------------

namespace detail {
/// RNEA on a floating base (RBDA §9.3 with the root's acceleration given): the tree's recursion from the root's
/// v₀ and a₀ − a_g, then f₀ = I₀ (a₀ − a_g) + v₀ ×* I₀ v₀ − f₀ˣ + Σ_children ʲX₀ᵀ fⱼ. Writes τ (nv) into `tau`.
template <unsigned Terms, bool Simd = true, class S, class T, class Q, class V, class A, class Ext, class Out>
void rnea_floating(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                   const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, const Ext& fext, ForceFrame frame,
                   Eigen::MatrixBase<Out>& tau) {
  constexpr bool G = (Terms & kGravity) != 0;
  constexpr bool Vel = (Terms & kVelocity) != 0;
  constexpr bool Acc = (Terms & kAcceleration) != 0;
  constexpr bool X = has_external_v<Ext>;
  constexpr int NJ = FloatingModel<S, T>::NJ;
  const int n = model.njoints();
  const Inertia<S>& I0 = model.root_inertia();
  data.X0 = root_transform<S>(q);
  Motion<S> v0 = Motion<S>::Zero(), a0 = Motion<S>::Zero();
  if constexpr (Vel) v0 = root_motion(v).template cast<S>();
  if constexpr (Acc) a0 = root_motion(a).template cast<S>();
  if constexpr (G) a0.v -= data.X0.E * model.gravity();
  data.v0 = v0;
  data.a0 = a0;
  data.f0 = I0 * a0;
  if constexpr (Vel) data.f0 += cross(v0, I0 * v0);
  MovingRoot<S> root;
  root.v = v0;
  root.a = a0;
  root.f = &data.f0;
  const auto qj = joint_block<NJ>(q, 7, n);
  const auto vj = joint_block<NJ>(v, 6, n);
  const auto aj = joint_block<NJ>(a, 6, n);
  auto tj = joint_block<NJ>(tau, 6, n);
  if constexpr (X) {
    if (frame == ForceFrame::Base) {
      data.f0 -= data.X0.apply_force(fext[0]);
      const TreeForcesFromWorld<S, Ext> tf{fext, data.X0};
      rnea_impl<Terms, Simd>(model.tree(), data.tree, qj, vj, aj, tf, ForceFrame::Base, tj, root);
    } else {
      data.f0 -= fext[0];
      const TreeForces<Ext> tf{fext};
      rnea_impl<Terms, Simd>(model.tree(), data.tree, qj, vj, aj, tf, ForceFrame::Body, tj, root);
    }
  } else {
    (void)fext, (void)frame;
    rnea_impl<Terms, Simd>(model.tree(), data.tree, qj, vj, aj, fext, ForceFrame::Body, tj, root);
  }
  tau.template head<3>() = data.f0.f;
  tau.template segment<3>(3) = data.f0.n;
}

/// The floating-base rows and columns of H after the tree's CRBA (RBDA §9.4): Iᶜ₀ = I₀ + Σ_children ʲX₀ᵀ Iᶜⱼ ʲX₀,
/// H₀₀ = Iᶜ₀ (linear first: [m1 h̃ᵀ; h̃ Ī]), H₀ⱼ = Fⱼ in root coordinates (Fⱼ = Iᶜⱼ Sⱼ), and the tree's H.
template <class S, class T>
void crba_floating_finish(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Inertia<S>& tree);

/// The floating H from the tree's CRBA: `crba_impl` hands the joints' entries and every body's Fⱼ⁰ (the free-flyer's
/// columns) here, in place of the tree's own `data.tree.H` (not written).
template <class S, class T>
struct FreeFlyerColumns {
  static constexpr bool active = true;
  static constexpr bool entries = true;
  static constexpr bool sums_roots = true;
  FloatingData<S, T>& data;
  /// The tree's inertia in root coordinates (its roots' composite inertias moved there and summed): Iᶜ₀ without the
  /// root body, which `crba_floating_finish` adds.
  Inertia<S>& tree;
  SPATIAL_INLINE void roots(const Inertia<S>& sum) const { tree = sum; }
  /// Hᵢⱼ of the tree (j = i or an ancestor of i) into the joints' block, both triangles.
  SPATIAL_INLINE void entry(int i, int j, S hij) const {
    data.H(6 + i, 6 + j) = hij;
    data.H(6 + j, 6 + i) = hij;
  }
  SPATIAL_INLINE void operator()(int i, const Force<S>& F0) const {
    auto& H = data.H;
    H(0, 6 + i) = H(6 + i, 0) = F0.f[0];
    H(1, 6 + i) = H(6 + i, 1) = F0.f[1];
    H(2, 6 + i) = H(6 + i, 2) = F0.f[2];
    H(3, 6 + i) = H(6 + i, 3) = F0.n[0];
    H(4, 6 + i) = H(6 + i, 4) = F0.n[1];
    H(5, 6 + i) = H(6 + i, 5) = F0.n[2];
  }
};

/// Whether S's comparisons give a bool (double, float, automatic differentiation), rather than one per SIMD lane
/// (batch.hpp's lanes), which Eigen's decompositions cannot branch on.
template <class S>
inline constexpr bool has_bool_comparisons_v =
    std::is_same_v<decltype(std::declval<const S&>() < std::declval<const S&>()), bool>;

/// x = A⁻¹ b for a symmetric positive definite 6 × 6 A, by A = L D Lᵀ (L unit lower triangular) without pivoting:
/// the same operations whatever the values, so that it runs on SIMD lanes (each lane its own A and b).
template <class S>
Vector6<S> spd_solve6(const Matrix6<S>& A, const Vector6<S>& b) {
  Matrix6<S> L;
  Vector6<S> d, x;
  for (int j = 0; j < 6; ++j) {
    S dj = A(j, j);
    for (int k = 0; k < j; ++k) dj -= L(j, k) * L(j, k) * d[k];
    d[j] = dj;
    const S inv = S(1) / dj;
    for (int i = j + 1; i < 6; ++i) {
      S lij = A(i, j);
      for (int k = 0; k < j; ++k) lij -= L(i, k) * L(j, k) * d[k];
      L(i, j) = lij * inv;
    }
  }
  for (int i = 0; i < 6; ++i) {  // L y = b
    S yi = b[i];
    for (int k = 0; k < i; ++k) yi -= L(i, k) * x[k];
    x[i] = yi;
  }
  for (int i = 0; i < 6; ++i) x[i] /= d[i];
  for (int i = 5; i >= 0; --i) {  // Lᵀ x = D⁻¹ y
    S xi = x[i];
    for (int k = i + 1; k < 6; ++k) xi -= L(k, i) * x[k];
    x[i] = xi;
  }
  return x;
}

/// ABA's root step (RBDA §9.5): a₀′ = Iᴬ₀⁻¹ (τ₀ − pᴬ₀) by a 6 × 6 Cholesky factorisation (Eigen's LLT; on SIMD
/// lanes `spd_solve6`), kept in `data.a0`.
template <class S, class T>
struct RootSolve {
  FloatingData<S, T>* data = nullptr;
  Force<S> tau0 = Force<S>::Zero();
  Motion<S> operator()() const {
    const Force<S> rhs = tau0 - data->pA0;
    Vector6<S> a;
    if constexpr (has_bool_comparisons_v<S>) a = data->IA0.matrix().llt().solve(rhs.vector());
    else a = spd_solve6<S>(data->IA0.matrix(), rhs.vector());
    data->a0 = Motion<S>(a.template head<3>(), a.template tail<3>());
    return data->a0;
  }
};

/// The tree's CRBA with the free-flyer's columns (see `crba_floating_finish`).
template <bool Simd = true, class S, class T>
void crba_floating(const FloatingModel<S, T>& model, FloatingData<S, T>& data) {
  Inertia<S> tree;
  crba_impl<Simd>(model.tree(), data.tree, FreeFlyerColumns<S, T>{data, tree});
  crba_floating_finish(model, data, tree);
}

template <class S, class T>
void crba_floating_finish(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Inertia<S>& tree) {
  data.Ic0 = tree + model.root_inertia();
  const Inertia<S>& Ic = data.Ic0;
  const Matrix3<S> hx = skew(Ic.h);
  data.H.template block<3, 3>(0, 0) = Ic.m * Matrix3<S>::Identity();
  data.H.template block<3, 3>(0, 3) = hx.transpose();
  data.H.template block<3, 3>(3, 0) = hx;
  data.H.template block<3, 3>(3, 3) = Ic.I;
}

}  // namespace detail

/// Inverse dynamics of a floating-base tree: τ = H(q) v̇ + C(q, v) − Σ Jᵢᵀ fᵢˣ (nv entries; the first six are the
/// wrench the root needs, force first, in root coordinates — zero when the motion is possible without pushing on
/// the root). `fext` (optional): n + 1 forces, [0] on the root, [i + 1] on body i, in body coordinates
/// (`ForceFrame::Body`) or world coordinates (`ForceFrame::Base`, moment about the world origin). Per-body results
/// are in `data.tree` (root coordinates for "base"); returns `data.tau`.
template <class S, class T, class Q, class V, class A, class Ext = NoExternalForces>
const typename FloatingData<S, T>::VectorV& rnea(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                                 const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                                 const Eigen::MatrixBase<A>& a, const Ext& fext = Ext(),
                                                 ForceFrame frame = ForceFrame::Body) {
  detail::check_q(model, q, "rnea");
  detail::check_v(model, v, "rnea", "v");
  detail::check_v(model, a, "rnea", "a");
  using namespace detail;
  rnea_floating<kGravity | kVelocity | kAcceleration>(model, data, q, v, a, fext, frame, data.tau);
  return data.tau;
}

/// Bias forces C(q, v) = RNEA(q, v, 0) of a floating-base tree (nv entries). Returns `data.tau`.
template <class S, class T, class Q, class V>
const typename FloatingData<S, T>::VectorV& bias_forces(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                                        const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v) {
  detail::check_q(model, q, "bias_forces");
  detail::check_v(model, v, "bias_forces", "v");
  using namespace detail;
  rnea_floating<kGravity | kVelocity>(model, data, q, v, v, NoExternalForces{}, ForceFrame::Body, data.tau);
  return data.tau;
}

/// Gravity forces G(q) = RNEA(q, 0, 0) of a floating-base tree (nv entries; the first six: the root's weight
/// wrench, which depends on the root's orientation). Returns `data.tau`.
template <class S, class T, class Q>
const typename FloatingData<S, T>::VectorV& gravity_torques(const FloatingModel<S, T>& model,
                                                            FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_q(model, q, "gravity_torques");
  using namespace detail;
  rnea_floating<kGravity>(model, data, q, data.tmp, data.tmp, NoExternalForces{}, ForceFrame::Body, data.tau);
  return data.tau;
}

/// Joint-space inertia H(q) (nv × nv) of a floating-base tree by CRBA (RBDA §9.4). H does not depend on the root's
/// pose. Entries coupling two joints on different branches are structurally zero. Returns `data.H`.
template <class S, class T, class Q>
const typename FloatingData<S, T>::MatrixV& crba(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                                 const Eigen::MatrixBase<Q>& q) {
  detail::check_q(model, q, "crba");
  const auto qj = detail::joint_block<FloatingModel<S, T>::NJ>(q, 7, model.njoints());
  detail::crba_inputs(model.tree(), data.tree, qj);
  detail::crba_floating(model, data);
  return data.H;
}

/// H = Lᵀ D L along the tree with the free-flyer's six coordinates as a chain above the roots (RBDA §6.5, §9.4):
/// each joint's row has its tree ancestors and the six root coordinates, and the root's 6 × 6 block is dense.
/// Joints are eliminated leaves first, as in `ltdl` (unrolled over the ancestors on compile-time trees), then the
/// root's block. Reads `data.H`, writes `data.L`.
template <class S, class T>
void ltdl(const FloatingModel<S, T>& model, FloatingData<S, T>& data) {
  const auto& tree = model.tree();
  auto& L = data.L;
  const auto& H = data.H;
  for (int k = 0; k < 6; ++k)
    for (int c = 0; c <= k; ++c) L(k, c) = H(k, c);
  for_each_body(tree, [&](auto K) {
    const int k = 6 + int(K);
    L(k, k) = H(k, k);
    walk_up(tree, K, [&](auto, auto P) { L(k, 6 + int(P)) = H(k, 6 + int(P)); });
    for (int c = 0; c < 6; ++c) L(k, c) = H(k, c);
  });
  for_each_body_reverse(tree, [&](auto K) {
    const int k = 6 + int(K);
    const S inv_d = S(1) / L(k, k);
    walk_up(tree, K, [&](auto, auto I) {
      const int i = 6 + int(I);
      const S lki = L(k, i);
      const S a = lki * inv_d;
      L(i, i) -= a * lki;
      if constexpr (FloatingModel<S, T>::is_static && FloatingModel<S, T>::NJ <= kMaxUnrolledLtdl) {
        walk_up(tree, I, [&](auto, auto J) { L(i, 6 + int(J)) -= a * L(k, 6 + int(J)); });
      } else {
        walk_up(tree, int(I), [&](int, int j) { L(i, 6 + j) -= a * L(k, 6 + j); });
      }
      for (int c = 0; c < 6; ++c) L(i, c) -= a * L(k, c);
      L(k, i) = a;
    });
    for (int b = 5; b >= 0; --b) {
      const S lkb = L(k, b);
      const S a = lkb * inv_d;
      L(b, b) -= a * lkb;
      for (int c = 0; c < b; ++c) L(b, c) -= a * L(k, c);
      L(k, b) = a;
    }
  });
  for (int k = 5; k >= 0; --k) {
    const S inv_d = S(1) / L(k, k);
    for (int b = k - 1; b >= 0; --b) {
      const S lkb = L(k, b);
      const S a = lkb * inv_d;
      L(b, b) -= a * lkb;
      for (int c = 0; c < b; ++c) L(b, c) -= a * L(k, c);
      L(k, b) = a;
    }
  }
}

namespace detail {
/// The two halves of `ltdl_solve`: x ← L⁻ᵀ x (rows from the last), and x ← D⁻¹ x then x ← L⁻¹ x (rows from the
/// first); contact.hpp uses them apart.
template <class S, class T, class X>
void ltdl_solve_lt(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, Eigen::MatrixBase<X>& x) {
  const auto& tree = model.tree();
  const auto& L = data.L;
  for_each_body_reverse(tree, [&](auto I) {
    const int i = 6 + int(I);
    const S xi = x[i];
    walk_up(tree, I, [&](auto, auto J) { x[6 + int(J)] -= L(i, 6 + int(J)) * xi; });
    for (int c = 0; c < 6; ++c) x[c] -= L(i, c) * xi;
  });
  for (int i = 5; i >= 0; --i)
    for (int c = 0; c < i; ++c) x[c] -= L(i, c) * x[i];
}
template <class S, class T, class X>
void ltdl_solve_dl(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, Eigen::MatrixBase<X>& x) {
  const auto& tree = model.tree();
  const auto& L = data.L;
  for (int i = 0; i < model.nv(); ++i) x[i] /= L(i, i);
  for (int i = 0; i < 6; ++i)
    for (int c = 0; c < i; ++c) x[i] -= L(i, c) * x[c];
  for_each_body(tree, [&](auto I) {
    const int i = 6 + int(I);
    S xi = x[i];
    walk_up(tree, I, [&](auto, auto J) { xi -= L(i, 6 + int(J)) * x[6 + int(J)]; });
    for (int c = 0; c < 6; ++c) xi -= L(i, c) * x[c];
    x[i] = xi;
  });
}
}  // namespace detail

/// Solves H x = b in place with the factor from `ltdl` (x holds b on entry).
template <class S, class T, class X>
void ltdl_solve(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, Eigen::MatrixBase<X>& x) {
  detail::check_v(model, x, "ltdl_solve", "x");
  detail::ltdl_solve_lt(model, data, x);
  detail::ltdl_solve_dl(model, data, x);
}

/// Forward dynamics of a floating-base tree by CRBA and the tree-sparse LTDL: v̇ = H⁻¹ (τ − C(q, v)) (nv entries;
/// τ's first six: a wrench applied to the root, usually zero). Returns `data.qdd`.
template <class S, class T, class Q, class V, class Tau>
const typename FloatingData<S, T>::VectorV& forward_dynamics_crba(const FloatingModel<S, T>& model,
                                                                  FloatingData<S, T>& data,
                                                                  const Eigen::MatrixBase<Q>& q,
                                                                  const Eigen::MatrixBase<V>& v,
                                                                  const Eigen::MatrixBase<Tau>& tau) {
  detail::check_q(model, q, "forward_dynamics_crba");
  detail::check_v(model, v, "forward_dynamics_crba", "v");
  detail::check_v(model, tau, "forward_dynamics_crba", "tau");
  using namespace detail;
  rnea_floating<kGravity | kVelocity>(model, data, q, v, v, NoExternalForces{}, ForceFrame::Body, data.tmp);
  data.tmp = tau - data.tmp;
  crba_floating(model, data);  // the transforms of the bias pass (the scalar path reads its X_up)
  ltdl(model, data);
  data.qdd = data.tmp;
  ltdl_solve(model, data, data.qdd);
  return data.qdd;
}

namespace detail {
template <bool Simd, class S, class T, class Q, class V, class Tau, class Ext>
void aba_floating(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                  const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<Tau>& tau, const Ext& fext,
                  ForceFrame frame);
}  // namespace detail

/// Forward dynamics of a floating-base tree by the articulated-body algorithm (RBDA §9.5, Table 9.6 with the
/// root's wrench τ₀): passes 1–2 over the tree with the root's velocity, the root's articulated inertia
/// Iᴬ₀ = I₀ + Σ and bias pᴬ₀ = v₀ ×* I₀ v₀ − f₀ˣ + Σ, then a₀′ = Iᴬ₀⁻¹ (τ₀ − pᴬ₀) (a 6 × 6 Cholesky solve), pass 3
/// from a₀′, and v̇₀ = a₀′ + a_g. `fext` as for `rnea`. Returns `data.qdd` (nv).
template <class S, class T, class Q, class V, class Tau, class Ext = NoExternalForces>
const typename FloatingData<S, T>::VectorV& aba(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                                const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                                const Eigen::MatrixBase<Tau>& tau, const Ext& fext = Ext(),
                                                ForceFrame frame = ForceFrame::Body) {
  detail::check_q(model, q, "aba");
  detail::check_v(model, v, "aba", "v");
  detail::check_v(model, tau, "aba", "tau");
  detail::aba_floating<true>(model, data, q, v, tau, fext, frame);
  return data.qdd;
}

namespace detail {
/// `aba` on a floating base; `Simd` = false forces the scalar tree passes (tests compare the two).
template <bool Simd, class S, class T, class Q, class V, class Tau, class Ext>
void aba_floating(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                  const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<Tau>& tau, const Ext& fext,
                  ForceFrame frame) {
  constexpr int NJ = FloatingModel<S, T>::NJ;
  constexpr bool X = has_external_v<Ext>;
  const int n = model.njoints();
  const Inertia<S>& I0 = model.root_inertia();
  data.X0 = root_transform<S>(q);
  data.v0 = root_motion(v).template cast<S>();
  data.IA0 = ArticulatedInertia<S>(I0);
  data.pA0 = cross(data.v0, I0 * data.v0);
  MovingRoot<S, RootSolve<S, T>> root;
  root.v = data.v0;
  root.IA = &data.IA0;
  root.pA = &data.pA0;
  root.solve = RootSolve<S, T>{&data, root_wrench(tau).template cast<S>()};
  const auto qj = joint_block<NJ>(q, 7, n);
  const auto vj = joint_block<NJ>(v, 6, n);
  const auto tj = joint_block<NJ>(tau, 6, n);
  if constexpr (X) {
    if (frame == ForceFrame::Base) {
      data.pA0 -= data.X0.apply_force(fext[0]);
      const TreeForcesFromWorld<S, Ext> tf{fext, data.X0};
      aba_impl<true, true, Simd>(model.tree(), data.tree, qj, vj, tj, tf, ForceFrame::Base, root);
    } else {
      data.pA0 -= fext[0];
      const TreeForces<Ext> tf{fext};
      aba_impl<true, true, Simd>(model.tree(), data.tree, qj, vj, tj, tf, ForceFrame::Body, root);
    }
  } else {
    (void)frame;
    aba_impl<true, true, Simd>(model.tree(), data.tree, qj, vj, tj, fext, ForceFrame::Body, root);
  }
  const Vector3<S> g0 = data.X0.E * model.gravity();
  data.qdd.template head<3>() = data.a0.v + g0;
  data.qdd.template segment<3>(3) = data.a0.w;
  if constexpr (NJ != Eigen::Dynamic) data.qdd.template segment<NJ>(6) = data.tree.qdd;
  else data.qdd.segment(6, n) = data.tree.qdd;
}
}  // namespace detail

/// Forward kinematics of a floating-base tree: `data.X0` = ⁰X_w and the tree's `data.tree.X_up`, `X_base` (root
/// → body coordinates). World transforms: `world_transform(data, i)`.
template <class S, class T, class Q>
void forward_kinematics(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_q(model, q, "forward_kinematics");
  data.X0 = detail::root_transform<S>(q);
  forward_kinematics(model.tree(), data.tree, detail::joint_block<FloatingModel<S, T>::NJ>(q, 7, model.njoints()));
}

/// ⁱX_w (world → body i coordinates; i = −1: the root) after `forward_kinematics`.
template <class S, class T>
Transform<S> world_transform(const FloatingData<S, T>& data, int i) {
  return i >= 0 ? data.tree.X_base[static_cast<std::size_t>(i)] * data.X0 : data.X0;
}
/// Pose of body i (−1: the root) in the world after `forward_kinematics`: rotation (body axes in world
/// coordinates) and position of the body origin.
template <class S, class T>
Eigen::Transform<S, 3, Eigen::Isometry> body_pose(const FloatingModel<S, T>&, const FloatingData<S, T>& data, int i) {
  const Transform<S> X = world_transform(data, i);
  Eigen::Transform<S, 3, Eigen::Isometry> pose = Eigen::Transform<S, 3, Eigen::Isometry>::Identity();
  pose.linear() = X.E.transpose();
  pose.translation() = X.r;
  return pose;
}
/// Pose in the world of a fixed frame (`model.tree().frames()[k]`) after `forward_kinematics`.
template <class S, class T>
Eigen::Transform<S, 3, Eigen::Isometry> frame_pose(const FloatingModel<S, T>& model, const FloatingData<S, T>& data,
                                                   int k) {
  const FixedFrame<S>& fr = model.tree().frames()[static_cast<std::size_t>(k)];
  const Transform<S> X = fr.X * world_transform(data, fr.body);
  Eigen::Transform<S, 3, Eigen::Isometry> pose = Eigen::Transform<S, 3, Eigen::Isometry>::Identity();
  pose.linear() = X.E.transpose();
  pose.translation() = X.r;
  return pose;
}

/// Kinetic energy ½ v₀ · I₀ v₀ + ½ Σ vᵢ · Iᵢ vᵢ.
template <class S, class T, class Q, class V>
S kinetic_energy(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                 const Eigen::MatrixBase<V>& v) {
  detail::check_q(model, q, "kinetic_energy");
  detail::check_v(model, v, "kinetic_energy", "v");
  constexpr int NJ = FloatingModel<S, T>::NJ;
  const int n = model.njoints();
  data.X0 = detail::root_transform<S>(q);
  data.v0 = root_motion(v).template cast<S>();
  const auto qj = detail::joint_block<NJ>(q, 7, n);
  const auto vj = detail::joint_block<NJ>(v, 6, n);
  forward_kinematics(model.tree(), data.tree, qj);
  auto& td = data.tree;
  S e = dot(data.v0, model.root_inertia() * data.v0);
  for_each_body(model.tree(), [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.tree().parent(I);
    td.v[k] = td.X_up[k].apply(p >= 0 ? td.v[static_cast<std::size_t>(p)] : data.v0) +
              model.tree().joint(I).motion(S(vj[i]));
    e += dot(td.v[k], model.tree().inertia(i) * td.v[k]);
  });
  return e / S(2);
}

/// Σ mᵢ cᵢ over the root and every body, and the total mass, in world coordinates (after `forward_kinematics`).
template <class S, class T>
std::pair<Vector3<S>, S> first_moment_world(const FloatingModel<S, T>& model, const FloatingData<S, T>& data) {
  const Inertia<S>& I0 = model.root_inertia();
  Vector3<S> h = I0.m * data.X0.r + data.X0.E.transpose() * I0.h;
  S m = I0.m;
  for (int i = 0; i < model.njoints(); ++i) {
    const Transform<S> X = world_transform(data, i);
    const Inertia<S>& In = model.tree().inertia(i);
    h += In.m * X.r + X.E.transpose() * In.h;
    m += In.m;
  }
  return {h, m};
}

/// Potential energy −Σ mᵢ g · cᵢ (world coordinates, zero at the world origin).
template <class S, class T, class Q>
S potential_energy(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_q(model, q, "potential_energy");
  forward_kinematics(model, data, q);
  return -model.gravity().dot(first_moment_world(model, data).first);
}

/// Centre of mass of the whole robot (root and tree) in world coordinates.
template <class S, class T, class Q>
Vector3<S> center_of_mass(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_q(model, q, "center_of_mass");
  forward_kinematics(model, data, q);
  const auto hm = first_moment_world(model, data);
  return hm.first / hm.second;
}

namespace detail {
/// What generic code (ik.hpp, contact.hpp) needs to know about fixed- and floating-base models: their data type,
/// nv at compile time (NV, Eigen::Dynamic for run-time trees) and the matching matrix dimension (NM), where the
/// joints start in q and v, the sizes, the tree, and q ⊕ v.
template <class M>
struct ModelTraits;
template <class S, class T>
struct ModelTraits<Model<S, T>> {
  using DataType = Data<S, T>;
  static constexpr int NV = DataType::NB;
  static constexpr int NM = DataType::NM;
  static constexpr int qoff = 0;  ///< first joint in q
  static constexpr int voff = 0;  ///< first joint in v
  static int nq(const Model<S, T>& m) { return m.size(); }
  static int nv(const Model<S, T>& m) { return m.size(); }
  static const Model<S, T>& tree(const Model<S, T>& m) { return m; }
  template <class Q, class V, class Out>
  static void integrate(const Model<S, T>&, const Q& q, const V& v, Out& out) {
    out = q + v;
  }
};
template <class S, class T>
struct ModelTraits<FloatingModel<S, T>> {
  using DataType = FloatingData<S, T>;
  static constexpr int NV = DataType::NV;
  static constexpr int NM = DataType::NM;
  static constexpr int qoff = 7;
  static constexpr int voff = 6;
  static int nq(const FloatingModel<S, T>& m) { return m.nq(); }
  static int nv(const FloatingModel<S, T>& m) { return m.nv(); }
  static const Model<S, T>& tree(const FloatingModel<S, T>& m) { return m.tree(); }
  template <class Q, class V, class Out>
  static void integrate(const FloatingModel<S, T>& m, const Q& q, const V& v, Out& out) {
    spatial::integrate(m, q, v, S(1), out);
  }
};
}  // namespace detail

}  // namespace spatial

#pragma once
/// \file algorithms.hpp
/// The dynamics algorithms, written once for compile-time and run-time trees. Each is a free function
/// `algorithm(model, data, inputs…)`; it reads the immutable model, writes only into `data` and returns a reference
/// to its result inside `data`. None allocates, throws or calls a virtual function.
///
/// Frames: every per-body quantity is expressed in that body's coordinates (RBDA §4.1 "link coordinates"), with
/// the Plücker conventions of algebra.hpp; the base frame is body −1's.
///
/// Scenes that need only some terms (no velocity, no gravity, gravity alone, forces in base coordinates) call
/// `rnea<Dyn::…>`, `aba<Dyn::…>` and `forward_dynamics_crba<Dyn::…>` from options.hpp, which documents the
/// equations of each option; reduce.hpp locks joints and keeps only the branches a scene moves.

#include "spatial/algebra.hpp"
#include "spatial/joints.hpp"
#include "spatial/model.hpp"
#include "spatial/simd.hpp"
#include "spatial/sizes.hpp"
#include "spatial/sincos.hpp"

#include <array>
#include <type_traits>
#include <utility>

namespace spatial {

/// Frame in which external forces are given to `rnea` and `aba`.
enum class ForceFrame {
  Body,  ///< fext[i] in body i's coordinates (moment about body i's origin)
  Base,  ///< fext[i] in base coordinates (moment about the base origin)
};

namespace detail {
template <class F, int... I>
void for_each_forward(F& f, std::integer_sequence<int, I...>) {
  (f(std::integral_constant<int, I>{}), ...);
}
template <int N, class F, int... I>
void for_each_backward(F& f, std::integer_sequence<int, I...>) {
  (f(std::integral_constant<int, N - 1 - I>{}), ...);
}
}  // namespace detail

/// Calls f(i) for every body in order 0 … n−1 (parents before children). For a compile-time tree, i is a
/// `std::integral_constant<int, i>` and the loop is unrolled, so each body's joint code is specialised.
template <class S, class T, class F>
void for_each_body(const Model<S, T>& model, F&& f) {
  if constexpr (Model<S, T>::is_static) {
    (void)model;
    detail::for_each_forward(f, std::make_integer_sequence<int, Model<S, T>::NB>{});
  } else {
    for (int i = 0; i < model.size(); ++i) f(i);
  }
}
/// Calls f(i) for every body in order n−1 … 0 (children before parents).
template <class S, class T, class F>
void for_each_body_reverse(const Model<S, T>& model, F&& f) {
  if constexpr (Model<S, T>::is_static) {
    (void)model;
    detail::for_each_backward<Model<S, T>::NB>(f, std::make_integer_sequence<int, Model<S, T>::NB>{});
  } else {
    for (int i = model.size() - 1; i >= 0; --i) f(i);
  }
}

namespace detail {
template <class M, int J, class F>
SPATIAL_INLINE void walk_up_static(const M& model, std::integral_constant<int, J> j, F& f) {
  constexpr int P = M::tree_type::parent[J];
  if constexpr (P >= 0) {
    f(j, std::integral_constant<int, P>{});
    walk_up_static(model, std::integral_constant<int, P>{}, f);
  }
}
}  // namespace detail

/// Largest compile-time tree whose ancestor walks are unrolled at compile time (each step then knows its joint's
/// type); deeper trees walk up at run time, where each step switches on the joint type.
inline constexpr int kMaxUnrolledWalk = 64;
/// Largest compile-time tree whose LTDL factorisation is unrolled over pairs of ancestors.
inline constexpr int kMaxUnrolledLtdl = 32;

/// Calls f(j, λ(j)) for every step from body i up to the root: (i, λ(i)), (λ(i), λ(λ(i))), … For a compile-time
/// index of a compile-time tree both arguments are `std::integral_constant`s.
template <class S, class T, class I, class F>
SPATIAL_INLINE void walk_up(const Model<S, T>& model, I i, F&& f) {
  if constexpr (Model<S, T>::is_static && Model<S, T>::NB <= kMaxUnrolledWalk &&
                !std::is_same_v<I, int>) {
    detail::walk_up_static(model, i, f);
  } else {
    for (int j = i, p = model.parent(j); p >= 0; j = p, p = model.parent(p)) f(j, p);
  }
}

/// No external forces (the default of `rnea` and `aba`).
struct NoExternalForces {};

namespace detail {
/// No per-body output from `crba_impl` (see there).
struct NoForceSink {
  static constexpr bool active = false;
  static constexpr bool entries = true;
  static constexpr bool sums_roots = false;
  template <class F>
  void operator()(int, const F&) const {}
};
/// The root of a fixed-base tree: the base does not move, and the recursions start from v = 0 and a = −a_g.
struct FixedRoot {
  static constexpr bool floating = false;
};
/// The root of a floating-base tree (floating.hpp): the bodies whose parent is −1 hang from a moving root body
/// with velocity `v` and acceleration `a` (root coordinates; `a` includes the fictitious −a_g where gravity is on).
/// RNEA adds the forces transmitted to the root into `*f`; ABA adds the articulated inertias and bias forces that
/// the root's children pass to it into `*IA` and `*pA` (root coordinates).
///
/// ABA calls `solve()` between its passes 2 and 3: it returns the root's acceleration (minus gravity) from the
/// completed `*IA` and `*pA` (floating.hpp solves Iᴬ₀ a₀′ = τ₀ − pᴬ₀), and pass 3 starts from it.
struct NoRootSolve {};
template <class S, class Solve = NoRootSolve>
struct MovingRoot {
  static constexpr bool floating = true;
  Motion<S> v, a;
  Force<S>* f = nullptr;
  ArticulatedInertia<S>* IA = nullptr;
  Force<S>* pA = nullptr;
  Solve solve{};
};
}  // namespace detail

namespace detail {

enum RneaTerms : unsigned {
  kGravity = 1u,
  kVelocity = 2u,
  kAcceleration = 4u,
};

template <class Ext>
inline constexpr bool has_external_v = !std::is_same_v<std::decay_t<Ext>, NoExternalForces>;

/// cos qᵢ and sin qᵢ of every joint into `data` (before any `update_transform`).
template <class S, class T, class Q>
SPATIAL_INLINE void joint_sincos(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  sincos_all<S>(q, data.cos_q, data.sin_q, model.size());
}

/// ⁱX_λ(i) = X_J(qᵢ) X_T(i) (RBDA eq. 4.11), and ⁱX_0 when asked; needs `joint_sincos` first.
template <bool Base, class S, class T, class I, class Q>
void update_transform(const Model<S, T>& model, Data<S, T>& data, I index, const Eigen::MatrixBase<Q>& q) {
  const int i = index;
  const auto k = static_cast<std::size_t>(i);
  data.X_up[k] = model.joint(index).compose(S(q[i]), data.cos_q[i], data.sin_q[i], model.tree_transform(i));
  if constexpr (Base) {
    const int p = model.parent(index);
    data.X_base[k] = p >= 0 ? data.X_up[k] * data.X_base[static_cast<std::size_t>(p)] : data.X_up[k];
  }
}

/// What `crba_impl` reads for configuration q: cos qᵢ and sin qᵢ, and on the scalar path the transforms ⁱX_λ in
/// `data.X_up` (the AVX2 CRBA composes them itself from the sines and cosines and writes them out).
template <bool Simd = true, class S, class T, class Q>
void crba_inputs(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  joint_sincos(model, data, q);
#if SPATIAL_SIMD_AVX2
  if constexpr (Simd && simd_candidate<S, T>()) {
    if (simd_applies(model)) return;
  }
#endif
  for_each_body(model, [&](auto I) { update_transform<false>(model, data, I, q); });
}

/// Gravity-only RNEA, τ = G(q). With q̇ = q̈ = 0 every body's acceleration is the uniform field −g: aᵢ has no
/// angular part, and the force transmitted across joint i is Iᶜᵢ aᵢ = [hᶜᵢ × aᵢ; mᶜᵢ aᵢ], which depends only on the
/// subtree's mass mᶜᵢ and first moment hᶜᵢ. These are accumulated leaves to root (h_λ += Eᵀ hᵢ + mᵢ r) in place
/// of whole forces.
///
/// With `Keep` (`rnea<Dyn::Static>`, the bias pass of `forward_dynamics_crba<Dyn::Static>`) the call leaves what
/// the full RNEA leaves: `data.X_up`, `data.a` and the transmitted forces in `data.f`. Without it (`gravity_torques`)
/// only the rotation E = E_J E_T of ⁱX_λ = X_J X_T is composed (`Joint::rotate`), and the first
/// moment moves up as Eᵀ (hᵢ + mᵢ E_J r_J) + mᵢ r_T (`Joint::shift_moment`; r_J = 0 for revolute joints), with
/// X_J = (E_J, r_J) and X_T = (E_T, r_T). E, gᵢ, hᵢ and mᵢ are scratch: on the stack for compile-time trees (where
/// the compiler knows they alias nothing), in `data.X_up[i].E`, `data.a[i].v`, `data.f[i].n` and `data.f[i].f[0]`
/// for run-time trees; `ek(k)`, `gk(k)`, `hk(k)`, `mk(k)` return references to them.
template <bool Keep, class S, class T, class Q, class Out, class EK, class GK, class HK, class MK>
SPATIAL_INLINE void gravity_passes(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                   Out& tau, EK&& ek, GK&& gk, HK&& hk, MK&& mk) {
  const Vector3<S> g0 = -model.gravity();
  joint_sincos(model, data, q);
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const Vector3<S>& gp = p >= 0 ? gk(static_cast<std::size_t>(p)) : g0;
    if constexpr (Keep) {
      update_transform<false>(model, data, I, q);
      data.a[k].w = Vector3<S>::Zero();
      gk(k) = mul(data.X_up[k].E, gp);
    } else {
      Matrix3<S>& E = ek(k);
      E = model.joint(I).rotate(data.cos_q[i], data.sin_q[i], model.tree_transform(i).E);
      gk(k) = mul(E, gp);
    }
    const Inertia<S>& In = model.inertia(I);
    hk(k) = In.h;
    mk(k) = In.m;
  });
  for_each_body_reverse(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const auto joint = model.joint(I);
    const Vector3<S> h = hk(k);
    const S m = mk(k);
    const Vector3<S> g = gk(k);
    const Force<S> f(cross3(h, g), scale3(m, g));
    tau[i] = joint.project(f);
    if constexpr (Keep) data.f[k] = f;
    if (p >= 0) {
      Vector3<S> up;  // Eᵀ h + m r: h about the parent's origin, in parent coordinates
      if constexpr (Keep) {
        const Transform<S>& Xup = data.X_up[k];
        up = add3(mul_t(Xup.E, h), scale3(m, Xup.r));
      } else {
        up = add3(mul_t(ek(k), joint.shift_moment(S(q[i]), h, m)), scale3(m, model.tree_transform(i).r));
      }
      const auto pk = static_cast<std::size_t>(p);
      hk(pk) = add3(hk(pk), up);
      mk(pk) += m;
    }
  });
}

template <bool Keep, class S, class T, class Q, class Out>
void gravity_impl(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q, Out& tau) {
  using Index = std::size_t;
  if constexpr (!Keep && Model<S, T>::is_static) {
    constexpr auto nb = static_cast<Index>(Model<S, T>::NB);
    std::array<Matrix3<S>, nb> E;
    std::array<Vector3<S>, nb> g, h;
    std::array<S, nb> m;
    gravity_passes<Keep>(
        model, data, q, tau, [&](Index k) -> Matrix3<S>& { return E[k]; },
        [&](Index k) -> Vector3<S>& { return g[k]; }, [&](Index k) -> Vector3<S>& { return h[k]; },
        [&](Index k) -> S& { return m[k]; });
  } else {
    gravity_passes<Keep>(
        model, data, q, tau, [&](Index k) -> Matrix3<S>& { return data.X_up[k].E; },
        [&](Index k) -> Vector3<S>& { return data.a[k].v; }, [&](Index k) -> Vector3<S>& { return data.f[k].n; },
        [&](Index k) -> S& { return data.f[k].f[0]; });
  }
}

/// Recursive Newton–Euler inverse dynamics with a compile-time choice of terms (RBDA Table 5.1):
///   vᵢ = ⁱX_λ v_λ + Sᵢ q̇ᵢ,  aᵢ = ⁱX_λ a_λ + Sᵢ q̈ᵢ + vᵢ × Sᵢ q̇ᵢ  (a₀ = −a_g),
///   fᵢ = Iᵢ aᵢ + vᵢ ×* Iᵢ vᵢ − fᵢˣ,  τᵢ = Sᵢᵀ fᵢ,  f_λ += ⁱX_λᵀ fᵢ.
/// Terms switched off are not computed at all (no multiplications by zero). `Simd` = false forces the scalar code
/// (tests compare the two paths; see simd.hpp for when the AVX2 path is taken).
/// With a `MovingRoot` (floating base) the recursion starts from the root's velocity and acceleration instead of
/// 0 and −a_g, and the forces transmitted into the root are added to `*root.f`.
template <unsigned Terms, bool Simd = true, class S, class T, class Q, class QD, class QDD, class Ext, class Out,
          class Root = FixedRoot>
void rnea_impl(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
               const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd, const Ext& fext,
               ForceFrame frame, Out& tau, const Root& root = Root{}) {
  constexpr bool G = (Terms & kGravity) != 0;
  constexpr bool V = (Terms & kVelocity) != 0;
  constexpr bool A = (Terms & kAcceleration) != 0;
  constexpr bool X = has_external_v<Ext>;
  constexpr bool R = Root::floating;
  (void)root;
#if SPATIAL_SIMD_AVX2
  if constexpr (Simd && !X && simd_candidate<S, T>()) {
    if (simd_applies(model)) {
      (void)fext, (void)frame;
      simd::rnea<Terms>(model, data, q, qd, qdd, tau, root);
      return;
    }
  }
#endif
  if constexpr (Terms == kGravity && !X && !R) {
    (void)qd, (void)qdd, (void)frame;
    gravity_impl<true>(model, data, q, tau);
    return;
  }
  const bool base_frame = X && frame == ForceFrame::Base;
  Motion<S> a0;
  if constexpr (R) a0 = root.a;
  else a0 = -model.gravity_motion();
  joint_sincos(model, data, q);

  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const auto pk = static_cast<std::size_t>(p);
    const auto joint = model.joint(I);
    if (base_frame) update_transform<true>(model, data, I, q);
    else update_transform<false>(model, data, I, q);
    const Transform<S>& Xup = data.X_up[k];

    if constexpr (V) {
      const Motion<S> vJ = joint.motion(S(qd[i]));
      if constexpr (R) data.v[k] = Xup.apply(p >= 0 ? data.v[pk] : root.v) + vJ;
      else data.v[k] = p >= 0 ? Xup.apply(data.v[pk]) + vJ : vJ;
    }
    if constexpr (G || R) {
      data.a[k] = Xup.apply(p >= 0 ? data.a[pk] : a0);
    } else {
      if (p >= 0) data.a[k] = Xup.apply(data.a[pk]);
      else data.a[k] = Motion<S>::Zero();
    }
    if constexpr (A) joint.add_motion(data.a[k], S(qdd[i]));
    if constexpr (V) data.a[k] += joint.cross_motion(data.v[k], S(qd[i]));

    const Inertia<S>& In = model.inertia(i);
    data.f[k] = In * data.a[k];
    if constexpr (V) data.f[k] += cross(data.v[k], In * data.v[k]);
    if constexpr (X) {
      if (base_frame) data.f[k] -= data.X_base[k].apply_force(fext[k]);
      else data.f[k] -= fext[k];
    }
  });

  for_each_body_reverse(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    tau[i] = model.joint(I).project(data.f[k]);
    if (p >= 0) data.f[static_cast<std::size_t>(p)] += data.X_up[k].apply_force_inverse(data.f[k]);
    else if constexpr (R) *root.f += data.X_up[k].apply_force_inverse(data.f[k]);
  });
}

}  // namespace detail

/// Inverse dynamics by the recursive Newton–Euler algorithm (RBDA Table 5.1; Featherstone's notes, slide 55):
/// τ = H(q) q̈ + C(q, q̇) − Σ Jᵢᵀ fᵢˣ. Gravity enters as the fictitious base acceleration a₀ = −a_g, so
/// `data.a[i]` is body i's acceleration minus gravity (in body coordinates). After the call `data.v`, `data.a`,
/// `data.f` (force transmitted from the parent across joint i, in body i coordinates) and `data.X_up` hold the
/// per-body values. `fext[i]` is the external force acting on body i, in body or base coordinates per `frame`
/// (any container indexable by body with `Force<S>` elements).
/// Returns `data.tau`.
template <class S, class T, class Q, class QD, class QDD, class Ext = NoExternalForces>
const typename Data<S, T>::VectorN& rnea(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                         const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd,
                                         const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_sizes(model, "rnea", "q", q, "qd", qd, "qdd", qdd);
  using namespace detail;
  rnea_impl<kGravity | kVelocity | kAcceleration>(model, data, q, qd, qdd, fext, frame, data.tau);
  return data.tau;
}

/// Bias forces C(q, q̇) = RNEA(q, q̇, 0): Coriolis, centrifugal and gravity terms, without computing any q̈ term.
/// Returns `data.tau`.
template <class S, class T, class Q, class QD>
const typename Data<S, T>::VectorN& bias_forces(const Model<S, T>& model, Data<S, T>& data,
                                                const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd) {
  detail::check_sizes(model, "bias_forces", "q", q, "qd", qd);
  using namespace detail;
  rnea_impl<kGravity | kVelocity>(model, data, q, qd, qd, NoExternalForces{}, ForceFrame::Body, data.tau);
  return data.tau;
}

/// Gravity torques G(q) = RNEA(q, 0, 0): no velocity or acceleration term is computed, and of each joint transform
/// only the rotation is composed, so unlike `rnea` (and `rnea<Dyn::Static>`, which gives the same torques) it leaves
/// no other result in `data` (`data.X_up`, `data.a` and `data.f` may be used as scratch). Returns `data.tau`.
template <class S, class T, class Q>
const typename Data<S, T>::VectorN& gravity_torques(const Model<S, T>& model, Data<S, T>& data,
                                                    const Eigen::MatrixBase<Q>& q) {
  detail::check_sizes(model, "gravity_torques", "q", q);
#if SPATIAL_SIMD_AVX2
  // The AVX2 RNEA with gravity alone is as fast as the scalar path below under g++ and 10 % faster under clang.
  if constexpr (detail::simd_candidate<S, T>()) {
    if (detail::simd_applies(model)) {
      detail::rnea_impl<detail::kGravity>(model, data, q, q, q, NoExternalForces{}, ForceFrame::Body, data.tau);
      return data.tau;
    }
  }
#endif
  detail::gravity_impl<false>(model, data, q, data.tau);
  return data.tau;
}

/// Forward kinematics: `data.X_up[i]` = ⁱX_λ(i) and `data.X_base[i]` = ⁱX_0 (base → body i coordinates). In
/// ⁱX_0 = (E, r), r is body i's origin in base coordinates and Eᵀ its orientation (body axes in base coordinates).
template <class S, class T, class Q>
void forward_kinematics(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_sizes(model, "forward_kinematics", "q", q);
  detail::joint_sincos(model, data, q);
#if SPATIAL_SIMD_AVX2
  if constexpr (detail::simd_candidate<S, T>()) {
    if (detail::simd_applies(model)) {
      detail::simd::forward_kinematics(model, data);  // also leaves data.S_base
      return;
    }
  }
#endif
  for_each_body(model, [&](auto I) { detail::update_transform<true>(model, data, I, q); });
}

/// Pose of body i in the base frame after `forward_kinematics`: rotation (body axes in base coordinates) and
/// position of the body origin.
template <class S, class T>
Eigen::Transform<S, 3, Eigen::Isometry> body_pose(const Data<S, T>& data, int i) {
  const Transform<S>& X = data.X_base[static_cast<std::size_t>(i)];
  Eigen::Transform<S, 3, Eigen::Isometry> pose = Eigen::Transform<S, 3, Eigen::Isometry>::Identity();
  pose.linear() = X.E.transpose();
  pose.translation() = X.r;
  return pose;
}

/// Pose in the base frame of a fixed frame (`model.frames()[k]`) after `forward_kinematics`.
template <class S, class T>
Eigen::Transform<S, 3, Eigen::Isometry> frame_pose(const Model<S, T>& model, const Data<S, T>& data, int k) {
  const FixedFrame<S>& fr = model.frames()[static_cast<std::size_t>(k)];
  const Transform<S> X = fr.body >= 0 ? fr.X * data.X_base[static_cast<std::size_t>(fr.body)] : fr.X;
  Eigen::Transform<S, 3, Eigen::Isometry> pose = Eigen::Transform<S, 3, Eigen::Isometry>::Identity();
  pose.linear() = X.E.transpose();
  pose.translation() = X.r;
  return pose;
}

/// Body velocities `data.v` (and `data.X_up`) from (q, q̇): vᵢ = ⁱX_λ v_λ + Sᵢ q̇ᵢ (RBDA eq. 5.7).
template <class S, class T, class Q, class QD>
void forward_velocities(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                        const Eigen::MatrixBase<QD>& qd) {
  detail::check_sizes(model, "forward_velocities", "q", q, "qd", qd);
  detail::joint_sincos(model, data, q);
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    detail::update_transform<true>(model, data, I, q);
    const Motion<S> vJ = model.joint(I).motion(S(qd[i]));
    data.v[k] = p >= 0 ? data.X_up[k].apply(data.v[static_cast<std::size_t>(p)]) + vJ : vJ;
  });
}

/// Kinetic energy ½ Σ vᵢ · Iᵢ vᵢ (RBDA eq. 2.71).
template <class S, class T, class Q, class QD>
S kinetic_energy(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                 const Eigen::MatrixBase<QD>& qd) {
  detail::check_sizes(model, "kinetic_energy", "q", q, "qd", qd);
  forward_velocities(model, data, q, qd);
  S e = S(0);
  for (int i = 0; i < model.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    e += dot(data.v[k], model.inertia(i) * data.v[k]);
  }
  return e / S(2);
}

/// Potential energy −Σ mᵢ g · cᵢ (cᵢ: body i's centre of mass in base coordinates), zero at the base origin.
template <class S, class T, class Q>
S potential_energy(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_sizes(model, "potential_energy", "q", q);
  forward_kinematics(model, data, q);
  Vector3<S> first_moment = Vector3<S>::Zero();  // Σ mᵢ cᵢ in base coordinates
  for (int i = 0; i < model.size(); ++i) {
    const Transform<S>& X = data.X_base[static_cast<std::size_t>(i)];
    first_moment += model.inertia(i).m * X.r + X.E.transpose() * model.inertia(i).h;
  }
  return -model.gravity().dot(first_moment);
}

/// Centre of mass of the moving bodies, in base coordinates.
template <class S, class T, class Q>
Vector3<S> center_of_mass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_sizes(model, "center_of_mass", "q", q);
  forward_kinematics(model, data, q);
  Vector3<S> first_moment = Vector3<S>::Zero();
  S mass = S(0);
  for (int i = 0; i < model.size(); ++i) {
    const Transform<S>& X = data.X_base[static_cast<std::size_t>(i)];
    first_moment += model.inertia(i).m * X.r + X.E.transpose() * model.inertia(i).h;
    mass += model.inertia(i).m;
  }
  return first_moment / mass;
}

namespace detail {
/// CRBA on the inputs of `crba_inputs` (RBDA Table 6.2):
///   Iᶜᵢ = Iᵢ + Σ_children ʲX_iᵀ Iᶜⱼ ʲX_i;  Hᵢᵢ = Sᵢᵀ Iᶜᵢ Sᵢ;  H_ij = H_ji = Sⱼᵀ Fⱼ for every ancestor j of i, with
///   Fⱼ = Iᶜᵢ Sᵢ carried to body j by the force transforms. Rather than walking F up the ancestor chain (one force
///   transform per ancestor), F and every Sⱼ are expressed once in base coordinates (F⁰ = ⁱX_0ᵀ F,
///   S⁰ⱼ = ʲX_0⁻¹ Sⱼ, kept in `data.S_base`, with ⁱX_0 in `data.X_base`), where H_ij = S⁰ⱼ · F⁰ is a 6-term dot
///   product (the scalar product is invariant under the change of coordinates). Entries where neither joint is an
///   ancestor of the other stay zero.
///
/// `sink`, when given (floating.hpp: the joint-space inertia of a floating base), takes the place of `data.H`: it
/// receives every entry `sink.entry(i, j, Hᵢⱼ)` (j = i or an ancestor of i; `data.H` is then not written) and every
/// body's `sink(i, F⁰)`, Fᵢ⁰ = ⁱX_0ᵀ Iᶜᵢ Sᵢ in base coordinates, the roots' included. The default `NoForceSink`
/// compiles to nothing. A sink whose `entries` is false (centroidal.hpp: the columns of A_G) takes the forces
/// alone: no entry of H is computed. A sink whose `sums_roots` is true (both of those) also receives, between the
/// composite inertias and the forces, `sink.roots(Σ ⁱX_0ᵀ Iᶜᵢ ⁱX_0)`: the composite inertias of the roots (bodies
/// whose parent is the base) moved to base coordinates and summed, i.e. the whole tree's inertia there.
template <bool Simd = true, class S, class T, class Sink = NoForceSink>
void crba_impl(const Model<S, T>& model, Data<S, T>& data, Sink&& sink = Sink{}) {
  constexpr bool Out = std::decay_t<Sink>::active;
  constexpr bool Entries = std::decay_t<Sink>::entries;
#if SPATIAL_SIMD_AVX2
  if constexpr (Simd && simd_candidate<S, T>()) {
    if (simd_applies(model)) {
      simd::crba(model, data, sink);
      return;
    }
  }
#endif
  for_each_body(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const int p = model.parent(I);
    data.Ic[k] = model.inertia(I);
    data.X_base[k] = p >= 0 ? data.X_up[k] * data.X_base[static_cast<std::size_t>(p)] : data.X_up[k];
    data.S_base[k] = model.joint(I).subspace_inverse(data.X_base[k]);
  });
  constexpr bool Roots = std::decay_t<Sink>::sums_roots;
  [[maybe_unused]] Inertia<S> roots;
  if constexpr (Roots) roots = Inertia<S>::Zero();
  for_each_body_reverse(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const int p = model.parent(I);
    if (p >= 0) data.Ic[static_cast<std::size_t>(p)] += data.Ic[k].transformed_inverse(data.X_up[k]);
    else if constexpr (Roots) roots += data.Ic[k].transformed_inverse(data.X_up[k]);
  });
  if constexpr (Roots) sink.roots(roots);
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const auto joint = model.joint(I);
    const Force<S> F = joint.apply_inertia(data.Ic[k]);
    if constexpr (!Entries) {
      sink(i, data.X_base[k].apply_force_inverse(F));
    } else {
      if constexpr (Out) sink.entry(i, i, joint.project(F));
      else data.H(i, i) = joint.project(F);
      if (model.parent(I) < 0) {
        if constexpr (Out) sink(i, data.X_base[k].apply_force_inverse(F));
        return;
      }
      const Force<S> F0 = data.X_base[k].apply_force_inverse(F);
      if constexpr (Out) sink(i, F0);
      walk_up(model, I, [&](auto, auto P) {
        const int p = P;
        const S hip = dot(data.S_base[static_cast<std::size_t>(p)], F0);
        if constexpr (Out) {
          sink.entry(i, p, hip);
        } else {
          data.H(i, p) = hip;
          data.H(p, i) = hip;
        }
      });
    }
  });
}
}  // namespace detail

/// Joint-space inertia matrix H(q) by the composite-rigid-body algorithm (RBDA Table 6.2). Only the entries
/// H(i, j) where one of i, j is an ancestor of the other are written; the others are structurally zero (they were
/// zeroed when `data` was built). Returns `data.H`.
template <class S, class T, class Q>
const typename Data<S, T>::MatrixN& crba(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  detail::check_sizes(model, "crba", "q", q);
  detail::crba_inputs(model, data, q);
  detail::crba_impl(model, data);
  return data.H;
}

/// Sparse LTDL factorisation H = Lᵀ D L that follows the tree (RBDA Table 6.3): L is unit lower triangular with
/// L(i, j) ≠ 0 only where j is an ancestor of i, so the cost grows with the tree's depth, not with n³. Reads
/// `data.H`, writes `data.L` (D on its diagonal, L below it; other entries untouched).
template <class S, class T>
void ltdl(const Model<S, T>& model, Data<S, T>& data) {
  auto& L = data.L;
  for_each_body(model, [&](auto I) {
    const int k = I;
    L(k, k) = data.H(k, k);
    walk_up(model, I, [&](auto, auto P) { L(k, int(P)) = data.H(k, int(P)); });
  });
  for_each_body_reverse(model, [&](auto K) {
    const int k = K;
    const S inv_d = S(1) / L(k, k);
    walk_up(model, K, [&](auto, auto I) {
      const int i = I;
      const S lki = L(k, i);
      const S a = lki * inv_d;
      L(i, i) -= a * lki;
      // Unrolled over the ancestors of i only on small compile-time trees (the unrolled code grows as depth²).
      if constexpr (Model<S, T>::is_static && Model<S, T>::NB <= kMaxUnrolledLtdl) {
        walk_up(model, I, [&](auto, auto J) { L(i, int(J)) -= a * L(k, int(J)); });
      } else {
        walk_up(model, i, [&](int, int j) { L(i, j) -= a * L(k, j); });
      }
      L(k, i) = a;
    });
  });
}

namespace detail {
/// The two halves of `ltdl_solve`: x ← L⁻ᵀ x, and x ← L⁻¹ D⁻¹ x (so H⁻¹ = L⁻¹ D⁻¹ L⁻ᵀ; contact.hpp uses them apart).
template <class S, class T, class X>
void ltdl_solve_lt(const Model<S, T>& model, const Data<S, T>& data, Eigen::MatrixBase<X>& x) {
  const auto& L = data.L;
  for_each_body_reverse(model, [&](auto I) {
    const int i = I;
    const S xi = x[i];
    walk_up(model, I, [&](auto, auto J) { x[int(J)] -= L(i, int(J)) * xi; });
  });
}
template <class S, class T, class X>
void ltdl_solve_dl(const Model<S, T>& model, const Data<S, T>& data, Eigen::MatrixBase<X>& x) {
  const auto& L = data.L;
  for_each_body(model, [&](auto I) { x[int(I)] /= L(int(I), int(I)); });
  for_each_body(model, [&](auto I) {
    const int i = I;
    S xi = x[i];
    walk_up(model, I, [&](auto, auto J) { xi -= L(i, int(J)) * x[int(J)]; });
    x[i] = xi;
  });
}
}  // namespace detail

/// Solves H x = b in place (x holds b on entry) with the factor from `ltdl` (RBDA Table 6.4):
/// x ← L⁻ᵀ x, x ← D⁻¹ x, x ← L⁻¹ x.
template <class S, class T, class X>
void ltdl_solve(const Model<S, T>& model, const Data<S, T>& data, Eigen::MatrixBase<X>& x) {
  detail::check_sizes(model, "ltdl_solve", "x", x);
  detail::ltdl_solve_lt(model, data, x);
  detail::ltdl_solve_dl(model, data, x);
}

namespace detail {
/// q̈ = H⁻¹ (τ − bias) by CRBA and LTDL, the bias being RNEA with `Terms` (kGravity, kVelocity; never
/// kAcceleration). With no term the bias pass is skipped and only the transforms are computed. Result in data.qdd.
template <unsigned Terms, class S, class T, class Q, class QD, class Tau>
void forward_dynamics_crba_impl(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau) {
  static_assert((Terms & kAcceleration) == 0u, "the bias forces have no acceleration term");
  if constexpr (Terms != 0u) {
    rnea_impl<Terms>(model, data, q, qd, qd, NoExternalForces{}, ForceFrame::Body, data.tmp);
    data.tmp = tau - data.tmp;
  } else {
    (void)qd;
    crba_inputs(model, data, q);
    data.tmp = tau;
  }
  crba_impl(model, data);  // reuses the sines, cosines and transforms of the bias-force pass
  ltdl(model, data);
  data.qdd = data.tmp;
  ltdl_solve(model, data, data.qdd);
}
}  // namespace detail

/// Forward dynamics by CRBA and the tree-sparse LTDL factorisation (RBDA §6.5):
/// q̈ = H⁻¹ (τ − C(q, q̇)). Leaves H in `data.H`, its factor in `data.L`, τ − C in `data.tmp`; `data.tau` is not
/// touched. Returns `data.qdd`.
template <class S, class T, class Q, class QD, class Tau>
const typename Data<S, T>::VectorN& forward_dynamics_crba(const Model<S, T>& model, Data<S, T>& data,
                                                          const Eigen::MatrixBase<Q>& q,
                                                          const Eigen::MatrixBase<QD>& qd,
                                                          const Eigen::MatrixBase<Tau>& tau) {
  detail::check_sizes(model, "forward_dynamics_crba", "q", q, "qd", qd, "tau", tau);
  detail::forward_dynamics_crba_impl<detail::kGravity | detail::kVelocity>(model, data, q, qd, tau);
  return data.qdd;
}

namespace detail {
/// The articulated-body algorithm with a compile-time choice of terms: without `V` (q̇ = 0) vᵢ = cᵢ = 0, pass 1 is
/// the transforms alone and pass 2 drops Iᵃ cᵢ; without `G`, a₀ = 0. `aba` below and `aba<Dyn>` (options.hpp).
///
/// With a `MovingRoot` (floating base) pass 1 starts from the root's velocity `root.v`, pass 2 adds what the
/// root's children pass to it into `*root.IA` and `*root.pA`, `root.solve()` returns the root's acceleration and
/// pass 3 starts from it.
template <bool G, bool V, class S, class T, class Root>
void aba_pass3(const Model<S, T>& model, Data<S, T>& data, const Root& root);

template <bool G, bool V, bool Simd = true, class S, class T, class Q, class QD, class Tau, class Ext,
          class Root = FixedRoot>
void aba_impl(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
              const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau, const Ext& fext, ForceFrame frame,
              const Root& root = Root{}) {
  constexpr bool X = has_external_v<Ext>;
  constexpr bool R = Root::floating;
  (void)root;
#if SPATIAL_SIMD_AVX2
  if constexpr (Simd && !X && simd_candidate<S, T>()) {
    if (simd_applies(model)) {
      (void)fext, (void)frame;
      simd::aba<G, V>(model, data, q, qd, tau, root);
      return;
    }
  }
#endif
  const bool base_frame = X && frame == ForceFrame::Base;
  joint_sincos(model, data, q);
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    if (base_frame) update_transform<true>(model, data, I, q);
    else update_transform<false>(model, data, I, q);
    const Inertia<S>& In = model.inertia(i);
    data.IA[k] = ArticulatedInertia<S>(In);
    if constexpr (V) {
      const int p = model.parent(I);
      const auto joint = model.joint(I);
      const Motion<S> vJ = joint.motion(S(qd[i]));
      if constexpr (R) data.v[k] = data.X_up[k].apply(p >= 0 ? data.v[static_cast<std::size_t>(p)] : root.v) + vJ;
      else data.v[k] = p >= 0 ? data.X_up[k].apply(data.v[static_cast<std::size_t>(p)]) + vJ : vJ;
      data.c[k] = joint.cross_motion(data.v[k], S(qd[i]));
      data.pA[k] = cross(data.v[k], In * data.v[k]);
      if constexpr (X) {
        if (base_frame) data.pA[k] -= data.X_base[k].apply_force(fext[k]);
        else data.pA[k] -= fext[k];
      }
    } else if constexpr (X) {
      if (base_frame) data.pA[k] = -data.X_base[k].apply_force(fext[k]);
      else data.pA[k] = -fext[k];
    } else {
      data.pA[k] = Force<S>::Zero();
    }
  });
  for_each_body_reverse(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const auto joint = model.joint(I);
    data.U[k] = joint.apply_inertia(data.IA[k]);
    data.Dinv[k] = S(1) / joint.project(data.U[k]);
    data.u[k] = S(tau[i]) - joint.project(data.pA[k]);
    if (p >= 0 || R) {
      constexpr int K = NullAngular<std::decay_t<decltype(joint)>>::value;
      ArticulatedInertia<S> Ia = data.IA[k];
      Ia.template subtract_outer<K>(data.U[k], data.Dinv[k]);
      Force<S> pa = data.pA[k] + data.U[k] * (data.u[k] * data.Dinv[k]);
      if constexpr (V) pa += Ia.template mul_null<K>(data.c[k]);
      if (p >= 0) {
        const auto pk = static_cast<std::size_t>(p);
        data.IA[pk] += Ia.template transformed_inverse<K>(data.X_up[k]);
        data.pA[pk] += data.X_up[k].apply_force_inverse(pa);
      } else if constexpr (R) {
        *root.IA += Ia.template transformed_inverse<K>(data.X_up[k]);
        *root.pA += data.X_up[k].apply_force_inverse(pa);
      }
    }
  });
  if constexpr (R) {
    Root moved = root;
    moved.a = root.solve();
    aba_pass3<G, V>(model, data, moved);
  } else {
    aba_pass3<G, V>(model, data, root);
  }
}

/// ABA's pass 3 (see `aba_impl`): a′ = ⁱX_λ a_λ + cᵢ from a₀ = −a_g (fixed base) or `root.a` (floating base),
/// q̈ᵢ = (uᵢ − Uᵢᵀ a′) / Dᵢ, aᵢ = a′ + Sᵢ q̈ᵢ.
template <bool G, bool V, class S, class T, class Root>
void aba_pass3(const Model<S, T>& model, Data<S, T>& data, const Root& root) {
  constexpr bool R = Root::floating;
  (void)root;
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    if (p >= 0) data.a[k] = data.X_up[k].apply(data.a[static_cast<std::size_t>(p)]);
    else if constexpr (R) data.a[k] = data.X_up[k].apply(root.a);
    else if constexpr (G) data.a[k] = data.X_up[k].apply(-model.gravity_motion());
    else data.a[k] = Motion<S>::Zero();
    if constexpr (V) data.a[k] += data.c[k];
    const S qddi = (data.u[k] - dot(data.a[k], data.U[k])) * data.Dinv[k];
    data.qdd[i] = qddi;
    model.joint(I).add_motion(data.a[k], qddi);
  });
}
}  // namespace detail

/// Forward dynamics by the articulated-body algorithm (RBDA Table 7.1):
///  pass 1: vᵢ, cᵢ = vᵢ × Sᵢ q̇ᵢ, Iᴬᵢ = Iᵢ, pᴬᵢ = vᵢ ×* Iᵢ vᵢ − fᵢˣ;
///  pass 2 (leaves to root): Uᵢ = Iᴬᵢ Sᵢ, Dᵢ = Sᵢᵀ Uᵢ, uᵢ = τᵢ − Sᵢᵀ pᴬᵢ, and the parent receives
///    Iᵃ = Iᴬᵢ − Uᵢ Uᵢᵀ / Dᵢ, pᵃ = pᴬᵢ + Iᵃ cᵢ + Uᵢ uᵢ / Dᵢ through ⁱX_λᵀ;
///  pass 3: a′ = ⁱX_λ a_λ + cᵢ (a₀ = −a_g), q̈ᵢ = (uᵢ − Uᵢᵀ a′) / Dᵢ, aᵢ = a′ + Sᵢ q̈ᵢ.
/// A joint whose subtree has no inertia gives Dᵢ = 0 and non-finite results. Returns `data.qdd`.
template <class S, class T, class Q, class QD, class Tau, class Ext = NoExternalForces>
const typename Data<S, T>::VectorN& aba(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                        const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau,
                                        const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_sizes(model, "aba", "q", q, "qd", qd, "tau", tau);
  detail::aba_impl<true, true>(model, data, q, qd, tau, fext, frame);
  return data.qdd;
}

}  // namespace spatial

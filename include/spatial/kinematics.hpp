#pragma once
/// \file kinematics.hpp
/// Jacobians, frame velocities and accelerations, and their time variation, for fixed-base (`Model`/`Data`) and
/// floating-base (`FloatingModel`/`FloatingData`) trees, compile-time and run-time. Like the dynamics algorithms,
/// none of these functions allocates, throws or calls a virtual function; Jacobians are written into
/// `data.J` / `data.dJ` or into a caller-provided 6 × nv matrix (any Eigen matrix or block of the right size: it is
/// not resized; columns that do not move the body are set to zero).
///
/// ## Rows, columns and reference frames
/// **Every 6-row Jacobian has its linear rows first**: (vx vy vz ωx ωy ωz), as in Pinocchio, KDL and the
/// free-flyer's v — while `Motion` objects are angular first. Columns are the nv velocity coordinates (floating base:
/// the six free-flyer columns first, then the joints). "World" is the base frame for a fixed base.
/// For a body or frame F with pose (R, p) in the world (R: F's axes in world coordinates, p: its origin), with
/// ᶠX_w = (E = Rᵀ, r = p) the passive transform world → F, and a world spatial vector m = [ω; v_O] (v_O: velocity
/// of the body-fixed point at the world origin), the three reference frames of Pinocchio are
///   - `ReferenceFrame::Local`             ᶠX_w m = [Eω; E(v_O + ω × p)]   F's axes, velocity of F's origin
///   - `ReferenceFrame::World`             m = [ω; v_O]                     world axes, velocity of the point at
///                                                                          the world origin
///   - `ReferenceFrame::LocalWorldAligned` [ω; v_O + ω × p]                 world axes, velocity of F's origin
///                                                                          (what KDL's Jacobians return)
///
/// ## Jacobians
///   `compute_joint_jacobians(q)`: forward kinematics and `data.J` = [S⁰ⱼ] (World, 6 × nv), S⁰ⱼ = ʲX_w⁻¹ Sⱼ the motion
///   subspace of joint j in world coordinates (floating base: columns 0–5 the free-flyer's basis ʳX_w⁻¹ [0; e_k]
///   and ʳX_w⁻¹ [e_k; 0], r = the root). Then v_F^World = J v summed over the ancestors of F's body.
///   `body_jacobian` / `frame_jacobian` re-express the ancestor columns in a reference frame; `compute_body_jacobian`
///   / `compute_frame_jacobian` do everything in one walk over the body's chain (only the ancestors' joint
///   transforms are computed): their world transforms composed from the root down, ʲX_w = ʲX_λ(j) ᵏX_w, each
///   column the joint's world motion subspace ʲX_w⁻¹ Sⱼ moved into the reference frame (`jacobian_walk_down`; on
///   the AVX2 path, simd.hpp's conditions and a column-major 6-row output, `jacobian_walk_simd` writes each column
///   straight in the reference frame). A run-time chain deeper than kMaxWalkDepth walks from the body up instead:
///   Local column ᶠX_j Sⱼ, accumulating ᶠX_λ(j) = ᶠX_j ʲX_λ(j).
///
/// ## Velocities and accelerations
///   `forward_kinematics(q, v, a)`: transforms, body velocities and **spatial** accelerations (in body
///   coordinates, `data.v`, `data.a`; floating: `data.tree.v`, `data.tree.a`, the root's `data.v0`, `data.a0`):
///     vᵢ = ⁱX_λ v_λ + Sᵢ q̇ᵢ,   aᵢ = ⁱX_λ a_λ + Sᵢ q̈ᵢ + vᵢ × Sᵢ q̇ᵢ,
///   from v₀ = a₀ = 0 (fixed base) or the root's v₀ = v[0:6], a₀ = a[0:6] (root coordinates; floating base).
///   **Gravity is not included** (unlike `data.a` after RNEA/ABA, which holds a − a_g).
///   `body_velocity` / `frame_velocity`, `body_acceleration` / `frame_acceleration` return them (as `Motion`,
///   angular first) in a reference frame: Local = ᶠX_body applied; World = ᶠX_w⁻¹ applied (the world spatial
///   acceleration, which is the time derivative of the World velocity); LocalWorldAligned = the Local vector with
///   both parts rotated to world axes, [R ω̇; R a_lin] (Pinocchio's convention).
///
/// ## Spatial versus classical acceleration — read this before using either
///   The *spatial* acceleration's linear part a_lin is the time derivative of the velocity of the body-fixed point
///   that is at F's origin **as seen in F's own (moving) coordinates**: a_lin = d/dt(v_F^Local) (linear part). The
///   *classical* acceleration of F's origin, p̈ (what an accelerometer at the origin measures, minus gravity), is
///     p̈ = a_lin + ω × v_lin          (both in F's axes; rotated by R for world axes).
///   `frame_classical_acceleration(rf)` returns p̈ (Vector3) in F's axes (Local) or world axes (World and
///   LocalWorldAligned: both give the acceleration of F's origin — unlike Pinocchio, whose World variant is the
///   point at the world origin).
///
/// ## Time variation of the Jacobians and the drift term J̇ q̇
///   `compute_joint_jacobians_time_variation(q, v)`: `data.J` and `data.dJ` = d/dt J (World): column j is
///   v⁰ⱼ × S⁰ⱼ, v⁰ⱼ = body j's velocity in world coordinates (Sⱼ is constant in body j's coordinates).
///   `body_jacobian_time_variation(rf)` / `frame_jacobian_time_variation(rf)` = d/dt of the Jacobian in `rf`:
///     Local:             ᶠX_w (J̇⁰ − v⁰_F × J⁰)
///     World:             J̇⁰
///     LocalWorldAligned: column [ω̇ⱼ; v̇ⱼ + ω̇ⱼ × p + ωⱼ × ṗ] for the World column [ωⱼ; vⱼ], d/dt [ωⱼ; vⱼ] = [ω̇ⱼ; v̇ⱼ].
///   With v̇ = 0 the acceleration is J̇ v, hence (Jacobian rows: linear first)
///     J̇_Local v = spatial acceleration (Local)         = `frame_jdot_qdot(Local)`
///     J̇_World v = spatial acceleration (World)         = `frame_jdot_qdot(World)`
///     J̇_LWA  v = [p̈; R ω̇] — the **classical** linear acceleration p̈ = `frame_classical_jdot_qdot(LWA)`, NOT
///                 `frame_jdot_qdot(LocalWorldAligned)`, whose linear part is R a_lin = p̈ − ω × ṗ.
///   `frame_jdot_qdot(q, v, frame, rf)` returns the **spatial** acceleration of the frame at v̇ = 0 (a `Motion`,
///   angular first), `frame_classical_jdot_qdot(q, v, frame, rf)` the **classical** acceleration of its origin at
///   v̇ = 0 (Vector3). Both run `forward_kinematics(q, v, 0)` (data.a then holds the drift accelerations).
///
/// Body −1 is the base: for a fixed base its Jacobians, velocity and acceleration are zero; for a floating base it
/// is the root body (free-flyer columns only). Frames are indices into `model.frames()` (floating:
/// `model.tree().frames()`).

#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"

#include <cmath>
#include <cstddef>

namespace spatial {

/// The frame in which Jacobians, velocities and accelerations are expressed (Pinocchio's LOCAL, WORLD,
/// LOCAL_WORLD_ALIGNED; see the top of kinematics.hpp).
enum class ReferenceFrame {
  Local,              ///< the body's (frame's) axes, velocity of its origin
  World,              ///< world (fixed base: base) axes, velocity of the body-fixed point at the world origin
  LocalWorldAligned,  ///< world axes, velocity of the body's (frame's) origin (KDL's Jacobians)
};

namespace detail {

/// Column c of a Jacobian (rows linear first) as a Motion (angular first), and back.
template <class S, class M>
SPATIAL_INLINE Motion<S> jacobian_column(const Eigen::MatrixBase<M>& J, int c) {
  return Motion<S>(Vector3<S>(J(3, c), J(4, c), J(5, c)), Vector3<S>(J(0, c), J(1, c), J(2, c)));
}
template <class S, class M>
SPATIAL_INLINE void set_jacobian_column(Eigen::MatrixBase<M>& J, int c, const Motion<S>& m) {
  J(0, c) = m.v[0], J(1, c) = m.v[1], J(2, c) = m.v[2];
  J(3, c) = m.w[0], J(4, c) = m.w[1], J(5, c) = m.w[2];
}

/// A world spatial vector m in the reference frame of F, with X = ᶠX_w.
template <class S>
SPATIAL_INLINE Motion<S> world_to_frame(ReferenceFrame rf, const Transform<S>& X, const Motion<S>& m) {
  switch (rf) {
    case ReferenceFrame::Local: return X.apply(m);
    case ReferenceFrame::LocalWorldAligned: return Motion<S>(m.w, add3(m.v, cross3(m.w, X.r)));
    case ReferenceFrame::World: break;
  }
  return m;
}
/// A spatial vector in F's coordinates in the reference frame rf, with X = ᶠX_w.
template <class S>
SPATIAL_INLINE Motion<S> local_to_frame(ReferenceFrame rf, const Transform<S>& X, const Motion<S>& m) {
  switch (rf) {
    case ReferenceFrame::World: return X.apply_inverse(m);
    case ReferenceFrame::LocalWorldAligned: return Motion<S>(mul_t(X.E, m.w), mul_t(X.E, m.v));
    case ReferenceFrame::Local: break;
  }
  return m;
}

/// The free-flyer's k-th velocity coordinate as a motion in root coordinates (k < 3: linear, else angular).
template <class S>
SPATIAL_INLINE Motion<S> free_flyer_basis(int k) {
  Motion<S> m = Motion<S>::Zero();
  if (k < 3) m.v[k] = S(1);
  else m.w[k - 3] = S(1);
  return m;
}

/// The free-flyer's k-th velocity coordinate in world coordinates, ʳX_w⁻¹ free_flyer_basis(k) with X0 = ʳX_w: root
/// axis k mod 3 in the world is u = row k mod 3 of X0's E; a unit linear velocity along it moves every point by u, a
/// unit rotation about it through the root's origin r is [u; r × u].
template <class S>
SPATIAL_INLINE Motion<S> free_flyer_world_column(const Transform<S>& X0, int k) {
  const int a = k % 3;
  const Vector3<S> u(X0.E(a, 0), X0.E(a, 1), X0.E(a, 2));
  return k < 3 ? Motion<S>(Vector3<S>::Zero(), u) : Motion<S>(u, cross3(X0.r, u));
}

/// What the kinematics functions need from a fixed-base model and its data (`D`: Data or const Data).
template <class S, class T, class D>
struct FixedKin {
  using Scalar = S;
  static constexpr int root_cols = 0;  ///< free-flyer columns
  static constexpr int qoff = 0;       ///< offset of the joints in q
  const Model<S, T>& tree;
  D& data;
  D& td() const { return data; }
  const Model<S, T>& frames_model() const { return tree; }
  /// ⁱX_w (i = −1: the base, identity).
  Transform<S> world(int i) const {
    return i >= 0 ? data.X_base[static_cast<std::size_t>(i)] : Transform<S>::Identity();
  }
  /// World (base) coordinates of the point with coordinates x in body i's frame.
  Vector3<S> point_world(int i, const Vector3<S>& x) const {
    if (i < 0) return x;
    const Transform<S>& X = data.X_base[static_cast<std::size_t>(i)];
    return add3(X.r, mul_t(X.E, x));
  }
  Motion<S> velocity(int i) const { return i >= 0 ? data.v[static_cast<std::size_t>(i)] : Motion<S>::Zero(); }
  Motion<S> acceleration(int i) const { return i >= 0 ? data.a[static_cast<std::size_t>(i)] : Motion<S>::Zero(); }
  Transform<S> root() const { return Transform<S>::Identity(); }
};

/// The same for a floating-base model (`D`: FloatingData or const FloatingData).
template <class S, class T, class D>
struct FloatingKin {
  using Scalar = S;
  static constexpr int root_cols = 6;
  static constexpr int qoff = 7;
  const Model<S, T>& tree;
  D& data;
  auto& td() const { return data.tree; }
  const Model<S, T>& frames_model() const { return tree; }
  Transform<S> world(int i) const {
    return i >= 0 ? data.tree.X_base[static_cast<std::size_t>(i)] * data.X0 : data.X0;
  }
  Vector3<S> point_world(int i, const Vector3<S>& x) const {
    Vector3<S> y = x;
    if (i >= 0) {
      const Transform<S>& X = data.tree.X_base[static_cast<std::size_t>(i)];
      y = add3(X.r, mul_t(X.E, x));
    }
    return add3(data.X0.r, mul_t(data.X0.E, y));
  }
  Motion<S> velocity(int i) const { return i >= 0 ? data.tree.v[static_cast<std::size_t>(i)] : data.v0; }
  Motion<S> acceleration(int i) const { return i >= 0 ? data.tree.a[static_cast<std::size_t>(i)] : data.a0; }
  Transform<S> root() const { return data.X0; }
};

template <class S, class T>
FixedKin<S, T, Data<S, T>> kin(const Model<S, T>& m, Data<S, T>& d) { return {m, d}; }
template <class S, class T>
FixedKin<S, T, const Data<S, T>> kin(const Model<S, T>& m, const Data<S, T>& d) { return {m, d}; }
template <class S, class T>
FloatingKin<S, T, FloatingData<S, T>> kin(const FloatingModel<S, T>& m, FloatingData<S, T>& d) {
  return {m.tree(), d};
}
template <class S, class T>
FloatingKin<S, T, const FloatingData<S, T>> kin(const FloatingModel<S, T>& m, const FloatingData<S, T>& d) {
  return {m.tree(), d};
}

/// Calls f(column) for every velocity coordinate that moves body i: its ancestors' joints, then the free-flyer.
template <class K, class F>
SPATIAL_INLINE void for_each_ancestor_column(const K& k, int i, F&& f) {
  for (int j = i; j >= 0; j = k.tree.parent(j)) f(K::root_cols + j);
  for (int c = 0; c < K::root_cols; ++c) f(c);
}

/// The body and ᶠX_w of frame `f` (index into the frames).
template <class K>
SPATIAL_INLINE Transform<typename K::Scalar> frame_world(const K& k, int f, int& body) {
  const auto& fr = k.frames_model().frames()[static_cast<std::size_t>(f)];
  body = fr.body;
  return fr.X * k.world(fr.body);
}

/// data.J (World) from the transforms of forward kinematics; with `Dot`, data.dJ from the velocities too.
template <bool Dot, class K>
void joint_jacobian_columns(const K& k) {
  using S = typename K::Scalar;
  auto& td = k.td();
  auto& J = k.data.J;
  const Transform<S> X0 = k.root();
  if constexpr (K::root_cols > 0) {
    const Motion<S> v0 = X0.apply_inverse(k.data.v0);
    for (int c = 0; c < 6; ++c) {
      const Motion<S> s = free_flyer_world_column(X0, c);
      set_jacobian_column(J, c, s);
      if constexpr (Dot) set_jacobian_column(k.data.dJ, c, cross(v0, s));
    }
  }
#if SPATIAL_SIMD_AVX2
  // The AVX2 forward kinematics has left Sⱼ in base (root) coordinates in data.S_base.
  using TreeT = typename std::decay_t<decltype(k.tree)>::tree_type;
  if constexpr (!Dot && simd_candidate<S, TreeT>()) {
    if (simd_applies(k.tree)) {
      simd::world_jacobian_columns<(K::root_cols > 0)>(td.S_base.data(), k.tree.size(), X0, J.data(), K::root_cols);
      return;
    }
  }
#endif
  for_each_body(k.tree, [&](auto I) {
    const auto i = static_cast<std::size_t>(int(I));
    // Sⱼ and vⱼ in base (root) coordinates, then (floating) in world coordinates.
    Motion<S> s = k.tree.joint(I).subspace_inverse(td.X_base[i]);
    if constexpr (K::root_cols > 0) s = X0.apply_inverse(s);
    set_jacobian_column(J, K::root_cols + int(I), s);
    if constexpr (Dot) {
      Motion<S> vw = td.X_base[i].apply_inverse(td.v[i]);
      if constexpr (K::root_cols > 0) vw = X0.apply_inverse(vw);
      set_jacobian_column(k.data.dJ, K::root_cols + int(I), cross(vw, s));
    }
  });
}

/// Transforms, velocities and (with `Acc`) accelerations of every body of a tree hanging from a root moving with
/// (v0, a0) (zero for a fixed base); without `Acc` the accelerations are those at zero q̈ (the drift).
template <bool Acc, class S, class T, class Q, class V, class A>
void kinematics_pass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                     const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, const Motion<S>& v0,
                     const Motion<S>& a0) {
  (void)a;
  if constexpr (Acc) check_sizes(model, "kinematics", "q", q, "v", v, "a", a);
  else check_sizes(model, "kinematics", "q", q, "v", v);
  joint_sincos(model, data, q);
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const auto joint = model.joint(I);
    update_transform<true>(model, data, I, q);
    const Transform<S>& Xup = data.X_up[k];
    const S qd = S(v[i]);
    data.v[k] = Xup.apply(p >= 0 ? data.v[static_cast<std::size_t>(p)] : v0) + joint.motion(qd);
    data.a[k] = Xup.apply(p >= 0 ? data.a[static_cast<std::size_t>(p)] : a0);
    if constexpr (Acc) joint.add_motion(data.a[k], S(a[i]));
    data.a[k] += joint.cross_motion(data.v[k], qd);
  });
}

template <bool Acc, class S, class T, class Q, class V, class A>
void kinematics_pass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                     const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  kinematics_pass<Acc>(model, data, q, v, a, Motion<S>::Zero(), Motion<S>::Zero());
}
template <bool Acc, class S, class T, class Q, class V, class A>
void kinematics_pass(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                     const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  constexpr int NJ = FloatingModel<S, T>::NJ;
  const int n = model.njoints();
  check_q(model, q, "kinematics");
  check_v(model, v, "kinematics", "v");
  if constexpr (Acc) check_v(model, a, "kinematics", "a");
  data.X0 = root_transform<S>(q);
  data.v0 = root_motion(v).template cast<S>();
  if constexpr (Acc) data.a0 = root_motion(a).template cast<S>();
  else data.a0 = Motion<S>::Zero();
  if constexpr (Acc)
    kinematics_pass<true>(model.tree(), data.tree, joint_block<NJ>(q, 7, n), joint_block<NJ>(v, 6, n),
                          joint_block<NJ>(a, 6, n), data.v0, data.a0);
  else
    kinematics_pass<false>(model.tree(), data.tree, joint_block<NJ>(q, 7, n), joint_block<NJ>(v, 6, n),
                           joint_block<NJ>(v, 6, n), data.v0, data.a0);
}

/// The Jacobian of the body-fixed frame ᶠX_body = `Xf` on body `body` from data.J.
template <class K, class Out>
void jacobian_from_world(const K& k, int body, const Transform<typename Out::Scalar>& Xfw, ReferenceFrame rf,
                         Eigen::MatrixBase<Out>& J) {
  using S = typename Out::Scalar;
  J.setZero();
  const auto& J0 = k.data.J;
  for_each_ancestor_column(k, body, [&](int c) {
    set_jacobian_column(J, c, world_to_frame<S>(rf, Xfw, jacobian_column<S>(J0, c)));
  });
}

/// The same for rf = World or LocalWorldAligned, which need only F's origin p (world coordinates): a column
/// [v; ω] of data.J becomes [v + ω × p; ω] (LocalWorldAligned) or stays (World).
template <class K, class Out>
void jacobian_from_world_at(const K& k, int body, const Vector3<typename Out::Scalar>& p, ReferenceFrame rf,
                            Eigen::MatrixBase<Out>& J) {
  using S = typename Out::Scalar;
  J.setZero();
  const auto& J0 = k.data.J;
  if (rf == ReferenceFrame::World) {
    for_each_ancestor_column(k, body, [&](int c) { J.col(c) = J0.col(c); });
    return;
  }
#if SPATIAL_SIMD_AVX2
  if constexpr (lane_columns<Out>()) {
    if (lane_columns(J)) {
      const auto pv = simd::load3(p.data());
      S* out = J.derived().data();
      for_each_ancestor_column(k, body, [&](int c) { simd::jacobian_column_at(J0.data(), pv, out, c); });
      return;
    }
  }
#endif
  for_each_ancestor_column(k, body, [&](int c) {
    const Vector3<S> w = J0.template block<3, 1>(3, c);
    J.template block<3, 1>(0, c) = add3(Vector3<S>(J0.template block<3, 1>(0, c)), cross3(w, p));
    J.template block<3, 1>(3, c) = w;
  });
}

/// d/dt of the Jacobian of frame F (ᶠX_w = Xfw) on `body` from data.J and data.dJ.
template <class K, class Out>
void jacobian_time_variation_from_world(const K& k, int body, const Transform<typename Out::Scalar>& Xfw, ReferenceFrame rf,
                                        Eigen::MatrixBase<Out>& dJ) {
  using S = typename Out::Scalar;
  dJ.setZero();
  const auto& J0 = k.data.J;
  const auto& dJ0 = k.data.dJ;
  const Motion<S> vw = k.world(body).apply_inverse(k.velocity(body));  // the body's velocity, world coordinates
  const Vector3<S> pdot = add3(vw.v, cross3(vw.w, Xfw.r));             // velocity of F's origin, world axes
  for_each_ancestor_column(k, body, [&](int c) {
    const Motion<S> m = jacobian_column<S>(J0, c);
    const Motion<S> dm = jacobian_column<S>(dJ0, c);
    Motion<S> out = dm;
    switch (rf) {
      case ReferenceFrame::Local: out = Xfw.apply(dm - cross(vw, m)); break;
      case ReferenceFrame::LocalWorldAligned:
        out = Motion<S>(dm.w, add3(add3(dm.v, cross3(dm.w, Xfw.r)), cross3(m.w, pdot)));
        break;
      case ReferenceFrame::World: break;
    }
    set_jacobian_column(dJ, c, out);
  });
}

/// Deepest chain (bodies from a body up to the base) that the root-first walks (`jacobian_walk_simd`,
/// `jacobian_walk_down`) serve on a run-time tree (the size of their stack arrays); deeper ones take the body-first
/// walk of `jacobian_walk`.
inline constexpr int kMaxWalkDepth = 64;

/// Whether a root-first walk can take body's chain: always on a compile-time tree, and on a run-time tree when the
/// chain has at most kMaxWalkDepth bodies.
template <class Tree>
SPATIAL_INLINE bool walk_fits(const Tree& tree, int body) {
  if constexpr (Tree::is_static) {
    return (void)tree, (void)body, true;
  } else {
    int n = 0;
    for (int j = body; j >= 0; j = tree.parent(j))
      if (++n > kMaxWalkDepth) return false;
    return true;
  }
}

/// A body's chain for the root-first walks: its bodies from the body up (idx[0] = body, idx[n − 1] a root; run-time
/// trees: at most kMaxWalkDepth, `walk_fits`), their joint positions and, computed together (`sincos_all`
/// vectorises), their cosines and sines.
template <class K>
struct Chain {
  using S = typename K::Scalar;
  using Tree = std::decay_t<decltype(std::declval<const K&>().tree)>;
  static constexpr int NB = Tree::is_static ? Tree::NB : kMaxWalkDepth;
  std::array<int, NB> idx;
  std::array<S, NB> qc, cc, sc;
  int n = 0;
  template <class Q>
  SPATIAL_INLINE Chain(const K& k, const Eigen::MatrixBase<Q>& q, int body) {
    for (int j = body; j >= 0; j = k.tree.parent(j), ++n) {
      idx[static_cast<std::size_t>(n)] = j;
      qc[static_cast<std::size_t>(n)] = S(q[K::qoff + j]);
    }
    sincos_all<S>(qc, cc, sc, n);
  }
};

/// Where the root-first walks start, ʳX_w: the root's pose from q on a floating base, identity on a fixed one.
template <class K, class S, class Q>
SPATIAL_INLINE Transform<S> walk_root(const Eigen::MatrixBase<Q>& q) {
  if constexpr (K::root_cols > 0) return root_transform<S>(q);
  else return (void)q, Transform<S>::Identity();
}

/// The root-first walk over body's chain (run-time trees: at most kMaxWalkDepth bodies, `walk_fits`): the world
/// transforms composed from the root down, ⁱX_w = ⁱX_λ ᵏX_w (from the root's ʳX_w = X0: identity for a fixed base),
/// calling step(i, joint, ⁱX_w) for each of the chain's joints, root first (`joint` with its compile-time type,
/// `visit_joint`: one dispatch per joint on a run-time type), from the sines and cosines of `Chain`. Returns ᵇX_w
/// (X0 for body −1).
template <class K, class Q, class Step>
SPATIAL_INLINE Transform<typename K::Scalar> chain_world(const K& k, const Eigen::MatrixBase<Q>& q, int body,
                                                         const Transform<typename K::Scalar>& X0, Step&& step) {
  using S = typename K::Scalar;
  const Chain<K> ch(k, q, body);
  Transform<S> X = X0;
  for (int t = ch.n - 1; t >= 0; --t) {
    const auto u = static_cast<std::size_t>(t);
    const int i = ch.idx[u];
    visit_joint(k.tree.joint(i), [&](const auto& joint) SPATIAL_LAMBDA_INLINE {
      X = joint.compose(ch.qc[u], ch.cc[u], ch.sc[u], k.tree.tree_transform(i)) * X;  // ⁱX_w
      step(i, joint, X);
    });
  }
  return X;
}

/// ᵇX_w of body `body` (−1: the base, or the root of a floating base) from q by `chain_world`: only the chain's
/// joint transforms (batch.hpp's placements; `walk_fits` must hold).
template <class K, class Q>
SPATIAL_INLINE Transform<typename K::Scalar> chain_placement(const K& k, const Eigen::MatrixBase<Q>& q, int body) {
  using S = typename K::Scalar;
  const Transform<S> X0 = walk_root<K, S>(q);
  return chain_world(k, q, body, X0, [](int, const auto&, const Transform<S>&) {});
}

/// The root-first Jacobian walk for any scalar (jacobian_walk's path off AVX2: SIMD lanes of batch.hpp, joints of
/// any type, float or double without AVX2, automatic differentiation): `chain_world`, each joint's column in world
/// coordinates, S⁰ᵢ = ⁱX_w⁻¹ Sᵢ (`subspace_inverse`), written to J, then moved into `rf` in place with
/// ᶠX_w = Xf ᵇX_w (`world_to_frame`). Per joint this is one composition and the cheap world column (six products
/// for an axis-aligned revolute), where the body-first walk takes a composition, a whole transform of Sᵢ and, for
/// World or LocalWorldAligned, a rotation of each column at the end. J's other columns are left as they are.
template <class K, class Q, class Out>
void jacobian_walk_down(const K& k, const Eigen::MatrixBase<Q>& q, int body, const Transform<typename Out::Scalar>& Xf,
                        ReferenceFrame rf, Eigen::MatrixBase<Out>& J) {
  using S = typename Out::Scalar;
  const Transform<S> X0 = walk_root<K, S>(q);
  if constexpr (K::root_cols > 0)
    for (int c = 0; c < 6; ++c) set_jacobian_column(J, c, free_flyer_world_column(X0, c));
  const Transform<S> X = chain_world(k, q, body, X0, [&](int i, const auto& joint, const Transform<S>& Xi) {
    set_jacobian_column(J, K::root_cols + i, joint.subspace_inverse(Xi));
  });
  if (rf == ReferenceFrame::World) return;
  const Transform<S> Xfw = Xf * X;
  for_each_ancestor_column(k, body, [&](int c) {
    set_jacobian_column(J, c, world_to_frame<S>(rf, Xfw, jacobian_column<S>(J, c)));
  });
}

#if SPATIAL_SIMD_AVX2

/// jacobian_walk's AVX2 path (a tree of axis-aligned revolute joints, double or float, J a column-major matrix
/// with 6 rows): the chain's world transforms from the root down (ⁱX_w = ⁱX_λ ᵏX_w, starting from the root's
/// ⁰X_w = X0, identity for a fixed base), then every column straight in `rf`: a joint with world axis ω through
/// the point p moves the world origin at p × ω (World) and the frame's origin p_f at ω × (p_f − p)
/// (LocalWorldAligned; Local rotates that into the frame's axes). On a run-time tree, the caller has checked that
/// the chain is no deeper than kMaxWalkDepth (`walk_fits`).
template <class K, class Q, class S>
void jacobian_walk_simd(const K& k, const Eigen::MatrixBase<Q>& q, int body, const Transform<S>& Xf,
                        ReferenceFrame rf, S* J) {
  using namespace simd;
  using V = Vec<S>;
  constexpr int NB = Chain<K>::NB;
  const Chain<K> ch(k, q, body);
  const auto& idx = ch.idx;
  const auto& cc = ch.cc;
  const auto& sc = ch.sc;
  const int n = ch.n;
  const Transform<S> X0 = walk_root<K, S>(q);
  V col[3], row[3], r;  // the current body's ⁱX_w
  col[0] = load3z(X0.E.data());
  col[1] = load3z(X0.E.data() + 3);
  col[2] = load3(X0.E.data() + 6);
  transpose(col[0], col[1], col[2], row[0], row[1], row[2]);
  r = load3(X0.r.data());
  const V root_row[3] = {row[0], row[1], row[2]}, p0 = r;
  V w[NB], p[NB];  // joint axes and origins in the world, tip first
  for (int t = n - 1; t >= 0; --t) {
    const auto u = static_cast<std::size_t>(t);
    const int i = idx[u];
    V ucol[3], ur;
    const int axis_k = revolute_axis(k.tree.joint_type(i));
    if (axis_k == 0) compose<0>(k.tree.tree_transform(i), cc[u], sc[u], ucol[0], ucol[1], ucol[2], ur);
    else if (axis_k == 1) compose<1>(k.tree.tree_transform(i), cc[u], sc[u], ucol[0], ucol[1], ucol[2], ur);
    else compose<2>(k.tree.tree_transform(i), cc[u], sc[u], ucol[0], ucol[1], ucol[2], ur);
    r = add(r, comb(row[0], row[1], row[2], ur));
    for (int c = 0; c < 3; ++c) col[c] = comb(ucol[0], ucol[1], ucol[2], col[c]);
    transpose(col[0], col[1], col[2], row[0], row[1], row[2]);
    w[u] = row[axis_k];
    p[u] = r;
  }
  // The frame: ᶠX_w = ᶠX_b ᵇX_w.
  V fcol[3], frow[3];
  {
    const V a0 = load3z(Xf.E.data()), a1 = load3z(Xf.E.data() + 3), a2 = load3(Xf.E.data() + 6);
    for (int c = 0; c < 3; ++c) fcol[c] = comb(a0, a1, a2, col[c]);
    transpose(fcol[0], fcol[1], fcol[2], frow[0], frow[1], frow[2]);
  }
  const V pf = add(r, comb(row[0], row[1], row[2], load3(Xf.r.data())));
  auto column = [&](int c, V wc, V pc, bool linear) SPATIAL_LAMBDA_INLINE {
    V v;
    if (linear) {
      v = wc;  // a unit translation of the root along wc: every point moves by wc
      wc = zero<V>();
    } else if (rf == ReferenceFrame::World) {
      v = cross(pc, wc);
    } else {
      v = cross(wc, sub(pf, pc));
    }
    if (rf == ReferenceFrame::Local) {
      v = comb(fcol[0], fcol[1], fcol[2], v);
      wc = comb(fcol[0], fcol[1], fcol[2], wc);
    }
    S* out = J + 6 * c;
    store4(out, v);
    store3(out + 3, wc);
  };
  for (int t = 0; t < n; ++t) {
    const auto u = static_cast<std::size_t>(t);
    column(K::root_cols + idx[u], w[u], p[u], false);
  }
  if constexpr (K::root_cols > 0) {
    // The free-flyer's unit velocities in root coordinates: root axis c in the world is row c of ⁰X_w's E.
    for (int c = 0; c < 3; ++c) column(c, root_row[c], p0, true);
    for (int c = 0; c < 3; ++c) column(3 + c, root_row[c], p0, false);
  }
}

#endif

/// The one-walk Jacobian of the frame ᶠX_body = `Xf` on `body` at configuration q (full q of the model).
template <class K, class Q, class Out>
void jacobian_walk(const K& k, const Eigen::MatrixBase<Q>& q, int body, Transform<typename Out::Scalar> X,
                   ReferenceFrame rf, Eigen::MatrixBase<Out>& J) {
  using S = typename Out::Scalar;
  J.setZero();
#if SPATIAL_SIMD_AVX2
  using TreeT = typename std::decay_t<decltype(k.tree)>::tree_type;
  if constexpr (simd_candidate<S, TreeT>() && lane_columns<Out>()) {
    if (lane_columns(J) && simd_applies(k.tree) && walk_fits(k.tree, body)) {
      jacobian_walk_simd(k, q, body, X, rf, J.derived().data());
      return;
    }
  }
#endif
  if (walk_fits(k.tree, body)) {
    jacobian_walk_down(k, q, body, X, rf, J);
    return;
  }
  // A chain deeper than kMaxWalkDepth (run-time trees only): from the body up, ᶠX_λ(j) = ᶠX_j ʲX_λ(j), column
  // ᶠX_j Sⱼ (Local); the ancestors' sines and cosines eight at a time (sincos_all vectorises), then the walk over them.
  constexpr int kChunk = 8;
  std::array<int, kChunk> idx;
  std::array<S, kChunk> qc, cc, sc;
  for (int j = body; j >= 0;) {
    int n = 0;
    for (; n < kChunk && j >= 0; ++n, j = k.tree.parent(j)) {
      idx[static_cast<std::size_t>(n)] = j;
      qc[static_cast<std::size_t>(n)] = S(q[K::qoff + j]);
    }
    sincos_all<S>(qc, cc, sc, n);
    for (int t = 0; t < n; ++t) {
      const auto u = static_cast<std::size_t>(t);
      const int i = idx[u];
      const auto joint = k.tree.joint(i);
      set_jacobian_column(J, K::root_cols + i, X.apply(joint.motion(S(1))));  // ᶠX_i Sᵢ
      X = X * joint.compose(qc[u], cc[u], sc[u], k.tree.tree_transform(i));    // ᶠX_λ(i)
    }
  }
  if constexpr (K::root_cols > 0) {
    for (int c = 0; c < 6; ++c) set_jacobian_column(J, c, X.apply(free_flyer_basis<S>(c)));
    X = X * root_transform<S>(q);
  }
  if (rf == ReferenceFrame::Local) return;
  for_each_ancestor_column(k, body, [&](int c) {
    set_jacobian_column(J, c, local_to_frame<S>(rf, X, jacobian_column<S>(J, c)));
  });
}

template <class K>
auto frame_velocity_impl(const K& k, int f, ReferenceFrame rf) {
  int body;
  const auto Xfw = frame_world(k, f, body);
  const auto& fr = k.frames_model().frames()[static_cast<std::size_t>(f)];
  return local_to_frame(rf, Xfw, fr.X.apply(k.velocity(body)));
}
template <class K>
auto frame_acceleration_impl(const K& k, int f, ReferenceFrame rf) {
  int body;
  const auto Xfw = frame_world(k, f, body);
  const auto& fr = k.frames_model().frames()[static_cast<std::size_t>(f)];
  return local_to_frame(rf, Xfw, fr.X.apply(k.acceleration(body)));
}
/// p̈ = a_lin + ω × v_lin in the frame's axes (Local) or world axes, for the frame ᶠX_body = Xf on `body`.
template <class K, class S>
Vector3<S> classical_impl(const K& k, int body, const Transform<S>& Xf, ReferenceFrame rf) {
  const Motion<S> vl = Xf.apply(k.velocity(body));
  const Motion<S> al = Xf.apply(k.acceleration(body));
  const Vector3<S> c = add3(al.v, cross3(vl.w, vl.v));
  if (rf == ReferenceFrame::Local) return c;
  return mul_t((Xf * k.world(body)).E, c);
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------------------------
// Kinematics passes
// ---------------------------------------------------------------------------------------------------------------

/// Forward kinematics with velocities and spatial accelerations (no gravity): `data.X_up`, `data.X_base`,
/// `data.v`, `data.a` (body coordinates). See the top of kinematics.hpp.
template <class S, class T, class Q, class V, class A>
void forward_kinematics(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                        const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  detail::kinematics_pass<true>(model, data, q, v, a);
}
/// Floating base: also `data.X0`, the root's `data.v0` = v[0:6] and `data.a0` = a[0:6] (root coordinates; no
/// gravity), the tree's `data.tree.v`, `data.tree.a`.
template <class S, class T, class Q, class V, class A>
void forward_kinematics(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                        const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  detail::kinematics_pass<true>(model, data, q, v, a);
}

// ---------------------------------------------------------------------------------------------------------------
// Jacobians
// ---------------------------------------------------------------------------------------------------------------

/// Forward kinematics and every joint's motion subspace in world coordinates: `data.J` (6 × nv, World, rows linear
/// first). Returns `data.J`.
template <class S, class T, class Q>
const auto& compute_joint_jacobians(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  forward_kinematics(model, data, q);
  detail::joint_jacobian_columns<false>(detail::kin(model, data));
  return data.J;
}
template <class S, class T, class Q>
const auto& compute_joint_jacobians(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                    const Eigen::MatrixBase<Q>& q) {
  forward_kinematics(model, data, q);
  detail::joint_jacobian_columns<false>(detail::kin(model, data));
  return data.J;
}

/// The Jacobian of body `body` (−1: the base or root) in `rf`, from `data.J` after `compute_joint_jacobians` (or
/// `compute_joint_jacobians_time_variation`). `J`: 6 × nv, written (const& so that blocks can be passed).
template <class S, class T, class Out>
void body_jacobian(const Model<S, T>& model, const Data<S, T>& data, int body, ReferenceFrame rf,
                   const Eigen::MatrixBase<Out>& J) {
  const auto k = detail::kin(model, data);
  if (rf != ReferenceFrame::Local)
    return detail::jacobian_from_world_at(k, body, k.point_world(body, Vector3<S>::Zero()), rf,
                                          const_cast<Eigen::MatrixBase<Out>&>(J));
  detail::jacobian_from_world(k, body, k.world(body), rf, const_cast<Eigen::MatrixBase<Out>&>(J));
}
template <class S, class T, class Out>
void body_jacobian(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int body, ReferenceFrame rf,
                   const Eigen::MatrixBase<Out>& J) {
  const auto k = detail::kin(model, data);
  if (rf != ReferenceFrame::Local)
    return detail::jacobian_from_world_at(k, body, k.point_world(body, Vector3<S>::Zero()), rf,
                                          const_cast<Eigen::MatrixBase<Out>&>(J));
  detail::jacobian_from_world(k, body, k.world(body), rf, const_cast<Eigen::MatrixBase<Out>&>(J));
}
/// The Jacobian of fixed frame `frame` in `rf`, from `data.J` after `compute_joint_jacobians`.
template <class S, class T, class Out>
void frame_jacobian(const Model<S, T>& model, const Data<S, T>& data, int frame, ReferenceFrame rf,
                    const Eigen::MatrixBase<Out>& J) {
  const auto k = detail::kin(model, data);
  if (rf != ReferenceFrame::Local) {
    const FixedFrame<S>& fr = k.frames_model().frames()[static_cast<std::size_t>(frame)];
    return detail::jacobian_from_world_at(k, fr.body, k.point_world(fr.body, fr.X.r), rf,
                                          const_cast<Eigen::MatrixBase<Out>&>(J));
  }
  int body;
  const Transform<S> X = detail::frame_world(k, frame, body);
  detail::jacobian_from_world(k, body, X, rf, const_cast<Eigen::MatrixBase<Out>&>(J));
}
template <class S, class T, class Out>
void frame_jacobian(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int frame, ReferenceFrame rf,
                    const Eigen::MatrixBase<Out>& J) {
  const auto k = detail::kin(model, data);
  if (rf != ReferenceFrame::Local) {
    const FixedFrame<S>& fr = k.frames_model().frames()[static_cast<std::size_t>(frame)];
    return detail::jacobian_from_world_at(k, fr.body, k.point_world(fr.body, fr.X.r), rf,
                                          const_cast<Eigen::MatrixBase<Out>&>(J));
  }
  int body;
  const Transform<S> X = detail::frame_world(k, frame, body);
  detail::jacobian_from_world(k, body, X, rf, const_cast<Eigen::MatrixBase<Out>&>(J));
}

/// The Jacobian of body `body` in `rf` at q in one walk from the body to the root (only its ancestors' transforms
/// are computed; `data` is not used beyond the call's arguments). `J`: 6 × nv.
template <class S, class T, class Q, class Out>
void compute_body_jacobian(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q, int body,
                           ReferenceFrame rf, const Eigen::MatrixBase<Out>& J) {
  detail::check_sizes(model, "compute_body_jacobian", "q", q);
  detail::jacobian_walk(detail::kin(model, data), q, body, Transform<S>::Identity(), rf,
                        const_cast<Eigen::MatrixBase<Out>&>(J));
}
template <class S, class T, class Q, class Out>
void compute_body_jacobian(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                           int body, ReferenceFrame rf, const Eigen::MatrixBase<Out>& J) {
  detail::check_q(model, q, "compute_body_jacobian");
  detail::jacobian_walk(detail::kin(model, data), q, body, Transform<S>::Identity(), rf,
                        const_cast<Eigen::MatrixBase<Out>&>(J));
}
/// The Jacobian of fixed frame `frame` in `rf` at q in one walk (Pinocchio's computeFrameJacobian).
template <class S, class T, class Q, class Out>
void compute_frame_jacobian(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q, int frame,
                            ReferenceFrame rf, const Eigen::MatrixBase<Out>& J) {
  detail::check_sizes(model, "compute_frame_jacobian", "q", q);
  const FixedFrame<S>& fr = model.frames()[static_cast<std::size_t>(frame)];
  detail::jacobian_walk(detail::kin(model, data), q, fr.body, fr.X, rf, const_cast<Eigen::MatrixBase<Out>&>(J));
}
template <class S, class T, class Q, class Out>
void compute_frame_jacobian(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                            const Eigen::MatrixBase<Q>& q, int frame, ReferenceFrame rf,
                            const Eigen::MatrixBase<Out>& J) {
  detail::check_q(model, q, "compute_frame_jacobian");
  const FixedFrame<S>& fr = model.tree().frames()[static_cast<std::size_t>(frame)];
  detail::jacobian_walk(detail::kin(model, data), q, fr.body, fr.X, rf, const_cast<Eigen::MatrixBase<Out>&>(J));
}

// ---------------------------------------------------------------------------------------------------------------
// Velocities and accelerations (after forward_kinematics(q, v, a))
// ---------------------------------------------------------------------------------------------------------------

/// Spatial velocity of body `body` (−1: base/root) in `rf`, after `forward_kinematics(q, v, a)` (or any pass that
/// leaves the velocities: `compute_joint_jacobians_time_variation`, `frame_jdot_qdot`, RNEA).
template <class S, class T>
Motion<S> body_velocity(const Model<S, T>& model, const Data<S, T>& data, int body, ReferenceFrame rf) {
  const auto k = detail::kin(model, data);
  return detail::local_to_frame(rf, k.world(body), k.velocity(body));
}
template <class S, class T>
Motion<S> body_velocity(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int body,
                        ReferenceFrame rf) {
  const auto k = detail::kin(model, data);
  return detail::local_to_frame(rf, k.world(body), k.velocity(body));
}
template <class S, class T>
Motion<S> frame_velocity(const Model<S, T>& model, const Data<S, T>& data, int frame, ReferenceFrame rf) {
  return detail::frame_velocity_impl(detail::kin(model, data), frame, rf);
}
template <class S, class T>
Motion<S> frame_velocity(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int frame,
                         ReferenceFrame rf) {
  return detail::frame_velocity_impl(detail::kin(model, data), frame, rf);
}

/// Spatial acceleration (no gravity) of body `body` in `rf`, after `forward_kinematics(q, v, a)`.
template <class S, class T>
Motion<S> body_acceleration(const Model<S, T>& model, const Data<S, T>& data, int body, ReferenceFrame rf) {
  const auto k = detail::kin(model, data);
  return detail::local_to_frame(rf, k.world(body), k.acceleration(body));
}
template <class S, class T>
Motion<S> body_acceleration(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int body,
                            ReferenceFrame rf) {
  const auto k = detail::kin(model, data);
  return detail::local_to_frame(rf, k.world(body), k.acceleration(body));
}
template <class S, class T>
Motion<S> frame_acceleration(const Model<S, T>& model, const Data<S, T>& data, int frame, ReferenceFrame rf) {
  return detail::frame_acceleration_impl(detail::kin(model, data), frame, rf);
}
template <class S, class T>
Motion<S> frame_acceleration(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int frame,
                             ReferenceFrame rf) {
  return detail::frame_acceleration_impl(detail::kin(model, data), frame, rf);
}

/// Classical acceleration p̈ = a_lin + ω × v_lin of the frame's origin (no gravity), in the frame's axes (Local) or
/// world axes (World, LocalWorldAligned), after `forward_kinematics(q, v, a)`.
template <class S, class T>
Vector3<S> frame_classical_acceleration(const Model<S, T>& model, const Data<S, T>& data, int frame,
                                        ReferenceFrame rf) {
  const FixedFrame<S>& fr = model.frames()[static_cast<std::size_t>(frame)];
  return detail::classical_impl(detail::kin(model, data), fr.body, fr.X, rf);
}
template <class S, class T>
Vector3<S> frame_classical_acceleration(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int frame,
                                        ReferenceFrame rf) {
  const FixedFrame<S>& fr = model.tree().frames()[static_cast<std::size_t>(frame)];
  return detail::classical_impl(detail::kin(model, data), fr.body, fr.X, rf);
}
/// The same for a body's origin.
template <class S, class T>
Vector3<S> body_classical_acceleration(const Model<S, T>& model, const Data<S, T>& data, int body,
                                       ReferenceFrame rf) {
  return detail::classical_impl(detail::kin(model, data), body, Transform<S>::Identity(), rf);
}
template <class S, class T>
Vector3<S> body_classical_acceleration(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int body,
                                       ReferenceFrame rf) {
  return detail::classical_impl(detail::kin(model, data), body, Transform<S>::Identity(), rf);
}

// ---------------------------------------------------------------------------------------------------------------
// Time variation
// ---------------------------------------------------------------------------------------------------------------

/// Forward kinematics, velocities, drift accelerations (v̇ = 0), `data.J` and `data.dJ` = J̇ (World, 6 × nv).
/// Returns `data.dJ`.
template <class S, class T, class Q, class V>
const auto& compute_joint_jacobians_time_variation(const Model<S, T>& model, Data<S, T>& data,
                                                   const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v) {
  detail::kinematics_pass<false>(model, data, q, v, v);
  detail::joint_jacobian_columns<true>(detail::kin(model, data));
  return data.dJ;
}
template <class S, class T, class Q, class V>
const auto& compute_joint_jacobians_time_variation(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                                   const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v) {
  detail::kinematics_pass<false>(model, data, q, v, v);
  detail::joint_jacobian_columns<true>(detail::kin(model, data));
  return data.dJ;
}

/// d/dt of `body_jacobian(rf)` from `data.J`, `data.dJ` after `compute_joint_jacobians_time_variation`.
template <class S, class T, class Out>
void body_jacobian_time_variation(const Model<S, T>& model, const Data<S, T>& data, int body, ReferenceFrame rf,
                                  const Eigen::MatrixBase<Out>& dJ) {
  const auto k = detail::kin(model, data);
  detail::jacobian_time_variation_from_world(k, body, k.world(body), rf, const_cast<Eigen::MatrixBase<Out>&>(dJ));
}
template <class S, class T, class Out>
void body_jacobian_time_variation(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int body,
                                  ReferenceFrame rf, const Eigen::MatrixBase<Out>& dJ) {
  const auto k = detail::kin(model, data);
  detail::jacobian_time_variation_from_world(k, body, k.world(body), rf, const_cast<Eigen::MatrixBase<Out>&>(dJ));
}
/// d/dt of `frame_jacobian(rf)` after `compute_joint_jacobians_time_variation`.
template <class S, class T, class Out>
void frame_jacobian_time_variation(const Model<S, T>& model, const Data<S, T>& data, int frame, ReferenceFrame rf,
                                   const Eigen::MatrixBase<Out>& dJ) {
  const auto k = detail::kin(model, data);
  int body;
  const Transform<S> X = detail::frame_world(k, frame, body);
  detail::jacobian_time_variation_from_world(k, body, X, rf, const_cast<Eigen::MatrixBase<Out>&>(dJ));
}
template <class S, class T, class Out>
void frame_jacobian_time_variation(const FloatingModel<S, T>& model, const FloatingData<S, T>& data, int frame,
                                   ReferenceFrame rf, const Eigen::MatrixBase<Out>& dJ) {
  const auto k = detail::kin(model, data);
  int body;
  const Transform<S> X = detail::frame_world(k, frame, body);
  detail::jacobian_time_variation_from_world(k, body, X, rf, const_cast<Eigen::MatrixBase<Out>&>(dJ));
}

/// The drift: the frame's **spatial** acceleration at v̇ = 0 in `rf` (a Motion, angular first). Equals J̇ v for
/// Local and World; for LocalWorldAligned J̇ v has the classical linear part instead (see the top of the file).
/// Runs forward_kinematics(q, v, 0).
template <class S, class T, class Q, class V>
Motion<S> frame_jdot_qdot(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                          const Eigen::MatrixBase<V>& v, int frame, ReferenceFrame rf) {
  detail::kinematics_pass<false>(model, data, q, v, v);
  return frame_acceleration(model, data, frame, rf);
}
template <class S, class T, class Q, class V>
Motion<S> frame_jdot_qdot(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                          const Eigen::MatrixBase<V>& v, int frame, ReferenceFrame rf) {
  detail::kinematics_pass<false>(model, data, q, v, v);
  return frame_acceleration(model, data, frame, rf);
}
/// The **classical** acceleration p̈ of the frame's origin at v̇ = 0 (Vector3; frame axes for Local, world axes
/// otherwise) = the linear rows of J̇_LWA v (rotated to the frame's axes for Local).
template <class S, class T, class Q, class V>
Vector3<S> frame_classical_jdot_qdot(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                     const Eigen::MatrixBase<V>& v, int frame, ReferenceFrame rf) {
  detail::kinematics_pass<false>(model, data, q, v, v);
  return frame_classical_acceleration(model, data, frame, rf);
}
template <class S, class T, class Q, class V>
Vector3<S> frame_classical_jdot_qdot(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                     const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, int frame,
                                     ReferenceFrame rf) {
  detail::kinematics_pass<false>(model, data, q, v, v);
  return frame_classical_acceleration(model, data, frame, rf);
}

}  // namespace spatial

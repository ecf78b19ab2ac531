#pragma once
/// \file centroidal.hpp
/// Centre of mass (position, velocity, acceleration, per subtree), its Jacobian, and centroidal dynamics: the
/// centroidal momentum matrix A_G, the momentum h_G = A_G v, its rate ḣ_G and Ȧ_G v, and the centroidal composite
/// inertia I_G (Orin, Goswami & Lee, "Centroidal dynamics of a humanoid robot", Auton. Robots 35, 2013; Pinocchio's
/// `ccrba`, `jacobianCenterOfMass`, `computeCentroidalMomentumTimeVariation`).
///
/// Frames. Fixed base: everything in **base coordinates** (body −1), over the moving bodies only (the base and
/// the mass merged into it do not move; this is `center_of_mass(model, data, q)`'s convention). Floating base:
/// **world coordinates**, over the root body and every body of the tree. The centroidal frame G has its origin at
/// the centre of mass c and the base (world) axes.
///
/// Ordering. The 6-vectors and the rows of A_G are **linear first**: h_G = [p; k_G] with p = M ċ the linear
/// momentum and k_G the angular momentum about c (Pinocchio's order, the free-flyer's order), while `Motion` and
/// `Force` objects stay angular first. A floating model's first six columns follow v's free-flyer order
/// (linear velocity of the root, then its angular velocity, both in root coordinates).
///
/// Method (one pass each, no allocation, no exception):
///  - CoM Jacobian: the subtree masses mⱼ and first moments hⱼ = Σ_subtree mₖ cₖ in base coordinates, accumulated
///    leaves to root; joint j with motion subspace Sⱼ = (ω, v_O) in base coordinates moves its subtree's linear
///    momentum by mⱼ v_O + ω × hⱼ, so column j of J_c is (mⱼ v_O + ω × hⱼ) / M.
///  - A_G: the first two passes of CRBA (the kernels of simd.hpp where they apply), without H: composite inertias
///    Iᶜⱼ summed leaves to root in body coordinates; column j is Fⱼ⁰ = ʲX_0ᵀ Iᶜⱼ Sⱼ (the subtree's momentum for a
///    unit rate of joint j, a force about the base origin in base coordinates) moved to c: k_G = n_O − c × f. The
///    total mass and first moment come from the roots' composite inertias moved to the base.
///  - I_G: every body's inertia in base coordinates, summed.
///  - h_G, ḣ_G, Ȧ_G v: body velocities vᵢ and accelerations aᵢ (no gravity) as in RNEA; each body's momentum Iᵢ vᵢ
///    and net force Iᵢ aᵢ + vᵢ ×* Iᵢ vᵢ summed in base coordinates and moved to c. The sum of net forces is the
///    rate of the momentum about the fixed base origin, and moving it to c gives ḣ_G because ċ × M ċ = 0.
///    Ȧ_G v is the same with v̇ = 0 (velocity-product accelerations only).
/// A floating model runs these on the tree in root coordinates (with the root body added), then rotates by the
/// root's orientation R: a vector x in root coordinates is R x in the world, and c_world = p_root + R c_root.
///
/// Scratch. The functions use the buffers of `Data` (for a floating model, of `data.tree`): `X_up`, `X_base`
/// (forward kinematics), `Ic` (base — root — coordinates: after the CoM and Jacobian functions `Ic[i].m` and
/// `Ic[i].h` are the mass and first moment of body i's subtree, `Ic[i].I` is not computed; after the A_G functions
/// `Ic[i]` is the composite inertia of the subtree in body coordinates, as CRBA leaves it; after the I_G functions,
/// in base coordinates), `S_base` (motion subspaces in base coordinates), `v`, `a` (accelerations without gravity), `c` (the
/// velocity-product accelerations of Ȧ_G v) and `tmp` (subtree flags of `subtree_com_jacobian`). Results:
/// `data.com`, `data.vcom`, `data.acom` (base coordinates for `Data`, world coordinates for `FloatingData`).
/// A model of zero total mass (or a massless subtree, for the subtree functions) gives non-finite results.

#include "spatial/algebra.hpp"
#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"
#include "spatial/model.hpp"

#include <cstddef>

namespace spatial {

/// Mass and centre of mass of a subtree (`subtree_center_of_mass`).
template <class S>
struct SubtreeCom {
  S mass;
  Vector3<S> com;
};

/// `centroidal_momentum_time_variation`'s results, linear first: ḣ_G (the rate of the centroidal momentum) and
/// Ȧ_G v (its velocity-product part, ḣ_G at v̇ = 0).
template <class S>
struct CentroidalMomentumRate {
  Vector6<S> dhg;
  Vector6<S> dAg_v;
};

namespace detail {

/// Mass and first moment of every subtree, in base coordinates, into `data.Ic[i].m` and `.h` (after forward
/// kinematics). Returns the total over the tree's roots (the root body of a floating model excluded) as an
/// `Inertia` with only m and h set.
template <class S, class T>
Inertia<S> subtree_first_moments(const Model<S, T>& model, Data<S, T>& data) {
  for_each_body(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const Transform<S>& X = data.X_base[k];
    const Inertia<S>& In = model.inertia(int(I));
    data.Ic[k].m = In.m;
    data.Ic[k].h = add3(scale3(In.m, X.r), mul_t(X.E, In.h));
  });
  Inertia<S> total = Inertia<S>::Zero();
  for_each_body_reverse(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const int p = model.parent(I);
    Inertia<S>& target = p >= 0 ? data.Ic[static_cast<std::size_t>(p)] : total;
    target.m += data.Ic[k].m;
    target.h = add3(target.h, data.Ic[k].h);
  });
  return total;
}

/// The composite inertia of every subtree in base coordinates into `data.Ic` (after `forward_kinematics(model, data,
/// q)`, on which it relies). Returns the sum over the tree's roots.
template <class S, class T>
Inertia<S> composite_inertias_base(const Model<S, T>& model, Data<S, T>& data) {
  for_each_body(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    data.Ic[k] = model.inertia(int(I)).transformed_inverse(data.X_base[k]);
  });
  Inertia<S> total = Inertia<S>::Zero();
  for_each_body_reverse(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const int p = model.parent(I);
    if (p >= 0) data.Ic[static_cast<std::size_t>(p)] += data.Ic[k];
    else total += data.Ic[k];
  });
  return total;
}

/// What `momentum_pass` sums, in base coordinates about the base origin (angular first).
template <class S>
struct MomentumSums {
  S m;
  Vector3<S> h;     ///< first moment Σ mᵢ cᵢ
  Force<S> mom;     ///< Σ Iᵢ vᵢ: spatial momentum
  Force<S> rate;    ///< Σ Iᵢ aᵢ + vᵢ ×* Iᵢ vᵢ (aᵢ without gravity)
  Force<S> bias;    ///< the same with v̇ = 0
};

/// One forward pass over the tree: transforms (`X_up`, `X_base`), velocities `data.v` from the root's `v0`
/// (R = floating; a fixed base does not move), with `Acc` accelerations `data.a` (no gravity) from the root's
/// `a0`, with `Bias` the accelerations at v̇ = 0 in `data.c`; the bodies' mass, first moment, momentum and net
/// forces summed in base coordinates (the root body of a floating model not included).
template <bool R, bool Acc, bool Bias, class S, class T, class Q, class V, class A>
MomentumSums<S> momentum_pass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                              const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, const Motion<S>& v0,
                              const Motion<S>& a0) {
  (void)a, (void)v0, (void)a0;
  if constexpr (Acc) check_sizes(model, "centroidal", "q", q, "v", v, "a", a);
  else check_sizes(model, "centroidal", "q", q, "v", v);
  MomentumSums<S> out{S(0), Vector3<S>::Zero(), Force<S>::Zero(), Force<S>::Zero(), Force<S>::Zero()};
  joint_sincos(model, data, q);
  for_each_body(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const auto pk = static_cast<std::size_t>(p);
    const auto joint = model.joint(I);
    update_transform<true>(model, data, I, q);
    const Transform<S>& Xup = data.X_up[k];
    const S qd = S(v[i]);
    const Motion<S> vJ = joint.motion(qd);
    if constexpr (R) data.v[k] = Xup.apply(p >= 0 ? data.v[pk] : v0) + vJ;
    else data.v[k] = p >= 0 ? Xup.apply(data.v[pk]) + vJ : vJ;
    const Motion<S> cJ = joint.cross_motion(data.v[k], qd);
    if constexpr (Acc) {
      if constexpr (R) data.a[k] = Xup.apply(p >= 0 ? data.a[pk] : a0) + cJ;
      else data.a[k] = p >= 0 ? Xup.apply(data.a[pk]) + cJ : cJ;
      joint.add_motion(data.a[k], S(a[i]));
    }
    if constexpr (Bias) data.c[k] = p >= 0 ? Xup.apply(data.c[pk]) + cJ : cJ;
    const Inertia<S>& In = model.inertia(i);
    const Transform<S>& Xb = data.X_base[k];
    out.m += In.m;
    out.h = add3(out.h, add3(scale3(In.m, Xb.r), mul_t(Xb.E, In.h)));
    const Force<S> Iv = In * data.v[k];
    out.mom += Xb.apply_force_inverse(Iv);
    if constexpr (Acc || Bias) {
      const Force<S> vIv = cross(data.v[k], Iv);
      if constexpr (Acc) out.rate += Xb.apply_force_inverse(In * data.a[k] + vIv);
      if constexpr (Bias) out.bias += Xb.apply_force_inverse(In * data.c[k] + vIv);
    }
  });
  return out;
}

/// The root body's share of `momentum_pass` (root coordinates).
template <bool Acc, bool Bias, class S>
void add_root_body(MomentumSums<S>& s, const Inertia<S>& I0, const Motion<S>& v0, const Motion<S>& a0) {
  (void)a0;
  s.m += I0.m;
  s.h += I0.h;
  const Force<S> Iv = I0 * v0;
  s.mom += Iv;
  const Force<S> vIv = cross(v0, Iv);
  if constexpr (Acc) s.rate += I0 * a0 + vIv;
  if constexpr (Bias) s.bias += vIv;
}

/// Column j of the (subtree) CoM Jacobian in base coordinates: (m v_O + ω × h) / m_b for the motion subspace
/// s = (ω, v_O) and the subtree (m, h).
template <class S>
SPATIAL_INLINE Vector3<S> com_column(const Motion<S>& s, S m, const Vector3<S>& h, S inv_mb) {
  return scale3(inv_mb, add3(scale3(m, s.v), cross3(s.w, h)));
}

/// The (subtree) CoM Jacobian of the tree in base coordinates into columns offset … offset + n − 1 of `Jc`, each
/// column multiplied by `E` (identity or the root's rotation R); after `subtree_first_moments`. `body` < 0: the
/// whole tree (every column uses its own subtree), with total mass `mb`; otherwise body's subtree, of mass `mb`
/// and first moment `hb`, and the flags in `data.tmp` (1: in the subtree, 2: strict ancestor, 0: neither).
template <bool Rotate, class S, class T, class J>
void tree_com_columns(const Model<S, T>& model, Data<S, T>& data, int body, S mb, const Vector3<S>& hb,
                      const Matrix3<S>& E, int offset, J& Jc) {
  (void)E;
  const S inv_mb = S(1) / mb;
  const bool have_s = simd_applies(model);  // the AVX2 forward kinematics has left S_base
  for_each_body(model, [&](auto I) {
    const int j = I;
    const auto k = static_cast<std::size_t>(j);
    const Motion<S> s = have_s ? data.S_base[k] : model.joint(I).subspace_inverse(data.X_base[k]);
    Vector3<S> col;
    if (body < 0 || data.tmp[j] == S(1)) col = com_column(s, data.Ic[k].m, data.Ic[k].h, inv_mb);
    else if (data.tmp[j] == S(2)) col = com_column(s, mb, hb, inv_mb);
    else col = Vector3<S>::Zero();
    if constexpr (Rotate) Jc.template block<3, 1>(0, offset + j) = mul(E, col);
    else Jc.template block<3, 1>(0, offset + j) = col;
  });
}

/// Marks body's subtree (1) and its strict ancestors (2) in `data.tmp`, the others 0.
template <class S, class T>
void mark_subtree(const Model<S, T>& model, Data<S, T>& data, int body) {
  for (int k = 0; k < model.size(); ++k) {
    const int p = model.parent(k);
    data.tmp[k] = (k == body || (p >= 0 && data.tmp[p] == S(1))) ? S(1) : S(0);
  }
  for (int k = body >= 0 ? model.parent(body) : -1; k >= 0; k = model.parent(k)) data.tmp[k] = S(2);
}

/// `crba_impl`'s sink for A_G (no entry of H is computed): column offset + i of A_G (linear first) takes body i's
/// Fᵢ⁰ = ⁱX_0ᵀ Iᶜᵢ Sᵢ, the subtree's momentum for a unit rate of joint i, in base coordinates about the base origin;
/// `centroidal_columns` then moves it to the centroidal frame. `*total` takes the whole tree's inertia in base
/// coordinates (the roots' composite inertias moved there and summed).
template <class S, class AG>
struct MomentumColumns {
  static constexpr bool active = true;
  static constexpr bool entries = false;
  static constexpr bool sums_roots = true;
  AG& Ag;
  int offset;
  Inertia<S>* total;
  SPATIAL_INLINE void roots(const Inertia<S>& sum) const { *total = sum; }
  SPATIAL_INLINE void operator()(int i, const Force<S>& F0) const {
    Ag.template block<3, 1>(0, offset + i) = F0.f;
    Ag.template block<3, 1>(3, offset + i) = F0.n;
  }
};

/// Columns offset … offset + n − 1 of A_G by the tree's CRBA without H: the composite inertias (body coordinates,
/// as `crba` leaves them in `data.Ic`) and every column's force about the base origin (`MomentumColumns`), still to
/// be moved to the centroidal frame by `centroidal_columns`. Returns the composite inertia of the whole tree in base
/// coordinates (the roots' composite inertias moved there).
template <class S, class T, class Q, class AG>
Inertia<S> base_momentum_columns(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                 int offset, AG& Ag) {
  crba_inputs(model, data, q);
  Inertia<S> total = Inertia<S>::Zero();
  crba_impl(model, data, MomentumColumns<S, AG>{Ag, offset, &total});
  return total;
}

/// Moves columns offset … offset + n − 1 of A_G (linear first: forces about the base origin, base coordinates) to
/// the centroidal frame XG = ᴳX_base: f′ = E f, n′ = E (n − r × f). With AVX2 and a column-major A_G whose columns
/// are contiguous (a plain matrix, a Map or Ref of one), four lanes per 3-vector (simd.hpp); otherwise scalar.
template <class S, class AG>
void centroidal_columns(const Transform<S>& XG, int offset, int n, AG& Ag) {
#if SPATIAL_SIMD_AVX2
  if constexpr (lane_columns<AG>()) {
    if (lane_columns(Ag)) {
      simd::move_force_columns(XG, Ag.derived().data(), offset, n);
      return;
    }
  }
#endif
  for (int c = offset; c < offset + n; ++c) {
    const Force<S> F = XG.apply_force(
        Force<S>(Vector3<S>(Ag.template block<3, 1>(3, c)), Vector3<S>(Ag.template block<3, 1>(0, c))));
    Ag.template block<3, 1>(0, c) = F.f;
    Ag.template block<3, 1>(3, c) = F.n;
  }
}

/// The free-flyer's six columns of A_G, from the composite inertia of the whole robot at the root, Ic0 = (m, h = m c,
/// Ī) in root coordinates, and R (root axes → world axes). A unit root motion (linear first) carries the momentum
/// Ic0 u; moved to the CoM and turned to world axes it is
///   linear rates:  [m R; 0]             (a translation has no angular momentum about the CoM)
///   angular rates: [−R h̃; R Ī_c]       (Ī_c = Ī − h̃ h̃ᵀ / m: the rotational inertia about the CoM)
template <class S, class AG>
void root_centroidal_columns(const Inertia<S>& Ic0, const Matrix3<S>& R, AG& Ag) {
  Ag.template block<3, 3>(0, 0) = Ic0.m * R;
  Ag.template block<3, 3>(3, 0).setZero();
  Ag.template block<3, 3>(0, 3) = -(R * skew(Ic0.h));
  Ag.template block<3, 3>(3, 3) = R * Ic0.inertia_com();
}

/// I_G (linear first) from the whole robot's inertia in base coordinates moved to the centroidal frame XG:
/// [M 1, h̃ᵀ; h̃, Ī] with h = 0 up to rounding.
template <class S>
Matrix6<S> centroidal_inertia_matrix(const Inertia<S>& total, const Transform<S>& XG) {
  const Inertia<S> IG = total.transformed(XG);
  Matrix6<S> out;
  const Matrix3<S> hx = skew(IG.h);
  out.template topLeftCorner<3, 3>() = IG.m * Matrix3<S>::Identity();
  out.template topRightCorner<3, 3>() = hx.transpose();
  out.template bottomLeftCorner<3, 3>() = hx;
  out.template bottomRightCorner<3, 3>() = IG.I;
  return out;
}

template <class Out>
Eigen::MatrixBase<Out>& out_arg(const Eigen::MatrixBase<Out>& x) {
  return const_cast<Eigen::MatrixBase<Out>&>(x);
}

/// Root-coordinate → world quantities of a floating model (after `data.X0` is set).
template <class S, class T>
SPATIAL_INLINE Matrix3<S> root_rotation(const FloatingData<S, T>& data) {
  return data.X0.E.transpose();
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------------------------
// Fixed base (base coordinates, the moving bodies)
// ---------------------------------------------------------------------------------------------------------------

/// Centre of mass and its velocity: `data.com`, `data.vcom` (base coordinates). Returns `data.com`.
template <class S, class T, class Q, class V>
const Vector3<S>& center_of_mass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                 const Eigen::MatrixBase<V>& v) {
  const auto s = detail::momentum_pass<false, false, false>(model, data, q, v, v, Motion<S>::Zero(),
                                                            Motion<S>::Zero());
  data.com = s.h / s.m;
  data.vcom = s.mom.f / s.m;
  return data.com;
}

/// Centre of mass, its velocity and its acceleration for v̇ = a: `data.com`, `data.vcom`, `data.acom` (base
/// coordinates). Returns `data.com`.
template <class S, class T, class Q, class V, class A>
const Vector3<S>& center_of_mass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                 const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  const auto s = detail::momentum_pass<false, true, false>(model, data, q, v, a, Motion<S>::Zero(),
                                                           Motion<S>::Zero());
  data.com = s.h / s.m;
  data.vcom = s.mom.f / s.m;
  data.acom = s.rate.f / s.m;
  return data.com;
}

/// Mass and centre of mass (base coordinates) of body's subtree (body −1: every moving body). Leaves every
/// subtree's mass and first moment in `data.Ic[i].m`, `.h` (base coordinates).
template <class S, class T, class Q>
SubtreeCom<S> subtree_center_of_mass(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                     int body) {
  forward_kinematics(model, data, q);
  const Inertia<S> total = detail::subtree_first_moments(model, data);
  const Inertia<S>& sub = body >= 0 ? data.Ic[static_cast<std::size_t>(body)] : total;
  return SubtreeCom<S>{sub.m, sub.h / sub.m};
}

/// CoM Jacobian J_c (3 × n, base coordinates): ċ = J_c q̇. Also `data.com`.
template <class S, class T, class Q, class J>
void com_jacobian(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                  const Eigen::MatrixBase<J>& Jc_) {
  auto& Jc = detail::out_arg(Jc_);
  forward_kinematics(model, data, q);
  const Inertia<S> total = detail::subtree_first_moments(model, data);
  data.com = total.h / total.m;
  detail::tree_com_columns<false>(model, data, -1, total.m, total.h, Matrix3<S>(Matrix3<S>::Identity()), 0, Jc);
}

/// Jacobian of the centre of mass of body's subtree (3 × n, base coordinates; body −1: every moving body).
/// Columns of joints neither in the subtree nor above it are zero.
template <class S, class T, class Q, class J>
void subtree_com_jacobian(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q, int body,
                          const Eigen::MatrixBase<J>& Jc_) {
  auto& Jc = detail::out_arg(Jc_);
  forward_kinematics(model, data, q);
  const Inertia<S> total = detail::subtree_first_moments(model, data);
  const Inertia<S>& sub = body >= 0 ? data.Ic[static_cast<std::size_t>(body)] : total;
  if (body >= 0) detail::mark_subtree(model, data, body);
  detail::tree_com_columns<false>(model, data, body, sub.m, sub.h, Matrix3<S>(Matrix3<S>::Identity()), 0, Jc);
}

/// Centroidal momentum matrix A_G (6 × n, linear first, base axes, angular momentum about the CoM): h_G = A_G q̇.
/// Also `data.com`.
template <class S, class T, class Q, class AG>
void centroidal_momentum_matrix(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                const Eigen::MatrixBase<AG>& Ag_) {
  auto& Ag = detail::out_arg(Ag_);
  detail::check_sizes(model, "centroidal_momentum_matrix", "q", q);
  const Inertia<S> total = detail::base_momentum_columns(model, data, q, 0, Ag);
  data.com = total.h / total.m;
  detail::centroidal_columns(Transform<S>(Matrix3<S>::Identity(), data.com), 0, model.size(), Ag);
}

/// Centroidal momentum h_G = [M ċ; k_G] (linear first, base axes, angular momentum about the CoM). Also
/// `data.com`, `data.vcom`.
template <class S, class T, class Q, class V>
Vector6<S> centroidal_momentum(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                               const Eigen::MatrixBase<V>& v) {
  const auto s = detail::momentum_pass<false, false, false>(model, data, q, v, v, Motion<S>::Zero(),
                                                            Motion<S>::Zero());
  data.com = s.h / s.m;
  data.vcom = s.mom.f / s.m;
  return detail::linear_first(xlt(data.com).apply_force(s.mom));
}

/// ḣ_G for q̈ = a and Ȧ_G q̇ (linear first, base axes, about the CoM). Gravity is not included: ḣ_G is the rate of
/// the momentum, i.e. the sum of the external forces on the moving bodies (the base's reaction and the weight).
/// Also `data.com`, `data.vcom`, `data.acom`.
template <class S, class T, class Q, class V, class A>
CentroidalMomentumRate<S> centroidal_momentum_time_variation(const Model<S, T>& model, Data<S, T>& data,
                                                             const Eigen::MatrixBase<Q>& q,
                                                             const Eigen::MatrixBase<V>& v,
                                                             const Eigen::MatrixBase<A>& a) {
  const auto s = detail::momentum_pass<false, true, true>(model, data, q, v, a, Motion<S>::Zero(),
                                                          Motion<S>::Zero());
  data.com = s.h / s.m;
  data.vcom = s.mom.f / s.m;
  data.acom = s.rate.f / s.m;
  const Transform<S> XG = xlt(data.com);
  return CentroidalMomentumRate<S>{detail::linear_first(XG.apply_force(s.rate)),
                                   detail::linear_first(XG.apply_force(s.bias))};
}

/// Centroidal composite inertia I_G (6 × 6, linear first: [M 1, 0; 0, I_c]): the inertia of the moving bodies
/// about their CoM, base axes. Also `data.com`.
template <class S, class T, class Q>
Matrix6<S> centroidal_composite_inertia(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q) {
  forward_kinematics(model, data, q);
  const Inertia<S> total = detail::composite_inertias_base(model, data);
  data.com = total.h / total.m;
  return detail::centroidal_inertia_matrix(total, xlt(data.com));
}

// ---------------------------------------------------------------------------------------------------------------
// Floating base (world coordinates, the root body and the tree)
// ---------------------------------------------------------------------------------------------------------------

namespace detail {
template <bool Acc, bool Bias, class S, class T, class Q, class V, class A>
MomentumSums<S> floating_momentum(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                  const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                  const Eigen::MatrixBase<A>& a) {
  constexpr int NJ = FloatingModel<S, T>::NJ;
  const int n = model.njoints();
  check_q(model, q, "centroidal");
  check_v(model, v, "centroidal", "v");
  if constexpr (Acc) check_v(model, a, "centroidal", "a");
  data.X0 = root_transform<S>(q);
  data.v0 = root_motion(v).template cast<S>();
  Motion<S> a0 = Motion<S>::Zero();
  if constexpr (Acc) a0 = root_motion(a).template cast<S>();
  const auto qj = joint_block<NJ>(q, 7, n);
  const auto vj = joint_block<NJ>(v, 6, n);
  const auto aj = joint_block<NJ>(a, 6, n);
  auto s = momentum_pass<true, Acc, Bias>(model.tree(), data.tree, qj, vj, aj, data.v0, a0);
  add_root_body<Acc, Bias>(s, model.root_inertia(), data.v0, a0);
  return s;
}
/// ᴳX_root: origin at the CoM c_r (root coordinates), world axes (E = R).
template <class S, class T>
Transform<S> centroidal_frame(const FloatingData<S, T>& data, const Vector3<S>& c_root) {
  return Transform<S>(root_rotation(data), c_root);
}
}  // namespace detail

/// Centre of mass and its velocity (world coordinates): `data.com`, `data.vcom`. Returns `data.com`.
template <class S, class T, class Q, class V>
const Vector3<S>& center_of_mass(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                 const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v) {
  const auto s = detail::floating_momentum<false, false>(model, data, q, v, v);
  const Matrix3<S> R = detail::root_rotation(data);
  data.com = data.X0.r + R * (s.h / s.m);
  data.vcom = R * (s.mom.f / s.m);
  return data.com;
}

/// Centre of mass, its velocity and its acceleration for v̇ = a (world coordinates): `data.com`, `data.vcom`,
/// `data.acom`. Returns `data.com`.
template <class S, class T, class Q, class V, class A>
const Vector3<S>& center_of_mass(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                 const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                 const Eigen::MatrixBase<A>& a) {
  const auto s = detail::floating_momentum<true, false>(model, data, q, v, a);
  const Matrix3<S> R = detail::root_rotation(data);
  data.com = data.X0.r + R * (s.h / s.m);
  data.vcom = R * (s.mom.f / s.m);
  data.acom = R * (s.rate.f / s.m);
  return data.com;
}

/// Mass and centre of mass (world coordinates) of body's subtree; body −1: the root, i.e. the whole robot. Leaves
/// the tree's subtree masses and first moments in `data.tree.Ic[i]` (root coordinates).
template <class S, class T, class Q>
SubtreeCom<S> subtree_center_of_mass(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                     const Eigen::MatrixBase<Q>& q, int body) {
  forward_kinematics(model, data, q);
  Inertia<S> total = detail::subtree_first_moments(model.tree(), data.tree);
  total.m += model.root_inertia().m;
  total.h += model.root_inertia().h;
  const Inertia<S>& sub = body >= 0 ? data.tree.Ic[static_cast<std::size_t>(body)] : total;
  return SubtreeCom<S>{sub.m, data.X0.r + detail::root_rotation(data) * (sub.h / sub.m)};
}

namespace detail {
/// The floating CoM Jacobian of body's subtree (−1: the whole robot), world coordinates.
template <class S, class T, class Q, class J>
void floating_com_jacobian(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                           int body, J& Jc) {
  forward_kinematics(model, data, q);
  Inertia<S> total = subtree_first_moments(model.tree(), data.tree);
  total.m += model.root_inertia().m;
  total.h += model.root_inertia().h;
  const Inertia<S>& sub = body >= 0 ? data.tree.Ic[static_cast<std::size_t>(body)] : total;
  const Matrix3<S> R = root_rotation(data);
  const Vector3<S> c = sub.h / sub.m;  // root coordinates
  data.com = data.X0.r + R * (total.h / total.m);
  // The root's columns: linear e_k → R e_k, angular e_k → R (e_k × c) = −R c̃ e_k.
  Jc.template block<3, 3>(0, 0) = R;
  Jc.template block<3, 3>(0, 3) = -R * skew(c);
  if (body >= 0) mark_subtree(model.tree(), data.tree, body);
  tree_com_columns<true>(model.tree(), data.tree, body, sub.m, sub.h, R, 6, Jc);
}
}  // namespace detail

/// CoM Jacobian J_c (3 × nv, world coordinates): ċ = J_c v. Also `data.com`.
template <class S, class T, class Q, class J>
void com_jacobian(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                  const Eigen::MatrixBase<J>& Jc_) {
  detail::floating_com_jacobian(model, data, q, -1, detail::out_arg(Jc_));
}

/// Jacobian of the centre of mass of body's subtree (3 × nv, world coordinates; body −1: the whole robot). The
/// free-flyer's columns are never zero (the root carries every subtree). Also `data.com` (the whole robot's).
template <class S, class T, class Q, class J>
void subtree_com_jacobian(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                          int body, const Eigen::MatrixBase<J>& Jc_) {
  detail::floating_com_jacobian(model, data, q, body, detail::out_arg(Jc_));
}

namespace detail {
/// Composite inertias (root coordinates) of the tree into `data.tree.Ic`, and the whole robot's at the root.
template <class S, class T, class Q>
Inertia<S> floating_composite(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                              const Eigen::MatrixBase<Q>& q) {
  forward_kinematics(model, data, q);
  Inertia<S> total = composite_inertias_base(model.tree(), data.tree);
  total += model.root_inertia();
  data.com = data.X0.r + root_rotation(data) * (total.h / total.m);
  return total;
}
}  // namespace detail

/// Centroidal momentum matrix A_G (6 × nv, linear first, world axes, angular momentum about the CoM): h_G = A_G v.
/// The first six columns are the whole robot's composite inertia at the root moved to the centroidal frame, in
/// the free-flyer's column order (linear, angular). Also `data.com`.
template <class S, class T, class Q, class AG>
void centroidal_momentum_matrix(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<AG>& Ag_) {
  auto& Ag = detail::out_arg(Ag_);
  constexpr int NJ = FloatingModel<S, T>::NJ;
  const int n = model.njoints();
  detail::check_q(model, q, "centroidal_momentum_matrix");
  data.X0 = detail::root_transform<S>(q);
  Inertia<S> total = detail::base_momentum_columns(model.tree(), data.tree, detail::joint_block<NJ>(q, 7, n), 6, Ag);
  total += model.root_inertia();
  const Vector3<S> c = total.h / total.m;  // root coordinates
  data.com = data.X0.r + detail::root_rotation(data) * c;
  const Transform<S> XG = detail::centroidal_frame(data, c);
  detail::root_centroidal_columns(total, XG.E, Ag);
  detail::centroidal_columns(XG, 6, n, Ag);
}

/// Centroidal momentum h_G = [M ċ; k_G] (linear first, world axes, about the CoM). Also `data.com`, `data.vcom`.
template <class S, class T, class Q, class V>
Vector6<S> centroidal_momentum(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                               const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v) {
  const auto s = detail::floating_momentum<false, false>(model, data, q, v, v);
  const Vector3<S> c = s.h / s.m;
  const Matrix3<S> R = detail::root_rotation(data);
  data.com = data.X0.r + R * c;
  data.vcom = R * (s.mom.f / s.m);
  return detail::linear_first(detail::centroidal_frame(data, c).apply_force(s.mom));
}

/// ḣ_G for v̇ = a and Ȧ_G v (linear first, world axes, about the CoM; gravity not included: ḣ_G is the sum of the
/// external forces other than gravity, and ḣ_G = (M g, 0) in free fall). Also `data.com`, `data.vcom`,
/// `data.acom`.
template <class S, class T, class Q, class V, class A>
CentroidalMomentumRate<S> centroidal_momentum_time_variation(const FloatingModel<S, T>& model,
                                                             FloatingData<S, T>& data,
                                                             const Eigen::MatrixBase<Q>& q,
                                                             const Eigen::MatrixBase<V>& v,
                                                             const Eigen::MatrixBase<A>& a) {
  const auto s = detail::floating_momentum<true, true>(model, data, q, v, a);
  const Vector3<S> c = s.h / s.m;
  const Matrix3<S> R = detail::root_rotation(data);
  data.com = data.X0.r + R * c;
  data.vcom = R * (s.mom.f / s.m);
  data.acom = R * (s.rate.f / s.m);
  const Transform<S> XG = detail::centroidal_frame(data, c);
  return CentroidalMomentumRate<S>{detail::linear_first(XG.apply_force(s.rate)),
                                   detail::linear_first(XG.apply_force(s.bias))};
}

/// Centroidal composite inertia I_G (6 × 6, linear first: [M 1, 0; 0, I_c]): the whole robot's inertia about its
/// CoM, world axes. Also `data.com`.
template <class S, class T, class Q>
Matrix6<S> centroidal_composite_inertia(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                        const Eigen::MatrixBase<Q>& q) {
  const Inertia<S> total = detail::floating_composite(model, data, q);
  return detail::centroidal_inertia_matrix(total, detail::centroidal_frame(data, Vector3<S>(total.h / total.m)));
}

}  // namespace spatial

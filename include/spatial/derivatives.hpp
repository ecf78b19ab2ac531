#pragma once
/// \file derivatives.hpp
/// Analytical derivatives of inverse and forward dynamics, for fixed- and floating-base trees, compile-time and
/// run-time, any scalar type.
///
///   rnea_derivatives(model, data, dd, q, v, a[, fext, frame])  → dd.dtau_dq = ∂τ/∂q, dd.dtau_dv = ∂τ/∂v
///                                                                 (∂τ/∂a = H: `crba`); τ itself in data.tau
///   aba_derivatives(model, data, dd, q, v, τ[, fext, frame])    → dd.dqdd_dq, dd.dqdd_dv, dd.dqdd_dtau = H⁻¹;
///                                                                 q̈ in data.qdd
///
/// **Tangent space.** On a floating base, derivatives with respect to q are taken in the tangent space at q: column
/// k is d/dε τ(integrate(q, ε e_k), v, a) at ε = 0 (nv columns; the free-flyer's six are a body-frame twist of the
/// root, linear first, as v). Pinocchio's `computeRNEADerivatives` / `computeABADerivatives` use the same
/// convention, so the matrices compare entry by entry. Rows and columns are ordered as v (and τ).
///
/// **Every entry is written**, on every call (no accumulation across calls): entries between joints of which
/// neither is an ancestor of the other are structurally zero and are zeroed once, when `dd` is built.
///
/// **The algorithm** (derived for this library; the idea is that of Carpentier & Mansard, RSS 2018). All quantities
/// are expressed in one inertial frame, the base frame (root coordinates at q for a floating base, fixed for the
/// differentiation). There, with Sⱼ joint j's axis, p = λ(j) its parent and i ⪰ j meaning "i is j or a descendant":
///   ∂Sᵢ/∂qⱼ = Sⱼ × Sᵢ,   ∂vᵢ/∂qⱼ = Sⱼ × (vᵢ − v_p),   ∂aᵢ/∂qⱼ = Sⱼ × (aᵢ − a_p) + (vᵢ − v_p) × βⱼ,
///   ∂vᵢ/∂q̇ⱼ = Sⱼ,         ∂aᵢ/∂q̇ⱼ = Sⱼ × vᵢ − 2βⱼ          (i ⪰ j; βⱼ = Sⱼ × v_p),
/// and the body inertias and body-fixed forces of the subtree turn with it (∂I/∂qⱼ = Sⱼ×* I − I Sⱼ×). Summing
/// the body forces fₖ = Iₖ aₖ + vₖ ×* Iₖ vₖ − fₖˣ over subtrees, the parts that only turn rigidly with the subtree
/// cancel against ∂Sᵢ/∂qⱼ, and what is left is linear in per-body subtree sums: the composite inertia Iᶜ, the
/// composite "velocity coupling" Bᶜ (Bₖ u = Iₖ (vₖ × u) − u ×* Iₖvₖ − vₖ ×* Iₖ u) and the subtree force F:
///   row i, column j ⪯ i:   ∂τᵢ/∂qⱼ = Sᵢᵀ(Bᶜᵢ βⱼ − Iᶜᵢ αⱼ) − Sⱼᵀ(Sᵢ ×* Fˣᵢ),  ∂τᵢ/∂q̇ⱼ = −Sᵢᵀ(Bᶜᵢ Sⱼ + 2 Iᶜᵢ βⱼ)
///   row i, column j ≻ i:   ∂τᵢ/∂qⱼ = Sᵢᵀ(Sⱼ ×* Fⱼ′ + Bᶜⱼ βⱼ − Iᶜⱼ αⱼ),           ∂τᵢ/∂q̇ⱼ = −Sᵢᵀ(Bᶜⱼ Sⱼ + 2 Iᶜⱼ βⱼ)
/// with αⱼ = Sⱼ × a_p + v_p × βⱼ, Fˣ the subtree's external forces that are fixed in the base frame
/// (`ForceFrame::Base`; zero for body-frame forces, which turn with their body) and Fⱼ′ = Fⱼ + Fˣⱼ. Per row i the
/// code keeps Pᵢ = Iᶜᵢ Sᵢ and Qᵢ = Bᶜᵢᵀ Sᵢ, per column j the vectors αⱼ, βⱼ, Bᶜⱼ βⱼ …, so that each entry is one or
/// two 6-vector dot products: one forward pass, one backward pass with a walk over each joint's ancestors (the
/// sparsity of CRBA), no 6 × n blocks. Bᶜ = Wᶜ + Wᶜᵀ + h̄ᶜ, with Wᶜ = Σ Iₖ (vₖ×) and h̄ᶜ u = −u ×* Σ Iₖ vₖ
/// (Wᶜ + Wᶜᵀ has 9 independent numbers: `VelocityCoupling`).
/// The free-flyer is the six columns Sᵦ = unit twists of the root (v_p = 0, a_p = −a_g), whose ∂a/∂v differs from
/// a one-DoF joint's (the root's spatial acceleration is v̇ itself): ∂τᵢ/∂vᵦ = Sᵢᵀ(Iᶜᵢ (v₀ × Sᵦ) − Bᶜᵢ Sᵦ).
///
/// Forward dynamics: q̈ = FD(q, v, τ) satisfies RNEA(q, v, q̈) = τ, so ∂q̈/∂x = −H⁻¹ ∂τ/∂x at (q, v, q̈) for
/// x = q, v, and ∂q̈/∂τ = H⁻¹, computed directly (minv.hpp, without forming H); q̈ itself is H⁻¹ (τ − RNEA(q, v, 0)).
///
/// **Kinematics.** `frame_kinematics_derivatives(model, data, out, q, v, a, frame, rf)` → the derivatives of a
/// frame's spatial velocity and spatial acceleration (as `frame_velocity` / `frame_acceleration` return them, in
/// the reference frame `rf`) with respect to q (tangent space), v and a; the derivative of the frame's placement
/// itself is its Jacobian (`frame_jacobian`: column k of the Local Jacobian is the body twist of the frame for
/// q ⊕ ε eₖ). See that function.

#include "spatial/algorithms.hpp"
#include "spatial/floating.hpp"
#include "spatial/kinematics.hpp"
#include "spatial/minv.hpp"

#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace spatial {

namespace detail {

/// The symmetric part of the subtree sum W = Σ Iₖ (vₖ×) (motion → force, angular first), W + Wᵀ, as 9 numbers
/// instead of 36. For one body, with I = [Ī h̃; h̃ᵀ m1] and v× = [ω̃ 0; ṽ ω̃] (v = (ω, u)), using ã b̃ = b aᵀ − (a·b) 1:
///   W = [Ī ω̃ + h̃ ṽ, h̃ ω̃; m ṽ − h̃ ω̃, m ω̃],   W + Wᵀ = [G + Gᵀ, k̃; −k̃, 0],
/// G = Ī ω̃ + h̃ ṽ, k = h × ω − m u (ω̃ᵀ = −ω̃, h̃ ω̃ − ω̃ h̃ = (h × ω)~, and m ω̃ + m ω̃ᵀ = 0). Sums over subtrees keep
/// that form, so each body carries a symmetric 3 × 3 block and a 3-vector, and a product with a motion is one 3 × 3
/// product and two cross products instead of two dense 6 × 6 ones.
template <class S>
struct VelocityCoupling {
  Matrix3<S> A;  ///< G + Gᵀ (symmetric)
  Vector3<S> k;  ///< k = h × ω − m u

  static SPATIAL_INLINE VelocityCoupling Zero() { return {Matrix3<S>::Zero(), Vector3<S>::Zero()}; }
  /// The coupling of one body of inertia I (base coordinates) moving with velocity v.
  static SPATIAL_INLINE VelocityCoupling of(const Inertia<S>& I, const Motion<S>& v) {
    const Vector3<S>& w = v.w;
    const Vector3<S>& u = v.v;
    Matrix3<S> G = I.I * skew(w) + u * I.h.transpose();  // Ī ω̃ + h̃ ṽ without its −(h·u) 1
    const S hu2 = S(2) * I.h.dot(u);
    VelocityCoupling c;
    c.A = G + G.transpose();
    c.A.diagonal().array() -= hu2;
    c.k = cross3(I.h, w) - I.m * u;
    return c;
  }
  SPATIAL_INLINE VelocityCoupling& operator+=(const VelocityCoupling& o) {
    A += o.A;
    k = add3(k, o.k);
    return *this;
  }
  /// (W + Wᵀ) x for a motion x = (ω, u): (A ω + k × u, ω × k).
  SPATIAL_INLINE Force<S> operator*(const Motion<S>& x) const {
    return Force<S>(add3(Vector3<S>(A * x.w), cross3(k, x.v)), cross3(x.w, k));
  }
};

/// Whether the AVX2 path of `rnea_derivatives` stores and walks `DerivativeBodies::W` rather than `C`: on deep trees,
/// where the walk's savings per (body, ancestor) pair outweigh W's cost per body, i.e. at least four ancestors per
/// body on average (stance21, rooted at a sole: 6.7; floating27's tree, rooted at the pelvis: 2.4, where W made
/// clang's RNEA derivatives 4 % slower). Run-time trees take W.
template <class T>
constexpr bool walk_lanes() {
  if constexpr (is_static_tree_v<T>) {
    int pairs = 0;  // (body, proper ancestor) pairs
    for (int i = 0; i < T::size; ++i)
      for (int a = T::parent[static_cast<std::size_t>(i)]; a >= 0; a = T::parent[static_cast<std::size_t>(a)]) ++pairs;
    return pairs >= 4 * T::size;
  } else {
    return true;
  }
}

/// Per-body buffers of `rnea_derivatives` (base coordinates).
template <class S, class T>
struct DerivativeBodies {
  using ModelType = Model<S, T>;
  template <class X>
  using Array = typename ModelType::template Array<X>;

  explicit DerivativeBodies(const ModelType& model) {
    if constexpr (!ModelType::is_static) {
      const auto k = static_cast<std::size_t>(model.size());
      S0.resize(k); v.resize(k); a.resize(k); alpha.resize(k); beta.resize(k); C.resize(k); W.resize(k);
      Ic.resize(k); M.resize(k); hc.resize(k); F.resize(k); Fx.resize(k);
    } else {
      (void)model;
    }
  }

  Array<Motion<S>> S0{};     ///< joint axis Sᵢ
  Array<Motion<S>> v{};      ///< body velocity
  Array<Motion<S>> a{};      ///< body acceleration minus gravity
  Array<Motion<S>> alpha{};  ///< αᵢ = Sᵢ × a_λ(i) + v_λ(i) × βᵢ
  Array<Motion<S>> beta{};   ///< βᵢ = Sᵢ × v_λ(i)
  /// [Sᵢ βᵢ αᵢ] as the columns of one 6 × 3 matrix (angular rows first), for the walk over the ancestors, where one
  /// row's four force-like vectors are paired with all three at once (`rnea_derivatives_tree`).
  Array<Eigen::Matrix<S, 6, 3>> C{};
  /// The AVX2 path's form of the same (`simd::derivatives_forward`, `simd::WalkRow`): for each of the six
  /// components k (angular first) the lanes (Sₖ, Sₖ, Sₖ, αₖ), then six times (βₖ, βₖ, βₖ, βₖ); so that a row's four
  /// vectors meet an ancestor's in two sums of six fused multiply-adds of whole registers.
  Array<Eigen::Matrix<S, 4, 12>> W{};
  Array<Inertia<S>> Ic{};    ///< subtree inertia
  Array<VelocityCoupling<S>> M{};  ///< W + Wᵀ, W = Σ over the subtree of Iₖ (vₖ×)
  Array<Force<S>> hc{};      ///< subtree momentum Σ Iₖ vₖ
  Array<Force<S>> F{};       ///< subtree force Σ (Iₖ aₖ + vₖ ×* Iₖ vₖ − fₖˣ)
  Array<Force<S>> Fx{};      ///< subtree external force fixed in the base frame (ForceFrame::Base only)
};

/// The free-flyer's column entries of row i (linear first) from Pᵢ, Qᵢ and Rᵢ = Sᵢ ×* Fˣᵢ: with Sᵦ the unit twists
/// of the root, ∂τᵢ/∂qᵦ = −αᵦ·Pᵢ − Sᵦ·Rᵢ (αᵦ = Sᵦ × (0, −g)) and ∂τᵢ/∂vᵦ = −Sᵦ·Qᵢ + Pᵢ·(v₀ × Sᵦ).
template <class S, class RowQ, class RowV>
SPATIAL_INLINE void free_flyer_columns(const Force<S>& P, const Force<S>& Q, const Force<S>* R, const Vector3<S>& g,
                                       const Motion<S>& v0, RowQ&& dq, RowV&& dv) {
  const Vector3<S> dq_ang = cross3(g, P.f);  // −(Pᶠ × g)
  const Vector3<S> dv_lin = sub3(cross3(P.f, v0.w), Q.f);
  const Vector3<S> dv_ang = sub3(add3(cross3(P.n, v0.w), cross3(P.f, v0.v)), Q.n);
  for (int c = 0; c < 3; ++c) {
    dq(c) = R ? -R->f[c] : S(0);
    dq(3 + c) = R ? dq_ang[c] - R->n[c] : dq_ang[c];
    dv(c) = dv_lin[c];
    dv(3 + c) = dv_ang[c];
  }
}

/// The root of the recursion: fixed (v = 0, a = −a_g) or a free-flying root body with its own accumulators.
template <class S>
struct DerivativeRoot {
  bool floating = false;
  Motion<S> v = Motion<S>::Zero(), a = Motion<S>::Zero();
  // Floating only: the root body's subtree sums (the whole robot).
  Inertia<S> Ic = Inertia<S>::Zero();
  VelocityCoupling<S> M = VelocityCoupling<S>::Zero();
  Force<S> hc = Force<S>::Zero(), F = Force<S>::Zero(), Fx = Force<S>::Zero();
};

#if SPATIAL_SIMD_AVX2
namespace simd {
/// The first six lanes' groups of `DerivativeBodies::W` of a body: (Sₖ, Sₖ, Sₖ, αₖ), k = 0 … 5.
template <class S, class V>
SPATIAL_INLINE void store_walk_alpha(S* W, V sw, V sv, V alw, V alv) {
  store4(W, low3_high1(lane<0>(sw), lane<0>(alw)));
  store4(W + 4, low3_high1(lane<1>(sw), lane<1>(alw)));
  store4(W + 8, low3_high1(lane<2>(sw), lane<2>(alw)));
  store4(W + 12, low3_high1(lane<0>(sv), lane<0>(alv)));
  store4(W + 16, low3_high1(lane<1>(sv), lane<1>(alv)));
  store4(W + 20, low3_high1(lane<2>(sv), lane<2>(alv)));
}

/// The forward pass of `rnea_derivatives_tree` on AVX2 (double or float, revolute joints about coordinate axes:
/// `simd_applies`), every 3-vector in a register: ⁱX_λ and ⁱX_0 into `data.X_up` and `data.X_base` (base_transform,
/// as forward_kinematics' kernel leaves them), and per body, in base coordinates, Sᵢ, vᵢ, aᵢ, βᵢ, αᵢ, Cᵢ, the body
/// inertia ⁱX_0ᵀ Iᵢ ⁱX_0 (transformed_inertia, the arithmetic of CRBA's and H⁻¹'s kernels), its momentum Iᵢ vᵢ, its
/// force Iᵢ aᵢ + vᵢ ×* Iᵢ vᵢ and its velocity coupling (`VelocityCoupling::of`), into the arrays of `b`; external
/// forces are left to the caller. Agrees with the scalar pass (the same formulas) to rounding.
///
/// `Reuse`: H⁻¹'s pass 1 (simd::minv_articulated) has just run at the same q, leaving the transforms and Sᵢ in
/// `data` (data.S_base) and the body inertias in base coordinates in `out.Ic`; the pass reads those instead of
/// composing the transforms and moving the inertias again (`aba_derivatives`).
///
/// `Bias`: the pass runs at q̈ = 0 (`qdd` is not read), for `aba_derivatives`, which takes the bias forces from it
/// and then adds q̈'s terms (`derivatives_accelerate`).
template <bool Reuse = false, bool Bias = false, class S, class T, class Bodies, class QD, class QDD, class Root>
void derivatives_forward(const Model<S, T>& model, Data<S, T>& data, Bodies& out, const QD& qd, const QDD& qdd,
                         const Root& root) {
  using V = Vec<S>;
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  struct Body {
    V col[3], row[3], r;  // ⁱX_0: columns and rows of E, r
    V vw, vv, aw, av;     // vᵢ and aᵢ, for the children
  };
  Body local[NB];
  Body* b = local;
  if constexpr (Static) keep_in_memory(b);
  else b = records<Body>(data, model.size());
  const V rvw = load3z(root.v.w.data()), rvv = load3(root.v.v.data());
  const V raw = load3z(root.a.w.data()), rav = load3(root.a.v.data());
  auto forward = [&](auto I, auto KC) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const auto p = parent_of(model, I);
    Body& B = b[i];
    V sw, sv;
    if constexpr (Reuse) {
      (void)KC;
      sw = load3z(data.S_base[k].w.data());
      sv = load3(data.S_base[k].v.data());
    } else {
      LocalTransform<S> up;
      base_transform<decltype(KC)::value>(model, data, i, p, b, up, B, sw, sv);
    }
    const bool has_parent = int(p) >= 0;
    const V vpw = has_parent ? b[int(p)].vw : rvw, vpv = has_parent ? b[int(p)].vv : rvv;
    const V apw = has_parent ? b[int(p)].aw : raw, apv = has_parent ? b[int(p)].av : rav;
    const V dq = bcast(S(qd[i]));
    // vᵢ = v_λ + Sᵢ q̇ᵢ, βᵢ = Sᵢ × v_λ, aᵢ = a_λ + Sᵢ q̈ᵢ − βᵢ q̇ᵢ, αᵢ = Sᵢ × a_λ + v_λ × βᵢ
    B.vw = fmadd(sw, dq, vpw);
    B.vv = fmadd(sv, dq, vpv);
    const V bw = cross(sw, vpw), bv = add(cross(sw, vpv), cross(sv, vpw));
    if constexpr (Bias) {
      (void)qdd;
      B.aw = fnmadd(bw, dq, apw);
      B.av = fnmadd(bv, dq, apv);
    } else {
      const V ddq = bcast(S(qdd[i]));
      B.aw = fnmadd(bw, dq, fmadd(sw, ddq, apw));
      B.av = fnmadd(bv, dq, fmadd(sv, ddq, apv));
    }
    const V alw = add(cross(sw, apw), cross(vpw, bw));
    const V alv = add(add(cross(sw, apv), cross(sv, apw)), add(cross(vpw, bv), cross(vpv, bw)));
    store_pair(out.S0[k].w.data(), sw, sv);
    store_pair(out.v[k].w.data(), B.vw, B.vv);
    store_pair(out.a[k].w.data(), B.aw, B.av);
    store_pair(out.beta[k].w.data(), bw, bv);
    store_pair(out.alpha[k].w.data(), alw, alv);
    if constexpr (walk_lanes<T>()) {
      S* W = out.W[k].data();  // (Sₖ, Sₖ, Sₖ, αₖ) and (βₖ, βₖ, βₖ, βₖ), k = 0 … 5
      store_walk_alpha(W, sw, sv, alw, alv);
      store4(W + 24, lane<0>(bw));
      store4(W + 28, lane<1>(bw));
      store4(W + 32, lane<2>(bw));
      store4(W + 36, lane<0>(bv));
      store4(W + 40, lane<1>(bv));
      store4(W + 44, lane<2>(bv));
    } else {
      S* C = out.C[k].data();  // [Sᵢ βᵢ αᵢ], column-major 6 × 3
      store_pair(C, sw, sv);
      store_pair(C + 6, bw, bv);
      store_pair(C + 12, alw, alv);
    }
    // The body inertia in base coordinates (m, h, Ī by columns); h and Ī are contiguous in an Inertia.
    const Inertia<S>& I0 = model.inertia(i);
    Inertia<S>& In = out.Ic[k];
    V h, c[3];
    if constexpr (Reuse) {
      h = load3z(In.h.data());
      c[0] = load3z(In.I.data());
      c[1] = load3z(In.I.data() + 3);
      c[2] = load3(In.I.data() + 6);
    } else {
      const V ic0[3] = {load3z(I0.I.data()), load3z(I0.I.data() + 3), load3(I0.I.data() + 6)};
      transformed_inertia<S>(B.col, B.row, B.r, I0.m, load3z(I0.h.data()), ic0, h, c);
      store_inertia(I0.m, h, c, In);
    }
    // The momentum Iᵢ vᵢ and the force Fᵢ = Iᵢ aᵢ + vᵢ ×* (Iᵢ vᵢ).
    const V m = bcast(I0.m);
    V hn, hf, ian, iaf, vhn, vhf;
    inertia_times(c[0], c[1], c[2], h, m, B.vw, B.vv, hn, hf);
    inertia_times(c[0], c[1], c[2], h, m, B.aw, B.av, ian, iaf);
    cross_force(B.vw, B.vv, hn, hf, vhn, vhf);
    store_pair(out.hc[k].n.data(), hn, hf);
    store_pair(out.F[k].n.data(), add(ian, vhn), add(iaf, vhf));
    // VelocityCoupling::of: A = G + Gᵀ − 2 (h·u) 1 with G = Ī ω̃ + u hᵀ, whose row j is Īⱼ × ω + uⱼ h (Ī
    // symmetric: row j of Ī ω̃ is −ω × Īⱼ); A is symmetric, so row j of G + Gᵀ is also its column j. k = h × ω − m u.
    V g[3], gt[3];
    g[0] = fmadd(lane<0>(B.vv), h, cross(c[0], B.vw));
    g[1] = fmadd(lane<1>(B.vv), h, cross(c[1], B.vw));
    g[2] = fmadd(lane<2>(B.vv), h, cross(c[2], B.vw));
    transpose(g[0], g[1], g[2], gt[0], gt[1], gt[2]);
    const V hu2 = bcast(S(2) * hsum(mul(h, B.vv)));
    S* A = out.M[k].A.data();  // then k, contiguous
    store4(A, sub(add(g[0], gt[0]), only<0>(hu2)));
    store4(A + 3, sub(add(g[1], gt[1]), only<1>(hu2)));
    store4(A + 6, sub(add(g[2], gt[2]), only<2>(hu2)));
    store3(A + 9, fnmadd(m, B.vv, cross(h, B.vw)));
  };
  bodies(model, forward);
}

/// After `derivatives_forward<true, true>` (q̈ = 0) and the external forces: adds q̈'s terms, which are linear in q̈.
/// With Δaᵢ = Δa_λ + Sᵢ q̈ᵢ (Δa of the root: `da0`, zero on a fixed base), aᵢ += Δaᵢ, αᵢ += Sᵢ × Δa_λ (in `alpha`
/// and in W's or C's lanes) and Fᵢ += Iᵢ Δaᵢ, with Iᵢ the body inertia in base coordinates that `out.Ic` still
/// holds (before the backward pass sums it into the subtree's). βᵢ, vᵢ and every velocity term are unchanged.
template <class S, class T, class Bodies, class QDD>
void derivatives_accelerate(const Model<S, T>& model, Data<S, T>& data, Bodies& out, const QDD& qdd,
                            const Motion<S>& da0) {
  using V = Vec<S>;
  constexpr bool Static = Model<S, T>::is_static;
  constexpr int NB = Static ? Model<S, T>::NB : 1;
  struct Body {
    V dw, dv;  // Δaᵢ
  };
  Body local[NB];
  Body* b = local;
  if constexpr (Static) keep_in_memory(b);
  else b = records<Body>(data, model.size());
  const V rw = load3z(da0.w.data()), rv = load3(da0.v.data());
  auto accelerate = [&](auto I, auto) SPATIAL_LAMBDA_INLINE {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const auto p = parent_of(model, I);
    const bool has_parent = int(p) >= 0;
    const V pw = has_parent ? b[int(p)].dw : rw, pv = has_parent ? b[int(p)].dv : rv;
    const V sw = load3z(out.S0[k].w.data()), sv = load3(out.S0[k].v.data());
    const V ddq = bcast(S(qdd[i]));
    const V dw = fmadd(sw, ddq, pw), dv = fmadd(sv, ddq, pv);
    b[i].dw = dw;
    b[i].dv = dv;
    Motion<S>& a = out.a[k];
    store_pair(a.w.data(), add(load3z(a.w.data()), dw), add(load3(a.v.data()), dv));
    Motion<S>& al = out.alpha[k];
    const V alw = add(load3z(al.w.data()), cross(sw, pw));
    const V alv = add(load3(al.v.data()), add(cross(sw, pv), cross(sv, pw)));
    store_pair(al.w.data(), alw, alv);
    if constexpr (walk_lanes<T>()) store_walk_alpha(out.W[k].data(), sw, sv, alw, alv);
    else store_pair(out.C[k].data() + 12, alw, alv);
    const Inertia<S>& In = out.Ic[k];
    const V c[3] = {load3z(In.I.data()), load3z(In.I.data() + 3), load3(In.I.data() + 6)};
    V fn, ff;
    inertia_times(c[0], c[1], c[2], load3z(In.h.data()), bcast(In.m), dw, dv, fn, ff);
    Force<S>& F = out.F[k];
    store_pair(F.n.data(), add(load3z(F.n.data()), fn), add(load3(F.f.data()), ff));
  };
  bodies(model, accelerate);
}

/// Columns 0, 1, 2 of the 4 × 4 matrix whose rows are a, b, c, d (lanes 0..3).
SPATIAL_INLINE void rows_to_columns(Vd a, Vd b, Vd c, Vd d, Vd& c0, Vd& c1, Vd& c2) {
  const Vd t0 = _mm256_unpacklo_pd(a, b), t1 = _mm256_unpackhi_pd(a, b);  // a0 b0 a2 b2, a1 b1 a3 b3
  const Vd t2 = _mm256_unpacklo_pd(c, d), t3 = _mm256_unpackhi_pd(c, d);  // c0 d0 c2 d2, c1 d1 c3 d3
  c0 = _mm256_permute2f128_pd(t0, t2, 0x20);
  c1 = _mm256_permute2f128_pd(t1, t3, 0x20);
  c2 = _mm256_permute2f128_pd(t0, t2, 0x31);
}
SPATIAL_INLINE void rows_to_columns(Vf a, Vf b, Vf c, Vf d, Vf& c0, Vf& c1, Vf& c2) {
  const Vf t0 = _mm_unpacklo_ps(a, b), t1 = _mm_unpacklo_ps(c, d);  // a0 b0 a1 b1, c0 d0 c1 d1
  const Vf t2 = _mm_unpackhi_ps(a, b), t3 = _mm_unpackhi_ps(c, d);  // a2 b2 a3 b3, c2 d2 c3 d3
  c0 = _mm_movelh_ps(t0, t1);
  c1 = _mm_movehl_ps(t1, t0);
  c2 = _mm_movelh_ps(t2, t3);
}

/// One body's row vectors of the backward pass of `rnea_derivatives_tree` with every 3-vector in a register (the
/// trees of derivatives_forward): Pᵢ = Iᶜ Sᵢ, Qᵢ = Bᶜᵀ Sᵢ, Yᵢ = −(Bᶜ Sᵢ + 2 Iᶜ βᵢ), Zᵢ = Sᵢ ×* F′ᵢ + Bᶜ βᵢ − Iᶜ αᵢ
/// as the rows of G (Q, Z, Y, P; moments then forces) and, when `vectors` (only a free-flying root reads them), into
/// P, Qr, Y, Z; returns τᵢ = Sᵢ·Fᵢ.
template <class S>
SPATIAL_INLINE S derivative_rows(const Motion<S>& Si, const Inertia<S>& Ic, const VelocityCoupling<S>& M,
                                 const Force<S>& hc, const Motion<S>& be, const Motion<S>& al, const Force<S>& Fp,
                                 const Force<S>& F, bool vectors, Force<S>& P, Force<S>& Qr, Force<S>& Y,
                                 Force<S>& Z, Eigen::Matrix<S, 4, 6>& G) {
  using V = Vec<S>;
  const V sw = load3z(Si.w.data()), sv = load3(Si.v.data());
  const V bw = load3z(be.w.data()), bv = load3(be.v.data());
  const V aw = load3z(al.w.data()), av = load3(al.v.data());
  const V m = bcast(Ic.m), h = load3z(Ic.h.data());
  const V ic[3] = {load3z(Ic.I.data()), load3z(Ic.I.data() + 3), load3(Ic.I.data() + 6)};
  const V ma[3] = {load3z(M.A.data()), load3z(M.A.data() + 3), load3z(M.A.data() + 6)};
  const V mk = load3(M.k.data());
  const V hn = load3z(hc.n.data()), hf = load3(hc.f.data());
  auto inertia = [&](V xw, V xv, V& n, V& f) SPATIAL_LAMBDA_INLINE {
    inertia_times(ic[0], ic[1], ic[2], h, m, xw, xv, n, f);
  };
  // (W + Wᵀ) x = (A ω + k × u, ω × k)
  auto coupling = [&](V xw, V xv, V& n, V& f) SPATIAL_LAMBDA_INLINE {
    n = add(comb(ma[0], ma[1], ma[2], xw), cross(mk, xv));
    f = cross(xw, mk);
  };
  V pn, pf, msn, msf, shn, shf, mbn, mbf, bhn, bhf, ibn, ibf, ian, iaf, sfn, sff;
  inertia(sw, sv, pn, pf);
  coupling(sw, sv, msn, msf);
  cross_force(sw, sv, hn, hf, shn, shf);
  coupling(bw, bv, mbn, mbf);
  cross_force(bw, bv, hn, hf, bhn, bhf);
  inertia(bw, bv, ibn, ibf);
  inertia(aw, av, ian, iaf);
  cross_force(sw, sv, load3z(Fp.n.data()), load3(Fp.f.data()), sfn, sff);
  const V two = bcast(S(2));
  const V qn = add(msn, shn), qf = add(msf, shf);                              // Bᶜᵀ S = M S + S ×* h
  const V yn = fnmadd(two, ibn, sub(shn, msn)), yf = fnmadd(two, ibf, sub(shf, msf));  // −(M S − S ×* h + 2 I β)
  const V zn = sub(add(sfn, sub(mbn, bhn)), ian), zf = sub(add(sff, sub(mbf, bhf)), iaf);  // S ×* F′ + Bᶜ β − I α
  if (vectors) {
    store_pair(P.n.data(), pn, pf);
    store_pair(Qr.n.data(), qn, qf);
    store_pair(Y.n.data(), yn, yf);
    store_pair(Z.n.data(), zn, zf);
  }
  V c[6];
  rows_to_columns(qn, zn, yn, pn, c[0], c[1], c[2]);
  rows_to_columns(qf, zf, yf, pf, c[3], c[4], c[5]);
  S* g = G.data();
  for (int j = 0; j < 6; ++j) store4(g + 4 * j, c[j]);
  return hsum(fmadd(sw, load3z(F.n.data()), mul(sv, load3(F.f.data()))));
}

/// One row's entries for one ancestor j (or the row's own body) from G (rows Q, Z, Y, P) and j's `W`:
/// l1 = (Q·Sⱼ, Z·Sⱼ, Y·Sⱼ, P·αⱼ), l2 = (Q·βⱼ, Z·βⱼ, Y·βⱼ, P·βⱼ), and e = (∂τᵢ/∂qⱼ, ∂τᵢ/∂q̇ⱼ, ∂τⱼ/∂qᵢ, ∂τⱼ/∂q̇ᵢ) =
/// (βⱼ·Q − αⱼ·P, −Sⱼ·Q − 2 βⱼ·P, Sⱼ·Z, Sⱼ·Y).
template <class S>
struct WalkRow {
  using V = Vec<S>;
  V g[6];
  explicit WalkRow(const Eigen::Matrix<S, 4, 6>& G) {
    for (int k = 0; k < 6; ++k) g[k] = load4(G.data() + 4 * k);
  }
  SPATIAL_INLINE void operator()(const S* w, S* e) const {
    V l1 = mul(g[0], load4(w)), l2 = mul(g[0], load4(w + 24));
    for (int k = 1; k < 6; ++k) {
      l1 = fmadd(g[k], load4(w + 4 * k), l1);
      l2 = fmadd(g[k], load4(w + 24 + 4 * k), l2);
    }
    alignas(32) S t1[4], t2[4];
    store4(t1, l1);
    store4(t2, l2);
    e[0] = t2[0] - t1[3];
    e[1] = -t1[0] - S(2) * t2[3];
    e[2] = t1[1];
    e[3] = t1[2];
  }
};
}  // namespace simd
#endif

/// τᵢ = Sᵢ · Σ over i's subtree of Fₖ from the per-body forces of the forward pass (`b.F`, left as they are; the
/// subtree sums go through `data.f`) into tau[off + i]; returns the sum of the subtree forces of the root's children.
template <class S, class T, class Tau>
Force<S> bias_backward(const Model<S, T>& model, Data<S, T>& data, const DerivativeBodies<S, T>& b, int off,
                       Tau& tau) {
  for_each_body(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    data.f[k] = b.F[k];
  });
  Force<S> top = Force<S>::Zero();
  for_each_body_reverse(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    tau[off + i] = dot(b.S0[k], data.f[k]);
    if (p >= 0) data.f[static_cast<std::size_t>(p)] += data.f[k];
    else top += data.f[k];
  });
  return top;
}

/// The tree's part of the RNEA derivatives. Writes rows/columns `off + i` of dq and dv, τᵢ into tau[off + i] and,
/// for a floating root, the free-flyer's rows (0…5) for the tree's columns and its columns for the tree's rows.
/// `after_minv`: `inverse_inertia_impl` has just run at the same q with `b.Ic` as its `body_inertia` (aba_derivatives),
/// so where the AVX2 kernels apply (to both alike) the forward pass reuses its transforms and inertias.
/// `solve` (aba_derivatives, only where the AVX2 kernels apply: simd_candidate and simd_applies): q̈ is not known
/// yet. The forward pass runs at q̈ = 0, the bias forces τ₀ = RNEA(q, q̇, 0, fext) are summed from it into `tau`
/// (`bias_backward`), `solve(F)` is then called with the sum F of the subtree forces of the root's children and must write q̈ where
/// `a` reads it and return the root's Δa (zero on a fixed base), and q̈'s terms are added (`derivatives_accelerate`)
/// before the backward pass: no separate RNEA for the bias forces.
template <class S, class T, class Q, class V, class A, class Ext, class MQ, class MV, class Tau,
          class Solve = std::nullptr_t>
void rnea_derivatives_tree(const Model<S, T>& model, Data<S, T>& data, DerivativeBodies<S, T>& b,
                           const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                           const Eigen::MatrixBase<A>& a, const Ext& fext, ForceFrame frame,
                           DerivativeRoot<S>& root, const Vector3<S>& g_base, int off, MQ& dq, MV& dv, Tau& tau,
                           bool after_minv = false, Solve&& solve = nullptr) {
  constexpr bool X = has_external_v<Ext>;
  constexpr bool Solving = !std::is_same_v<std::decay_t<Solve>, std::nullptr_t>;
  const bool world_forces = X && frame == ForceFrame::Base;
  // The forward pass: by the AVX2 kernel where it applies, else here.
  bool forward_done = false;
#if SPATIAL_SIMD_AVX2
  if constexpr (simd_candidate<S, T>()) {
    if (simd_applies(model)) {
      if constexpr (Solving) {
        simd::derivatives_forward<true, true>(model, data, b, v, a, root);
      } else if (after_minv) {
        simd::derivatives_forward<true>(model, data, b, v, a, root);
      } else {
        joint_sincos(model, data, q);
        simd::derivatives_forward(model, data, b, v, a, root);
      }
      forward_done = true;
    }
  }
#endif
  (void)after_minv;
  (void)solve;  // used only by the AVX2 path
  static_assert(!Solving || simd_candidate<S, T>(), "rnea_derivatives_tree: `solve` needs the AVX2 kernels");
  if (!forward_done) {
    joint_sincos(model, data, q);
    for_each_body(model, [&](auto I) {
      const int i = I;
      const auto k = static_cast<std::size_t>(i);
      const int p = model.parent(I);
      const auto pk = static_cast<std::size_t>(p);
      update_transform<true>(model, data, I, q);
      const Motion<S>& vp = p >= 0 ? b.v[pk] : root.v;
      const Motion<S>& ap = p >= 0 ? b.a[pk] : root.a;
      const Motion<S> Si = model.joint(I).subspace_inverse(data.X_base[k]);
      const S qd = S(v[i]), qdd = S(a[i]);
      b.S0[k] = Si;
      b.v[k] = vp + Si * qd;
      b.beta[k] = cross(Si, vp);
      b.a[k] = ap + Si * qdd - b.beta[k] * qd;  // vᵢ × Sᵢ q̇ᵢ = v_λ × Sᵢ q̇ᵢ = −βᵢ q̇ᵢ (Sᵢ × Sᵢ = 0)
      b.alpha[k] = cross(Si, ap) + cross(vp, b.beta[k]);
      b.C[k] << Si.w, b.beta[k].w, b.alpha[k].w, Si.v, b.beta[k].v, b.alpha[k].v;
      const Inertia<S> In = model.inertia(i).transformed_inverse(data.X_base[k]);
      const Force<S> h = In * b.v[k];
      b.F[k] = In * b.a[k] + cross(b.v[k], h);
      b.Ic[k] = In;
      b.hc[k] = h;
      b.M[k] = VelocityCoupling<S>::of(In, b.v[k]);
    });
  }
  if constexpr (X) {
    for_each_body(model, [&](auto I) {
      const auto k = static_cast<std::size_t>(int(I));
      if (world_forces) {
        b.Fx[k] = fext[k];
        b.F[k] -= fext[k];
      } else {
        b.F[k] -= data.X_base[k].apply_force_inverse(fext[k]);
      }
    });
  }
#if SPATIAL_SIMD_AVX2
  if constexpr (Solving) {
    const Motion<S> da0 = solve(bias_backward(model, data, b, off, tau));
    simd::derivatives_accelerate(model, data, b, a, da0);
  }
#endif

  for_each_body_reverse(model, [&](auto I) {
    const int i = I;
    const auto k = static_cast<std::size_t>(i);
    const int p = model.parent(I);
    const Motion<S>& Si = b.S0[k];
    const Inertia<S>& Ic = b.Ic[k];
    const VelocityCoupling<S>& M = b.M[k];
    const Motion<S>& be = b.beta[k];
    Force<S> Fp = b.F[k];
    Force<S> R = Force<S>::Zero();
    if (world_forces) {
      Fp += b.Fx[k];
      R = cross(Si, b.Fx[k]);
    }
    const int r = off + i;
    // Row i's four force-like vectors, also as the rows of G (moment first, as motions are angular first): each
    // entry of row i and column i is a dot product of one of them with one of Sⱼ, βⱼ, αⱼ, and G [Sⱼ βⱼ αⱼ] gives
    // all twelve of an ancestor j at once (three columns of four lanes: broadcasts and fused multiply-adds).
    Force<S> P, Qr, Y, Z;
    Eigen::Matrix<S, 4, 6> G;
    bool rows_done = false;
#if SPATIAL_SIMD_AVX2
    if constexpr (simd_candidate<S, T>()) {
      if (forward_done) {
        tau[r] = simd::derivative_rows(Si, Ic, M, b.hc[k], be, b.alpha[k], Fp, b.F[k], root.floating, P, Qr,
                                       Y, Z, G);
        rows_done = true;
      }
    }
#endif
    if (!rows_done) {
      P = Ic * Si;
      const Force<S> MS = M * Si;
      const Force<S> Sh = cross(Si, b.hc[k]);
      Qr = MS + Sh;                                     // Bᶜᵀ S
      const Force<S> BS = MS - Sh;                      // Bᶜ S
      const Force<S> Bb = M * be - cross(be, b.hc[k]);  // Bᶜ β
      Y = -(BS + S(2) * (Ic * be));
      Z = cross(Si, Fp) + Bb - Ic * b.alpha[k];
      tau[r] = dot(Si, b.F[k]);
      G << Qr.n.transpose(), Qr.f.transpose(), Z.n.transpose(), Z.f.transpose(), Y.n.transpose(), Y.f.transpose(),
          P.n.transpose(), P.f.transpose();
    }
    bool walked = false;
#if SPATIAL_SIMD_AVX2
    if constexpr (simd_candidate<S, T>() && walk_lanes<T>()) {
      if (forward_done) {
        // Row i's entries with body i itself, then with each ancestor j: e = (βⱼ·Qᵢ − αⱼ·Pᵢ, −Sⱼ·Qᵢ − 2 βⱼ·Pᵢ,
        // Sⱼ·Zᵢ, Sⱼ·Yᵢ) from Wⱼ.
        const simd::WalkRow<S> row(G);
        S e[4];
        row(b.W[k].data(), e);
        dq(r, r) = e[0];
        dv(r, r) = e[1];
        walk_up(model, I, [&](auto, auto J) {
          const auto jk = static_cast<std::size_t>(int(J));
          const int c = off + int(J);
          row(b.W[jk].data(), e);
          if (world_forces) e[0] -= dot(b.S0[jk], R);
          dq(r, c) = e[0];
          dv(r, c) = e[1];
          dq(c, r) = e[2];
          dv(c, r) = e[3];
        });
        walked = true;
      }
    }
#endif
    // The two walks (lanes Wⱼ above, G Cⱼ here) are written out separately on purpose: through one shared `walk`
    // lambda, clang's floating27 took 6 % longer and stance21 counted 1 900 (clang) to 3 200 (g++) instructions
    // more per call (bench/callgrind_derivatives.cpp).
    if (!walked) {  // the same entries from G Cⱼ
      {
        const Eigen::Matrix<S, 4, 3> D = G.lazyProduct(b.C[k]);
        dq(r, r) = D(0, 1) - D(3, 2);
        dv(r, r) = -D(0, 0) - S(2) * D(3, 1);
      }
      walk_up(model, I, [&](auto, auto J) {
        const auto jk = static_cast<std::size_t>(int(J));
        const int c = off + int(J);
        const Eigen::Matrix<S, 4, 3> D = G.lazyProduct(b.C[jk]);
        S x = D(0, 1) - D(3, 2);
        if (world_forces) x -= dot(b.S0[jk], R);
        dq(r, c) = x;
        dv(r, c) = -D(0, 0) - S(2) * D(3, 1);
        dq(c, r) = D(1, 0);
        dv(c, r) = D(2, 0);
      });
    }
    if (root.floating) {
      // The free-flyer's rows for column i (S_b·Z, S_b·Y, linear first) and its columns for row i.
      for (int c = 0; c < 3; ++c) {
        dq(c, r) = Z.f[c];
        dq(3 + c, r) = Z.n[c];
        dv(c, r) = Y.f[c];
        dv(3 + c, r) = Y.n[c];
      }
      free_flyer_columns<S>(P, Qr, world_forces ? &R : nullptr, g_base, root.v,
                            [&](int c) -> decltype(auto) { return dq(r, c); },
                            [&](int c) -> decltype(auto) { return dv(r, c); });
    }
    if (p >= 0) {
      const auto pk = static_cast<std::size_t>(p);
      b.Ic[pk] += Ic;
      b.M[pk] += M;
      b.hc[pk] += b.hc[k];
      b.F[pk] += b.F[k];
      if (world_forces) b.Fx[pk] += b.Fx[k];
    } else if (root.floating) {
      root.Ic += Ic;
      root.M += M;
      root.hc += b.hc[k];
      root.F += b.F[k];
      if (world_forces) root.Fx += b.Fx[k];
    }
  });
}

}  // namespace detail

namespace detail {
/// n rounded up to a whole number of m (the rows of a matrix whose columns are whole packets of m entries).
constexpr int round_up(int n, int m) { return (n + m - 1) / m * m; }

/// The buffers and results both derivative data types hold: per-body scratch of the tree and N × N matrices.
template <class S, class T, int N>
struct DerivativeBuffers {
  using Matrix = Eigen::Matrix<S, matrix_dim(N), matrix_dim(N)>;

  DerivativeBuffers(const Model<S, T>& tree, int n)
      : bodies(tree), dtau_dq(Matrix::Zero(n, n)), dtau_dv(Matrix::Zero(n, n)), dqdd_dq(Matrix::Zero(n, n)),
        dqdd_dv(Matrix::Zero(n, n)), dqdd_dtau(Matrix::Zero(n, n)),
        minv_padded(PaddedMatrix::Zero(round_up(n, kPacket), n)) {
    // Column c's structural non-zeros: rows of joints that are c's ancestors, c itself or its descendants, and on
    // a floating base (n = bodies + 6) the free-flyer's six rows and columns whole.
    const int off = n - tree.size();
    support_start.reserve(static_cast<std::size_t>(n) + 1);
    support_start.push_back(0);
    for (int c = 0; c < n; ++c) {
      for (int r = 0; r < n; ++r)
        if (r < off || c < off || tree.is_ancestor_or_self(r - off, c - off) ||
            tree.is_ancestor_or_self(c - off, r - off))
          support_rows.push_back(r);
      support_start.push_back(static_cast<int>(support_rows.size()));
    }
  }

  DerivativeBodies<S, T> bodies;      ///< per-body scratch (base coordinates)
  Matrix dtau_dq, dtau_dv;            ///< ∂τ/∂q, ∂τ/∂q̇ (rnea_derivatives; row = τ index, column = q index)
  Matrix dqdd_dq, dqdd_dv, dqdd_dtau; ///< ∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = H⁻¹ (aba_derivatives)
  /// The rows where column c of ∂τ/∂q and ∂τ/∂q̇ can be non-zero (the pattern of H):
  /// support_rows[support_start[c]] … support_rows[support_start[c + 1] − 1], ascending.
  std::vector<int> support_start, support_rows;

  static constexpr int kCols = Matrix::ColsAtCompileTime;
  static constexpr int kPacket =
      Eigen::internal::unpacket_traits<typename Eigen::internal::packet_traits<S>::type>::size;
  /// aba_derivatives' copy of H⁻¹ with rows of zeros below it up to a whole number of Eigen's packets, so that its
  /// columns are whole packets (`aba_derivatives_products`).
  static constexpr int kPadded = kCols == Eigen::Dynamic ? 0 : round_up(kCols, kPacket);
  using PaddedMatrix = Eigen::Matrix<S, kCols == Eigen::Dynamic ? Eigen::Dynamic : kPadded, kCols>;
  PaddedMatrix minv_padded;
};
}  // namespace detail

/// Buffers and results of the fixed-base derivatives (n × n), allocated once here.
template <class S, class T = DynamicTree>
struct DerivativeData : detail::DerivativeBuffers<S, T, Model<S, T>::NB> {
  using ModelType = Model<S, T>;
  using MatrixN = typename detail::DerivativeBuffers<S, T, ModelType::NB>::Matrix;
  explicit DerivativeData(const ModelType& model)
      : detail::DerivativeBuffers<S, T, ModelType::NB>(model, model.size()), minv(model) {}
  MinvData<S, T> minv;  ///< aba_derivatives' H⁻¹ (`minv.Minv`, the same as dqdd_dtau)
};

/// Buffers and results of the floating-base derivatives (nv × nv, tangent space, see the file comment).
template <class S, class T = DynamicTree>
struct FloatingDerivativeData : detail::DerivativeBuffers<S, T, FloatingModel<S, T>::NV> {
  using ModelType = FloatingModel<S, T>;
  using MatrixV = typename detail::DerivativeBuffers<S, T, ModelType::NV>::Matrix;
  explicit FloatingDerivativeData(const ModelType& model)
      : detail::DerivativeBuffers<S, T, ModelType::NV>(model.tree(), model.nv()), minv(model) {}
  FloatingMinvData<S, T> minv;  ///< aba_derivatives' H⁻¹ (`minv.Minv`, the same as dqdd_dtau)
};

namespace detail {
template <class S, class T, class Q, class QD, class QDD, class Ext, class Solve = std::nullptr_t>
void rnea_derivatives_impl(const Model<S, T>& model, Data<S, T>& data, DerivativeData<S, T>& dd,
                           const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                           const Eigen::MatrixBase<QDD>& qdd, const Ext& fext, ForceFrame frame,
                           bool after_minv = false, Solve&& solve = nullptr) {
  DerivativeRoot<S> root;
  root.a = -model.gravity_motion();
  rnea_derivatives_tree(model, data, dd.bodies, q, qd, qdd, fext, frame, root, model.gravity(), 0, dd.dtau_dq,
                        dd.dtau_dv, data.tau, after_minv, std::forward<Solve>(solve));
}
}  // namespace detail

/// ∂τ/∂q and ∂τ/∂q̇ of τ = RNEA(q, q̇, q̈, fext) into `dd.dtau_dq`, `dd.dtau_dv` (n × n, row = joint of τ,
/// column = joint differentiated), and τ itself into `data.tau`. `fext` and `frame` as for `rnea`: body-frame
/// forces turn with their body, base-frame forces stay fixed when q changes. ∂τ/∂q̈ is H (`crba`). No allocation.
template <class S, class T, class Q, class QD, class QDD, class Ext = NoExternalForces>
void rnea_derivatives(const Model<S, T>& model, Data<S, T>& data, DerivativeData<S, T>& dd,
                      const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                      const Eigen::MatrixBase<QDD>& qdd, const Ext& fext = Ext(),
                      ForceFrame frame = ForceFrame::Body) {
  detail::check_sizes(model, "rnea_derivatives", "q", q, "qd", qd, "qdd", qdd);
  detail::rnea_derivatives_impl(model, data, dd, q, qd, qdd, fext, frame);
}

namespace detail {
/// `solve`: see rnea_derivatives_tree; here it is called with no argument once the bias forces are in data.tau (the
/// free-flyer's six too), and must write q̈ into what `a` reads.
template <class S, class T, class Q, class V, class A, class Ext, class Solve = std::nullptr_t>
void rnea_derivatives_impl(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                           FloatingDerivativeData<S, T>& dd, const Eigen::MatrixBase<Q>& q,
                           const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, const Ext& fext,
                           ForceFrame frame, bool after_minv = false, Solve&& solve = nullptr) {
  constexpr bool X = has_external_v<Ext>;
  constexpr bool Solving = !std::is_same_v<std::decay_t<Solve>, std::nullptr_t>;
  constexpr int NJ = FloatingModel<S, T>::NJ;
  const int n = model.njoints();
  data.X0 = root_transform<S>(q);
  const Vector3<S> g = data.X0.E * model.gravity();  // gravity in root coordinates
  DerivativeRoot<S> root;
  root.floating = true;
  root.v = root_motion(v).template cast<S>();
  if constexpr (Solving) root.a = Motion<S>::Zero();  // q̈ = 0 until `solve`
  else root.a = root_motion(a).template cast<S>();
  root.a.v -= g;
  data.v0 = root.v;
  data.a0 = root.a;
  const Inertia<S>& I0 = model.root_inertia();
  const Force<S> h0 = I0 * root.v;
  root.Ic = I0;
  root.hc = h0;
  root.M = VelocityCoupling<S>::of(I0, root.v);
  root.F = I0 * root.a + cross(root.v, h0);
  const bool world_forces = X && frame == ForceFrame::Base;
  if constexpr (X) {
    if (world_forces) {
      root.Fx = data.X0.apply_force(fext[0]);
      root.F -= root.Fx;
    } else {
      root.F -= fext[0];
    }
  }
  const auto qj = joint_block<NJ>(q, 7, n);
  const auto vj = joint_block<NJ>(v, 6, n);
  const auto aj = joint_block<NJ>(a, 6, n);
  // With `solve`: the root's bias wrench (its own force and its children's subtrees'), then q̈, then the root's
  // acceleration and force with q̈'s free-flyer part.
  auto tree_solve = [&]() -> decltype(auto) {
    if constexpr (Solving) {
      return [&](const Force<S>& children) {
        const Force<S> w = root.F + children;
        data.tau.template head<3>() = w.f;
        data.tau.template segment<3>(3) = w.n;
        solve();
        const Motion<S> da0 = root_motion(a).template cast<S>();
        root.a += da0;
        root.F += I0 * da0;
        data.a0 = root.a;
        return da0;
      };
    } else {
      return nullptr;
    }
  };
  if constexpr (X) {
    if (world_forces) {
      const TreeForcesFromWorld<S, Ext> tf{fext, data.X0};
      rnea_derivatives_tree(model.tree(), data.tree, dd.bodies, qj, vj, aj, tf, ForceFrame::Base, root, g, 6,
                            dd.dtau_dq, dd.dtau_dv, data.tau, after_minv, tree_solve());
    } else {
      const TreeForces<Ext> tf{fext};
      rnea_derivatives_tree(model.tree(), data.tree, dd.bodies, qj, vj, aj, tf, ForceFrame::Body, root, g, 6,
                            dd.dtau_dq, dd.dtau_dv, data.tau, after_minv, tree_solve());
    }
  } else {
    rnea_derivatives_tree(model.tree(), data.tree, dd.bodies, qj, vj, aj, fext, ForceFrame::Body, root, g, 6,
                          dd.dtau_dq, dd.dtau_dv, data.tau, after_minv, tree_solve());
  }
  // The free-flyer's 6 × 6 block: rows Sₐ (Pₐ = Iᶜ₀ Sₐ, Qₐ = Bᶜ₀ᵀ Sₐ, Rₐ = Sₐ ×* Fˣ₀), columns as for any row.
  data.f0 = root.F;
  data.tau.template head<3>() = root.F.f;
  data.tau.template segment<3>(3) = root.F.n;
  for (int r = 0; r < 6; ++r) {
    Motion<S> Sa = Motion<S>::Zero();
    if (r < 3) Sa.v[r] = S(1);
    else Sa.w[r - 3] = S(1);
    const Force<S> P = root.Ic * Sa;
    const Force<S> Qr = root.M * Sa + cross(Sa, root.hc);
    const Force<S> R = cross(Sa, root.Fx);
    free_flyer_columns<S>(P, Qr, world_forces ? &R : nullptr, g, root.v,
                          [&](int c) -> decltype(auto) { return dd.dtau_dq(r, c); },
                          [&](int c) -> decltype(auto) { return dd.dtau_dv(r, c); });
  }
}
}  // namespace detail

/// The floating-base version: nv × nv matrices in the tangent space (see the file comment), τ (nv) in `data.tau`.
/// `fext` and `frame` as for the floating `rnea` (n + 1 forces, [0] on the root; `ForceFrame::Base` = world).
template <class S, class T, class Q, class V, class A, class Ext = NoExternalForces>
void rnea_derivatives(const FloatingModel<S, T>& model, FloatingData<S, T>& data, FloatingDerivativeData<S, T>& dd,
                      const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a,
                      const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_q(model, q, "rnea_derivatives");
  detail::check_v(model, v, "rnea_derivatives", "v");
  detail::check_v(model, a, "rnea_derivatives", "a");
  detail::rnea_derivatives_impl(model, data, dd, q, v, a, fext, frame);
}

namespace detail {
/// Rows [k0 L, (k0 + K) L) of column c of NP products −H⁻¹ Dₚ (L: Eigen's packet size), in NP K packets that stay in
/// registers: `mi` is H⁻¹ with `p` rows (n rounded up to whole packets, zeros below n), d[ₚ] the n × n Dₚ, o[ₚ] the
/// n × n result, column c's structural non-zeros rows[t0 … t1 − 1]; the rows from n on are not stored.
template <int K, int NP, class S>
inline void product_strip(const S* mi, int p, const S* const* d, S* const* o, int n, int c, const int* rows, int t0,
                          int t1, int k0) {
  using Packet = typename Eigen::internal::packet_traits<S>::type;
  constexpr int L = static_cast<int>(sizeof(Packet) / sizeof(S));  // (unpacket_traits<Packet>: g++ -Wignored-attributes)
  Packet y[NP][K];
  for (int j = 0; j < NP; ++j)
    for (int k = 0; k < K; ++k) y[j][k] = Eigen::internal::pset1<Packet>(S(0));
  const S* const strip = mi + k0 * L;
  for (int t = t0; t < t1; ++t) {
    const int r = rows[t];
    Packet x[NP];
    for (int j = 0; j < NP; ++j) x[j] = Eigen::internal::pset1<Packet>(-d[j][c * n + r]);
    const S* const col = strip + r * p;
    for (int k = 0; k < K; ++k) {
      const Packet m = Eigen::internal::ploadu<Packet>(col + k * L);
      for (int j = 0; j < NP; ++j) y[j][k] = Eigen::internal::pmadd(m, x[j], y[j][k]);
    }
  }
  for (int k = 0; k < K; ++k) {
    const int row = (k0 + k) * L;
    for (int j = 0; j < NP; ++j) {
      S* const out = o[j] + c * n + row;
      if (row + L <= n) {
        Eigen::internal::pstoreu(out, y[j][k]);
      } else {
        alignas(64) S tail[L];
        Eigen::internal::pstoreu(tail, y[j][k]);
        for (int i = 0; row + i < n; ++i) out[i] = tail[i];
      }
    }
  }
}

/// `product_strip` of `left` packets (0 < left < K), from packet k0 on.
template <int K, int NP, class S>
inline void product_strip_of(int left, const S* mi, int p, const S* const* d, S* const* o, int n, int c,
                             const int* rows, int t0, int t1, int k0) {
  if constexpr (K > 1) {
    if (left == K - 1) return product_strip<K - 1, NP>(mi, p, d, o, n, c, rows, t0, t1, k0);
    product_strip_of<K - 1, NP>(left, mi, p, d, o, n, c, rows, t0, t1, k0);
  }
}

/// The products of `aba_derivatives_products` over a run-time tree (floating-point scalars): column by column from
/// `minv_padded` through `product_strip`, both products at once where the column's packets for both and the two
/// broadcasts fit the registers (stance21 on AVX2: 6 packets), else one product after the other in strips of at
/// most eight packets (floating27 on AVX2: 7). Before, Eigen's loops over run-time columns (one axpy per
/// structural non-zero and product) took 60 % of the run-time stance21's `aba_derivatives`.
template <class DD, class M>
void runtime_products(DD& dd, const M& Minv) {
  using S = typename M::Scalar;
  constexpr int L = std::decay_t<DD>::kPacket, R = EIGEN_ARCH_DEFAULT_NUMBER_OF_REGISTERS;
  constexpr int Both = (R - 3) / 2, One = std::min(R - 2, 8);
  const int n = static_cast<int>(Minv.cols());
  dd.minv_padded.topRows(n) = Minv;
  const int p = static_cast<int>(dd.minv_padded.rows()), packets = p / L;
  const S* const mi = dd.minv_padded.data();
  const S* const d[2] = {dd.dtau_dq.data(), dd.dtau_dv.data()};
  S* const o[2] = {dd.dqdd_dq.data(), dd.dqdd_dv.data()};
  const int* const rows = dd.support_rows.data();
  for (int c = 0; c < n; ++c) {
    const int t0 = dd.support_start[static_cast<std::size_t>(c)];
    const int t1 = dd.support_start[static_cast<std::size_t>(c) + 1];
    if (packets <= Both) {
      product_strip_of<Both + 1, 2>(packets, mi, p, d, o, n, c, rows, t0, t1, 0);
      continue;
    }
    for (int j = 0; j < 2; ++j) {
      int k0 = 0;
      for (; k0 + One <= packets; k0 += One) product_strip<One, 1>(mi, p, d + j, o + j, n, c, rows, t0, t1, k0);
      if (k0 < packets) product_strip_of<One, 1>(packets - k0, mi, p, d + j, o + j, n, c, rows, t0, t1, k0);
    }
  }
}

/// ∂q̈/∂τ = H⁻¹, ∂q̈/∂q = −H⁻¹ ∂τ/∂q, ∂q̈/∂v = −H⁻¹ ∂τ/∂v. H⁻¹ is dense but ∂τ/∂q and ∂τ/∂v have H's pattern
/// (`support_rows`), so column c of each product sums only the columns of H⁻¹ of the joints related to c: 301 of
/// 441 per product for stance21 (rooted at a sole, the stance leg is everyone's ancestor), 409 of 729 for
/// floating27. (Eigen's dense product, its blocked kernel and packing, took a quarter of `aba_derivatives`'
/// instructions on stance21.) H⁻¹ is read from `minv_padded`, whose columns are whole packets: the column sums stay
/// in registers (n = 21 is no multiple of a packet, and Eigen went through 2-wide packets for a column of H⁻¹
/// itself); run-time trees through `runtime_products`.
template <class DD, class M>
void aba_derivatives_products(DD& dd, const M& Minv) {
  using S = typename M::Scalar;
  constexpr int N = std::decay_t<DD>::kCols, P = std::decay_t<DD>::kPadded;
  dd.dqdd_dtau = Minv;
  const int* const rows = dd.support_rows.data();
  constexpr int L = std::decay_t<DD>::kPacket, K = P / L;
  // Both products' columns (2 K packets) and the two broadcasts must fit the vector registers, or they spill
  // (floating27 on AVX2: 2 · 7 + 2 > 16, which made clang's ABA derivatives 15 % slower than one product at a time).
  constexpr bool in_registers = P != 0 && std::is_floating_point_v<S> &&
                                2 * K + 3 <= EIGEN_ARCH_DEFAULT_NUMBER_OF_REGISTERS;
  if constexpr (N == Eigen::Dynamic && std::is_floating_point_v<S>) {
    runtime_products(dd, Minv);
  } else if constexpr (in_registers) {
    dd.minv_padded.template topRows<N>() = Minv;
    // Column c of both products at once, in 2 K packets: each column of H⁻¹ is loaded once for the two.
    using Packet = typename Eigen::internal::packet_traits<S>::type;
    constexpr int Whole = N / L;
    const S* const mi = dd.minv_padded.data();
    const S* const dq = dd.dtau_dq.data();
    const S* const dv = dd.dtau_dv.data();
    for (int c = 0; c < N; ++c) {
      Packet yq[K], yv[K];
      for (int k = 0; k < K; ++k) yq[k] = yv[k] = Eigen::internal::pset1<Packet>(S(0));
      const int t0 = dd.support_start[static_cast<std::size_t>(c)];
      const int t1 = dd.support_start[static_cast<std::size_t>(c) + 1];
      for (int t = t0; t < t1; ++t) {
        const int r = rows[t];
        const Packet bq = Eigen::internal::pset1<Packet>(-dq[c * N + r]);
        const Packet bv = Eigen::internal::pset1<Packet>(-dv[c * N + r]);
        const S* const col = mi + r * P;
        for (int k = 0; k < K; ++k) {
          const Packet m = Eigen::internal::ploadu<Packet>(col + k * L);
          yq[k] = Eigen::internal::pmadd(m, bq, yq[k]);
          yv[k] = Eigen::internal::pmadd(m, bv, yv[k]);
        }
      }
      S* const oq = dd.dqdd_dq.data() + c * N;
      S* const ov = dd.dqdd_dv.data() + c * N;
      for (int k = 0; k < Whole; ++k) {
        Eigen::internal::pstoreu(oq + k * L, yq[k]);
        Eigen::internal::pstoreu(ov + k * L, yv[k]);
      }
      if constexpr (N % L != 0) {
        alignas(64) S tail[2][L];
        Eigen::internal::pstoreu(tail[0], yq[Whole]);
        Eigen::internal::pstoreu(tail[1], yv[Whole]);
        for (int i = 0; i < N % L; ++i) {
          oq[Whole * L + i] = tail[0][i];
          ov[Whole * L + i] = tail[1][i];
        }
      }
    }
  } else {
    // One product after the other, column by column (AD scalars, and compile-time trees too large for the above).
    if constexpr (P != 0) dd.minv_padded.template topRows<N>() = Minv;
    for (Eigen::Index c = 0; c < Minv.cols(); ++c) {
      const int t0 = dd.support_start[static_cast<std::size_t>(c)];
      const int t1 = dd.support_start[static_cast<std::size_t>(c) + 1];  // > t0: row c itself
      auto sum = [&](const auto& Mi, const auto& D, auto&& y) {
        y.noalias() = Mi.col(rows[t0]) * -D(rows[t0], c);
        for (int t = t0 + 1; t < t1; ++t) y.noalias() -= Mi.col(rows[t]) * D(rows[t], c);
      };
      if constexpr (P != 0) {
        Eigen::Matrix<S, P, 1> y;
        sum(dd.minv_padded, dd.dtau_dq, y);
        dd.dqdd_dq.col(c) = y.template head<N>();
        sum(dd.minv_padded, dd.dtau_dv, y);
        dd.dqdd_dv.col(c) = y.template head<N>();
      } else {
        sum(Minv, dd.dtau_dq, dd.dqdd_dq.col(c));
        sum(Minv, dd.dtau_dv, dd.dqdd_dv.col(c));
      }
    }
  }
}
}  // namespace detail

/// ∂q̈/∂q, ∂q̈/∂q̇ and ∂q̈/∂τ = H⁻¹ of q̈ = FD(q, q̇, τ, fext) into `dd` (n × n), and q̈ into `data.qdd`: H⁻¹ by
/// `inverse_inertia` (into `dd.minv`), q̈ = H⁻¹ (τ − RNEA(q, q̇, 0, fext)), RNEA's derivatives at (q, q̇, q̈), and
/// ∂q̈/∂x = −H⁻¹ ∂τ/∂x. `data.tau` holds τ on return (RNEA at q̈), `data.tmp` τ minus the bias forces.
template <class S, class T, class Q, class QD, class Tau, class Ext = NoExternalForces>
void aba_derivatives(const Model<S, T>& model, Data<S, T>& data, DerivativeData<S, T>& dd,
                     const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                     const Eigen::MatrixBase<Tau>& tau, const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_sizes(model, "aba_derivatives", "q", q, "qd", qd, "tau", tau);
  // H⁻¹, leaving the body inertias in base coordinates where the derivatives' forward pass reads them (after_minv).
  const auto& Minv = detail::inverse_inertia_impl<true>(model, data, dd.minv, q, dd.bodies.Ic.data());
  const auto solve = [&] {
    data.tmp = tau - data.tau;
    data.qdd.noalias() = Minv * data.tmp;
  };
#if SPATIAL_SIMD_AVX2
  if constexpr (detail::simd_candidate<S, T>()) {
    if (detail::simd_applies(model)) {
      // The bias forces from the derivatives' own forward pass (rnea_derivatives_tree's `solve`).
      detail::rnea_derivatives_impl(model, data, dd, q, qd, data.qdd, fext, frame, true, [&](const Force<S>&) {
        solve();
        return Motion<S>::Zero();
      });
      detail::aba_derivatives_products(dd, Minv);
      return;
    }
  }
#endif
  // The bias forces RNEA(q, q̇, 0, fext): RNEA without its acceleration term (q̈ = 0 is not added in).
  detail::rnea_impl<detail::kGravity | detail::kVelocity>(model, data, q, qd, qd, fext, frame, data.tau);
  solve();
  detail::rnea_derivatives_impl(model, data, dd, q, qd, data.qdd, fext, frame, true);
  detail::aba_derivatives_products(dd, Minv);
}

/// The floating-base version (nv × nv, tangent space), q̈ (nv) into `data.qdd`.
template <class S, class T, class Q, class V, class Tau, class Ext = NoExternalForces>
void aba_derivatives(const FloatingModel<S, T>& model, FloatingData<S, T>& data, FloatingDerivativeData<S, T>& dd,
                     const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                     const Eigen::MatrixBase<Tau>& tau, const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_q(model, q, "aba_derivatives");
  detail::check_v(model, v, "aba_derivatives", "v");
  detail::check_v(model, tau, "aba_derivatives", "tau");
  const auto& Minv = detail::inverse_inertia_impl<true>(model, data, dd.minv, q, dd.bodies.Ic.data());
  const auto solve = [&] {
    data.tmp = tau - data.tau;
    data.qdd.noalias() = Minv * data.tmp;
  };
#if SPATIAL_SIMD_AVX2
  if constexpr (detail::simd_candidate<S, T>()) {
    if (detail::simd_applies(model.tree())) {
      detail::rnea_derivatives_impl(model, data, dd, q, v, data.qdd, fext, frame, true, solve);
      detail::aba_derivatives_products(dd, Minv);
      return;
    }
  }
#endif
  detail::rnea_floating<detail::kGravity | detail::kVelocity>(model, data, q, v, v, fext, frame, data.tau);
  solve();
  detail::rnea_derivatives_impl(model, data, dd, q, v, data.qdd, fext, frame, true);
  detail::aba_derivatives_products(dd, Minv);
}

// ---------------------------------------------------------------------------------------------------------------
// Derivatives of frame velocities and accelerations
// ---------------------------------------------------------------------------------------------------------------

/// Output of `frame_kinematics_derivatives`: 6 × nv matrices, rows linear first like every Jacobian of
/// kinematics.hpp (vx vy vz ωx ωy ωz), columns the velocity coordinates (floating base: free-flyer first).
template <class S, int NV = Eigen::Dynamic>
struct FrameKinematicsDerivatives {
  using Matrix = Eigen::Matrix<S, 6, detail::matrix_dim(NV)>;
  explicit FrameKinematicsDerivatives(int nv)
      : v_dq(Matrix::Zero(6, nv)), v_dv(Matrix::Zero(6, nv)), a_dq(Matrix::Zero(6, nv)), a_dv(Matrix::Zero(6, nv)),
        a_da(Matrix::Zero(6, nv)) {}
  template <class M, class = decltype(std::declval<const M&>().nv())>
  explicit FrameKinematicsDerivatives(const M& model) : FrameKinematicsDerivatives(model.nv()) {}
  Matrix v_dq;  ///< ∂v_F/∂q (tangent space)
  Matrix v_dv;  ///< ∂v_F/∂v = the frame Jacobian in rf
  Matrix a_dq;  ///< ∂a_F/∂q (spatial acceleration)
  Matrix a_dv;  ///< ∂a_F/∂v
  Matrix a_da;  ///< ∂a_F/∂a = the frame Jacobian in rf
};

namespace detail {
/// The columns of `frame_kinematics_derivatives` for the frame ᶠX_w = Xfw on `body`, after forward kinematics.
template <class K, class Out>
void frame_derivative_columns(const K& k, int body, const Transform<typename K::Scalar>& Xfw, ReferenceFrame rf,
                              Out& out) {
  using S = typename K::Scalar;
  const auto world_of = [&](int i, const Motion<S>& m) { return k.world(i).apply_inverse(m); };
  const Motion<S> v0 = world_of(body, k.velocity(body)), a0 = world_of(body, k.acceleration(body));
  // The frame's velocity and acceleration in rf (LocalWorldAligned: for the turning of the axes).
  const Motion<S> vf = world_to_frame(rf, Xfw, v0), af = world_to_frame(rf, Xfw, a0);
  // One column from its world-coordinate derivatives (angular first); `dm_dq` = ∂(v⁰ or a⁰)/∂q, m = v⁰ or a⁰.
  const auto put = [&](auto& M, int c, const Motion<S>& d, const Motion<S>& s, const Motion<S>* m,
                       const Motion<S>* mf) {
    Motion<S> x = d;
    switch (rf) {
      case ReferenceFrame::World: break;
      case ReferenceFrame::Local: x = Xfw.apply(m ? d - cross(s, *m) : d); break;
      case ReferenceFrame::LocalWorldAligned: {
        // Local derivative rotated to world axes, plus the turning of those axes (ω_s × both parts).
        x = local_to_frame(rf, Xfw, Xfw.apply(m ? d - cross(s, *m) : d));
        if (m) {
          x.w = add3(x.w, cross3(s.w, mf->w));
          x.v = add3(x.v, cross3(s.w, mf->v));
        }
        break;
      }
    }
    set_jacobian_column(M, c, x);
  };
  for (int j = body; j >= 0; j = k.tree.parent(j)) {
    const int p = k.tree.parent(j);
    const Motion<S> s = world_of(j, k.tree.joint(j).motion(S(1)));
    Motion<S> vp = Motion<S>::Zero(), ap = Motion<S>::Zero();
    if (p >= 0 || K::root_cols > 0) {
      vp = world_of(p, k.velocity(p));
      ap = world_of(p, k.acceleration(p));
    }
    const Motion<S> beta = cross(s, vp);
    const int c = K::root_cols + j;
    put(out.v_dq, c, cross(s, v0 - vp), s, &v0, &vf);
    put(out.v_dv, c, s, s, nullptr, nullptr);
    put(out.a_dq, c, cross(s, a0 - ap) + cross(v0 - vp, beta), s, &a0, &af);
    put(out.a_dv, c, cross(s, v0) - beta - beta, s, nullptr, nullptr);
    put(out.a_da, c, s, s, nullptr, nullptr);
  }
  if constexpr (K::root_cols > 0) {
    // The free-flyer: q ⊕ δ moves everything rigidly (∂m/∂q_b = S_b × m); its acceleration is v̇ itself, so
    // ∂a/∂v_b = S_b × (v⁰ − v⁰_root).
    const Motion<S> vr = world_of(-1, k.velocity(-1));
    for (int b = 0; b < 6; ++b) {
      const Motion<S> s = free_flyer_world_column(k.world(-1), b);
      put(out.v_dq, b, cross(s, v0), s, &v0, &vf);
      put(out.v_dv, b, s, s, nullptr, nullptr);
      put(out.a_dq, b, cross(s, a0), s, &a0, &af);
      put(out.a_dv, b, cross(s, v0 - vr), s, nullptr, nullptr);
      put(out.a_da, b, s, s, nullptr, nullptr);
    }
  }
}
}  // namespace detail

/// Derivatives of frame `frame`'s spatial velocity and spatial acceleration (no gravity), in the reference frame
/// `rf` (as `frame_velocity` / `frame_acceleration` after `forward_kinematics(q, v, a)`), with respect to q (in the
/// tangent space: column k is d/dε at q ⊕ ε eₖ), v and a, into `out` (6 × nv each, rows linear first; columns of
/// joints that do not move the frame are zero). Runs `forward_kinematics(q, v, a)` (data as it leaves it).
/// In world coordinates, for a joint j moving the frame's body (S = S⁰ⱼ, parent velocity/acceleration v_p, a_p,
/// β = S × v_p):  ∂v/∂qⱼ = S × (v − v_p),  ∂a/∂qⱼ = S × (a − a_p) + (v − v_p) × β,  ∂a/∂vⱼ = S × v − 2β,
/// ∂v/∂vⱼ = ∂a/∂aⱼ = S. Local: ∂(ᶠX_w m)/∂qⱼ = ᶠX_w (∂m/∂qⱼ − S × m); LocalWorldAligned: the Local derivative
/// rotated to world axes plus ω_S × (both parts of the frame's vector). Pinocchio's `getFrameVelocityDerivatives`
/// and `getFrameAccelerationDerivatives` compute the same matrices (v_partial_dq, a_partial_dq, …) in its LOCAL,
/// WORLD and LOCAL_WORLD_ALIGNED. No allocation.
template <class S, class T, int NV, class Q, class V, class A>
void frame_kinematics_derivatives(const Model<S, T>& model, Data<S, T>& data, FrameKinematicsDerivatives<S, NV>& out,
                                  const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<V>& v,
                                  const Eigen::MatrixBase<A>& a, int frame, ReferenceFrame rf) {
  forward_kinematics(model, data, q, v, a);
  const auto k = detail::kin(model, data);
  out.v_dq.setZero(), out.v_dv.setZero(), out.a_dq.setZero(), out.a_dv.setZero(), out.a_da.setZero();
  int body;
  const Transform<S> Xfw = detail::frame_world(k, frame, body);
  detail::frame_derivative_columns(k, body, Xfw, rf, out);
}
/// The floating-base version (nv columns, free-flyer first; its q columns in the tangent space).
template <class S, class T, int NV, class Q, class V, class A>
void frame_kinematics_derivatives(const FloatingModel<S, T>& model, FloatingData<S, T>& data,
                                  FrameKinematicsDerivatives<S, NV>& out, const Eigen::MatrixBase<Q>& q,
                                  const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, int frame,
                                  ReferenceFrame rf) {
  forward_kinematics(model, data, q, v, a);
  const auto k = detail::kin(model, data);
  out.v_dq.setZero(), out.v_dv.setZero(), out.a_dq.setZero(), out.a_dv.setZero(), out.a_da.setZero();
  int body;
  const Transform<S> Xfw = detail::frame_world(k, frame, body);
  detail::frame_derivative_columns(k, body, Xfw, rf, out);
}

}  // namespace spatial

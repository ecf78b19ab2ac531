#pragma once
/// \file options.hpp
/// Pay only for what a scene uses: compile-time choices of the terms of the equations of motion
///
///   τ = H(q) q̈ + C(q, q̇) q̇ + G(q) − Σ Jᵢᵀ fᵢˣ
///
/// for RNEA, ABA and forward dynamics by CRBA + LTDL. A scene is one use of the dynamics: a static pose needs only
/// G(q); a quasi-static gesture (q̇ ≈ 0) needs H q̈ + G; a simulation in free fall or a horizontal plane needs no G.
/// The options are a `Dyn` flag set given as the first template argument:
///
///   rnea<Dyn::Gravity | Dyn::Acceleration>(model, data, q, qd, qdd)    // H q̈ + G: q̇ = 0, qd is never read
///   aba<Dyn::Gravity>(model, data, q, qd, tau)                         // q̈ from rest: qd is never read
///   forward_dynamics_crba<Dyn::Velocity>(model, data, q, qd, tau)      // no gravity
///
/// What is switched off generates no code: every flag is tested with `if constexpr`, so an unused input (qd
/// without `Velocity`, qdd without `Acceleration`) is not loaded, and no term is multiplied by zero. External
/// forces are switched on by passing them (the `NoExternalForces` default compiles them out). The calls without a
/// template argument (`rnea(model, data, q, qd, qdd)`, …) are unchanged and equal `Dyn::Full`.
///
/// Equations (RBDA Table 5.1 and 7.1; gravity enters as the base acceleration a₀ = −a_g, RBDA §5.3):
///   Gravity       a₀ = −a_g (off: a₀ = 0)
///   Velocity      vᵢ = ⁱX_λ v_λ + Sᵢ q̇ᵢ, the velocity-product acceleration cᵢ = vᵢ × Sᵢ q̇ᵢ and the bias force
///                 vᵢ ×* Iᵢ vᵢ (off: vᵢ = 0, so cᵢ = 0 and vᵢ ×* Iᵢ vᵢ = 0: these are not computed)
///   Acceleration  RNEA only: the Sᵢ q̈ᵢ term of aᵢ (off: q̈ = 0)
///   BaseForces    RNEA only: after the torques, `data.f[i]` (the force transmitted across joint i from body λ(i)
///                 to body i) is expressed in base coordinates, moment about the base origin, instead of body i's:
///                 f⁰ᵢ = ⁰Xᵢ* fᵢ. For a model rooted at a sole, f⁰₀ is the wrench that the foot's base link passes
///                 to the ankle, from which the contact wrench and the centre of pressure follow. Costs one
///                 transform composition and one force transform per body (`data.X_base` is filled too).
/// Without `BaseForces`, `data.f` holds the transmitted forces in body coordinates, as `rnea` always did: they
/// are needed for the torques anyway, so "torques only" has nothing more to skip (bench/bench_scenes.cpp measures
/// both).

#include "spatial/algorithms.hpp"
#include "spatial/sizes.hpp"

#include <type_traits>

namespace spatial {

/// Terms of the dynamics a scene needs; combine with `|`.
enum class Dyn : unsigned {
  None = 0u,
  Gravity = 1u,       ///< gravity (a₀ = −a_g)
  Velocity = 2u,      ///< every q̇ term (Coriolis, centrifugal, gyroscopic)
  Acceleration = 4u,  ///< RNEA: the q̈ term
  BaseForces = 8u,    ///< RNEA: `data.f` in base coordinates (see the file comment)
  Full = 7u,          ///< Gravity | Velocity | Acceleration: what the calls without options compute
  Static = 1u,        ///< Gravity alone: G(q) (a static pose; aba: q̈ from rest)
  QuasiStatic = 5u,   ///< Gravity | Acceleration: H q̈ + G (q̇ = 0)
  NoGravity = 6u,     ///< Velocity | Acceleration
};

constexpr Dyn operator|(Dyn a, Dyn b) { return static_cast<Dyn>(static_cast<unsigned>(a) | static_cast<unsigned>(b)); }
constexpr Dyn operator&(Dyn a, Dyn b) { return static_cast<Dyn>(static_cast<unsigned>(a) & static_cast<unsigned>(b)); }
/// True when every flag of `what` is in `set`.
constexpr bool has(Dyn set, Dyn what) { return (set & what) == what; }

namespace detail {
/// The `rnea_impl` term mask of a flag set.
constexpr unsigned rnea_terms(Dyn o) {
  return (has(o, Dyn::Gravity) ? kGravity : 0u) | (has(o, Dyn::Velocity) ? kVelocity : 0u) |
         (has(o, Dyn::Acceleration) ? kAcceleration : 0u);
}

/// `data.f[i]` from body i coordinates into base coordinates (f⁰ᵢ = ⁰Xᵢ* fᵢ), filling `data.X_base` from the
/// `data.X_up` of the last pass (`have_base`: X_base is already up to date).
template <class S, class T>
void forces_to_base(const Model<S, T>& model, Data<S, T>& data, bool have_base) {
  for_each_body(model, [&](auto I) {
    const auto k = static_cast<std::size_t>(int(I));
    const int p = model.parent(I);
    if (!have_base) data.X_base[k] = p >= 0 ? data.X_up[k] * data.X_base[static_cast<std::size_t>(p)] : data.X_up[k];
    data.f[k] = data.X_base[k].apply_force_inverse(data.f[k]);
  });
}
}  // namespace detail

/// Inverse dynamics with the terms of `O` only (see the file comment): τ = [H q̈]_A + [C q̇]_V + [G]_G − Σ Jᵢᵀ fᵢˣ.
/// `qd` is not read without `Dyn::Velocity`, `qdd` not without `Dyn::Acceleration` (pass any vector of the right
/// size, e.g. q). With `Dyn::BaseForces`, `data.f` ends in base coordinates. Returns `data.tau`.
template <Dyn O, class S, class T, class Q, class QD, class QDD, class Ext = NoExternalForces>
const typename Data<S, T>::VectorN& rnea(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                         const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd,
                                         const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_sizes(model, "rnea", "q", q, "qd", qd, "qdd", qdd);
  detail::rnea_impl<detail::rnea_terms(O)>(model, data, q, qd, qdd, fext, frame, data.tau);
  if constexpr (has(O, Dyn::BaseForces)) {
    constexpr bool X = detail::has_external_v<Ext>;
    detail::forces_to_base(model, data, X && frame == ForceFrame::Base);
  }
  return data.tau;
}

/// Forward dynamics by the articulated-body algorithm (RBDA Table 7.1, as `aba` in algorithms.hpp) with the terms
/// of `O`: without `Dyn::Velocity`, vᵢ = cᵢ = 0 and pᴬᵢ starts at −fᵢˣ (or 0), so pass 1 reduces to the transforms
/// and pass 2 drops Iᵃ cᵢ; without `Dyn::Gravity`, a₀ = 0. `Acceleration` and `BaseForces` do not apply.
/// Returns `data.qdd`.
template <Dyn O, class S, class T, class Q, class QD, class Tau, class Ext = NoExternalForces>
const typename Data<S, T>::VectorN& aba(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                                        const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau,
                                        const Ext& fext = Ext(), ForceFrame frame = ForceFrame::Body) {
  detail::check_sizes(model, "aba", "q", q, "qd", qd, "tau", tau);
  detail::aba_impl<has(O, Dyn::Gravity), has(O, Dyn::Velocity)>(model, data, q, qd, tau, fext, frame);
  return data.qdd;
}

/// Forward dynamics by CRBA and LTDL (as `forward_dynamics_crba`) with the bias terms of `O`: q̈ = H⁻¹ (τ − [C q̇]_V
/// − [G]_G). Without gravity and velocity the bias pass is skipped and only the transforms are computed.
/// Returns `data.qdd`.
template <Dyn O, class S, class T, class Q, class QD, class Tau>
const typename Data<S, T>::VectorN& forward_dynamics_crba(const Model<S, T>& model, Data<S, T>& data,
                                                          const Eigen::MatrixBase<Q>& q,
                                                          const Eigen::MatrixBase<QD>& qd,
                                                          const Eigen::MatrixBase<Tau>& tau) {
  detail::check_sizes(model, "forward_dynamics_crba", "q", q, "qd", qd, "tau", tau);
  constexpr unsigned terms = detail::rnea_terms(O) & ~unsigned(detail::kAcceleration);
  detail::forward_dynamics_crba_impl<terms>(model, data, q, qd, tau);
  return data.qdd;
}

}  // namespace spatial

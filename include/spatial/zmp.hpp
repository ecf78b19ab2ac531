#pragma once
/// \file zmp.hpp
/// The ground's wrench on a robot, the zero-moment point (ZMP) of the multibody model and the centre of pressure
/// (CoP) of contact forces.
///
///   - `base_wrench(q, v, v̇)`: the wrench the environment must apply to the base for the motion, the joints
///     supplying their torques: floating base, τ's first six entries of RNEA (the root's wrench), as a `Force`
///     (moment about the root's origin, then force; root coordinates); fixed base, the base's reaction on the
///     bodies hanging from it, Σ ⁰Xᵢᵀ fᵢ over the base's children (base coordinates). Gravity is included.
///     `base_wrench_world` gives the floating one in world coordinates (moment about the world origin).
///   - `zmp_on_plane(w, h)`: for a wrench w = (n about the origin, f) that the ground applies, the point p on the plane
///     z = h of the same frame where the moment of w has no horizontal component:
///       p_x = (h f_x − n_y) / f_z,  p_y = (n_x + h f_y) / f_z,  p_z = h;
///     NaN when f_z ≤ 0 (nothing pushes the robot up: no ZMP).
///   - `multibody_zmp(q, v, v̇, h)`: the ZMP of the whole model's gravity and inertia forces (floating base: world
///     coordinates, ground plane z = h; fixed base: base coordinates, plane z = h of the base frame).
///   - `contact_wrench(cd)`: the sum of the contact forces of `cd` (after `constrained_forward_dynamics` or
///     `contact_inverse_dynamics`: `cd.lambda` and `data`'s poses at the same q), world coordinates, moment about
///     the world origin; `center_of_pressure(cd, h)` = `zmp_on_plane(contact_wrench(cd), h)`.
/// When the contacts are the only external forces, the CoP of the contact forces and the multibody ZMP are the same
/// point (Newton–Euler for the whole robot); tests/test_contact.cpp checks it.

#include "spatial/algorithms.hpp"
#include "spatial/contact.hpp"
#include "spatial/floating.hpp"

#include <limits>

namespace spatial {

/// ZMP of the ground wrench w (moment about the frame's origin, force) on the plane z = h of the same frame; NaN
/// when w.f.z() ≤ 0.
template <class S>
Vector3<S> zmp_on_plane(const Force<S>& w, S h = S(0)) {
  if (!(w.f.z() > S(0))) return Vector3<S>::Constant(std::numeric_limits<S>::quiet_NaN());
  return Vector3<S>((h * w.f.x() - w.n.y()) / w.f.z(), (w.n.x() + h * w.f.y()) / w.f.z(), h);
}

/// The wrench the base must receive from the environment (fixed base: base coordinates).
template <class S, class T, class Q, class V, class A>
Force<S> base_wrench(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                     const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  rnea(model, data, q, v, a);
  Force<S> w = Force<S>::Zero();
  for (int i = 0; i < model.size(); ++i)
    if (model.parent(i) < 0) {
      const auto k = static_cast<std::size_t>(i);
      const Force<S> f = data.X_up[k].apply_force_inverse(data.f[k]);
      w.n += f.n;
      w.f += f.f;
    }
  return w;
}

/// The wrench the root must receive (floating base: root coordinates, moment about the root's origin).
template <class S, class T, class Q, class V, class A>
Force<S> base_wrench(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                     const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  const auto& tau = rnea(model, data, q, v, a);
  return Force<S>(Vector3<S>(tau.template segment<3>(3)), Vector3<S>(tau.template head<3>()));
}

/// The same in world coordinates, moment about the world origin.
template <class S, class T, class Q, class V, class A>
Force<S> base_wrench_world(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                           const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a) {
  const Force<S> w = base_wrench(model, data, q, v, a);
  return data.X0.apply_force_inverse(w);
}

/// ZMP of the whole model's motion on the plane z = h (fixed base: base frame).
template <class S, class T, class Q, class V, class A>
Vector3<S> multibody_zmp(const Model<S, T>& model, Data<S, T>& data, const Eigen::MatrixBase<Q>& q,
                         const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, S h = S(0)) {
  return zmp_on_plane(base_wrench(model, data, q, v, a), h);
}
/// Floating base: world coordinates, ground plane z = h.
template <class S, class T, class Q, class V, class A>
Vector3<S> multibody_zmp(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Eigen::MatrixBase<Q>& q,
                         const Eigen::MatrixBase<V>& v, const Eigen::MatrixBase<A>& a, S h = S(0)) {
  return zmp_on_plane(base_wrench_world(model, data, q, v, a), h);
}

/// Sum of the contact forces in `cd.lambda` (world coordinates, moment about the world origin), with the frames'
/// poses of `data` (the q of the call that filled `cd.lambda`).
template <class ModelT, class DataT>
Force<typename ModelT::Scalar> contact_wrench(const ModelT& model, const DataT& data, const ContactData<ModelT>& cd) {
  using S = typename ModelT::Scalar;
  const auto k = detail::kin(model, data);
  Force<S> total = Force<S>::Zero();
  int r = 0;
  for (const RigidContact<S>& c : cd.contacts) {
    int body;
    const Transform<S> X = detail::frame_world(k, c.frame, body);  // E = Rᵀ, r = p
    const bool local = c.reference == ReferenceFrame::Local;
    const Vector3<S> f0 = cd.lambda.template segment<3>(r);
    const Vector3<S> f = local ? Vector3<S>(X.E.transpose() * f0) : f0;
    Vector3<S> n = X.r.cross(f);
    if (c.type == ContactType::Contact6D) {
      const Vector3<S> n0 = cd.lambda.template segment<3>(r + 3);
      n += local ? Vector3<S>(X.E.transpose() * n0) : n0;
    }
    total.f += f;
    total.n += n;
    r += c.dim();
  }
  return total;
}

/// CoP of the contact forces on the plane z = h (world).
template <class ModelT, class DataT>
Vector3<typename ModelT::Scalar> center_of_pressure(const ModelT& model, const DataT& data, const ContactData<ModelT>& cd,
                                                    typename ModelT::Scalar h = 0) {
  return zmp_on_plane(contact_wrench(model, data, cd), h);
}

}  // namespace spatial

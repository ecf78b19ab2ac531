#pragma once
/// \file pinocchio_peer.hpp
/// Pinocchio as a peer: any spatial model (compile-time or run-time tree, in double or float) converted, in this
/// one place, into a pinocchio::ModelTpl built programmatically, so that Pinocchio runs on exactly the same numbers.
///
/// Conventions at the boundary:
///  - Pinocchio placements are ACTIVE SE3 poses (rotation, translation) of the child frame in the parent frame.
///    Our X_T(i) = (E, r) is passive, so joint i's placement in its parent joint's frame is SE3(Eᵀ, r).
///  - Joint models: RevoluteX/Y/Z → JointModelRX/RY/RZ, RevoluteAxis → JointModelRevoluteUnaligned(a),
///    PrismaticX/Y/Z → JointModelPX/PY/PZ, PrismaticAxis → JointModelPrismaticUnaligned(a); the joint moves the body
///    frame relative to the placed joint frame, as ours does, and the body frame is the joint frame.
///  - Body inertia: pinocchio::Inertia(m, c, I_c) with c and I_c (about the centre of mass) in body coordinates,
///    appended to its joint with an identity placement.
///  - Gravity: model.gravity = Motion(linear g, angular 0), g in base coordinates.
///  - Pinocchio stores spatial vectors linear first; only joint-space quantities cross this boundary.
///  - Pinocchio requires joints in depth-first order (a subtree's degrees of freedom must be contiguous). Our
///    bodies only need parents before children, so the peer keeps a permutation: Pinocchio's joint k (q index k)
///    is our body `order[k]`. Inputs are permuted once when the pool is built; results are permuted back only in
///    the check, never in the timed loop.

#include <spatial/spatial.hpp>

#include <pinocchio/multibody.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace spatial::peers {

template <class S>
struct PinocchioPeer {
  pinocchio::ModelTpl<S> model;
  std::vector<int> order;  ///< order[k] = our body index of Pinocchio's k-th degree of freedom

  /// Our joint-space vector → Pinocchio's order.
  template <class V>
  Eigen::Matrix<S, Eigen::Dynamic, 1> to_pinocchio(const V& v) const {
    Eigen::Matrix<S, Eigen::Dynamic, 1> out(static_cast<Eigen::Index>(order.size()));
    for (std::size_t k = 0; k < order.size(); ++k) out[Eigen::Index(k)] = S(v[order[k]]);
    return out;
  }
  /// Pinocchio's joint-space vector → our order.
  template <class V>
  Eigen::Matrix<S, Eigen::Dynamic, 1> from_pinocchio(const V& v) const {
    Eigen::Matrix<S, Eigen::Dynamic, 1> out(static_cast<Eigen::Index>(order.size()));
    for (std::size_t k = 0; k < order.size(); ++k) out[order[k]] = v[Eigen::Index(k)];
    return out;
  }
  /// Pinocchio's joint-space matrix → our order.
  template <class M>
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> from_pinocchio_matrix(const M& m) const {
    const auto n = static_cast<Eigen::Index>(order.size());
    Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> out(n, n);
    for (Eigen::Index a = 0; a < n; ++a)
      for (Eigen::Index b = 0; b < n; ++b) out(order[std::size_t(a)], order[std::size_t(b)]) = m(a, b);
    return out;
  }
};

/// Depth-first (pre-order) sequence of our bodies, children visited in increasing index.
template <class S, class TreeT>
std::vector<int> depth_first_order(const Model<S, TreeT>& m) {
  const int n = m.size();
  std::vector<std::vector<int>> children(static_cast<std::size_t>(n) + 1);  // slot n: the base
  for (int i = 0; i < n; ++i)
    children[static_cast<std::size_t>(m.parent(i) < 0 ? n : m.parent(i))].push_back(i);
  std::vector<int> order;
  std::function<void(int)> visit = [&](int slot) {
    for (int c : children[static_cast<std::size_t>(slot)]) {
      order.push_back(c);
      visit(c);
    }
  };
  visit(n);
  return order;
}

template <class S>
pinocchio::JointModelTpl<S> pinocchio_joint(JointType type, const Vector3<S>& axis) {
  using Collection = pinocchio::JointCollectionDefaultTpl<S>;
  switch (type) {
    case JointType::RevoluteX: return typename Collection::JointModelRX();
    case JointType::RevoluteY: return typename Collection::JointModelRY();
    case JointType::RevoluteZ: return typename Collection::JointModelRZ();
    case JointType::RevoluteAxis: return typename Collection::JointModelRevoluteUnaligned(axis);
    case JointType::PrismaticX: return typename Collection::JointModelPX();
    case JointType::PrismaticY: return typename Collection::JointModelPY();
    case JointType::PrismaticZ: return typename Collection::JointModelPZ();
    case JointType::PrismaticAxis: break;
  }
  return typename Collection::JointModelPrismaticUnaligned(axis);
}

/// Converts a model.
template <class S, class TreeT>
PinocchioPeer<S> make_pinocchio_peer(const Model<S, TreeT>& m) {
  PinocchioPeer<S> peer;
  peer.order = depth_first_order(m);
  std::vector<pinocchio::JointIndex> joint_of(static_cast<std::size_t>(m.size()), 0);
  peer.model.gravity = pinocchio::MotionTpl<S>(m.gravity(), Vector3<S>::Zero());
  for (int i : peer.order) {
    const auto k = static_cast<std::size_t>(i);
    const Transform<S>& XT = m.tree_transform(i);
    const pinocchio::SE3Tpl<S> placement(Matrix3<S>(XT.E.transpose()), XT.r);
    const pinocchio::JointIndex parent = m.parent(i) < 0 ? 0 : joint_of[static_cast<std::size_t>(m.parent(i))];
    joint_of[k] = peer.model.addJoint(parent, pinocchio_joint<S>(m.joint_type(i), m.axis(i)), placement, m.joint_name(i));
    const Inertia<S>& I = m.inertia(i);
    const Vector3<S> c = I.m > S(0) ? Vector3<S>(I.h / I.m) : Vector3<S>::Zero();
    const Matrix3<S> Ic = I.m > S(0) ? I.inertia_com() : I.I;
    peer.model.appendBodyToJoint(joint_of[k], pinocchio::InertiaTpl<S>(I.m, c, Ic), pinocchio::SE3Tpl<S>::Identity());
  }
  return peer;
}

/// A floating-base model as Pinocchio's free-flyer model: `JointModelFreeFlyer` "floating_base" at the root
/// (identity placement, the root inertia appended to it), then the tree as above with its roots on the free-flyer.
/// Pinocchio's free-flyer q, v and τ are ours (floating.hpp): [x y z qx qy qz qw] and [v ω] in the root frame,
/// linear first; gravity is the world's. `order` maps the joints as above; vectors are permuted after the first 7
/// (q) or 6 (v, τ) entries.
template <class S>
struct FloatingPinocchioPeer {
  PinocchioPeer<S> tree;  ///< model: the whole free-flyer model; order: the joints' permutation
  template <class V>
  Eigen::Matrix<S, Eigen::Dynamic, 1> to_pinocchio(const V& v, int head) const {
    Eigen::Matrix<S, Eigen::Dynamic, 1> out(v.size());
    out.head(head) = v.head(head).template cast<S>();
    out.tail(v.size() - head) = tree.to_pinocchio(v.tail(v.size() - head));
    return out;
  }
  template <class V>
  Eigen::Matrix<S, Eigen::Dynamic, 1> from_pinocchio(const V& v) const {  // v, τ, v̇ (head 6)
    Eigen::Matrix<S, Eigen::Dynamic, 1> out(v.size());
    out.head(6) = v.head(6);
    out.tail(v.size() - 6) = tree.from_pinocchio(v.tail(v.size() - 6));
    return out;
  }
  /// Our velocity index of Pinocchio's velocity index a.
  Eigen::Index ours(Eigen::Index a) const { return a < 6 ? a : 6 + tree.order[std::size_t(a - 6)]; }
  template <class M>
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> from_pinocchio_matrix(const M& m) const {
    const auto n = m.rows();
    Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> out(n, n);
    for (Eigen::Index a = 0; a < n; ++a)
      for (Eigen::Index b = 0; b < n; ++b) out(ours(a), ours(b)) = m(a, b);
    return out;
  }
  /// A matrix with one column per velocity (Jacobians, A_G): Pinocchio's column order → ours.
  template <class M>
  Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> from_pinocchio_columns(const M& m) const {
    Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> out(m.rows(), m.cols());
    for (Eigen::Index a = 0; a < m.cols(); ++a) out.col(ours(a)) = m.col(a);
    return out;
  }
};

template <class S, class TreeT>
FloatingPinocchioPeer<S> make_pinocchio_floating_peer(const FloatingModel<S, TreeT>& fm) {
  using Collection = pinocchio::JointCollectionDefaultTpl<S>;
  const Model<S, TreeT>& m = fm.tree();
  FloatingPinocchioPeer<S> peer;
  auto& pm = peer.tree.model;
  peer.tree.order = depth_first_order(m);
  pm.gravity = pinocchio::MotionTpl<S>(fm.gravity(), Vector3<S>::Zero());
  const pinocchio::JointIndex root =
      pm.addJoint(0, typename Collection::JointModelFreeFlyer(), pinocchio::SE3Tpl<S>::Identity(), kFreeFlyerName);
  const Inertia<S>& I0 = fm.root_inertia();
  pm.appendBodyToJoint(root, pinocchio::InertiaTpl<S>(I0.m, Vector3<S>(I0.h / I0.m), I0.inertia_com()),
                       pinocchio::SE3Tpl<S>::Identity());
  std::vector<pinocchio::JointIndex> joint_of(static_cast<std::size_t>(m.size()), 0);
  for (int i : peer.tree.order) {
    const auto k = static_cast<std::size_t>(i);
    const Transform<S>& XT = m.tree_transform(i);
    const pinocchio::SE3Tpl<S> placement(Matrix3<S>(XT.E.transpose()), XT.r);
    const pinocchio::JointIndex parent = m.parent(i) < 0 ? root : joint_of[static_cast<std::size_t>(m.parent(i))];
    joint_of[k] = pm.addJoint(parent, pinocchio_joint<S>(m.joint_type(i), m.axis(i)), placement, m.joint_name(i));
    const Inertia<S>& I = m.inertia(i);
    const Vector3<S> c = I.m > S(0) ? Vector3<S>(I.h / I.m) : Vector3<S>::Zero();
    const Matrix3<S> Ic = I.m > S(0) ? I.inertia_com() : I.I;
    pm.appendBodyToJoint(joint_of[k], pinocchio::InertiaTpl<S>(I.m, c, Ic), pinocchio::SE3Tpl<S>::Identity());
  }
  // Our fixed frames as Pinocchio operational frames (same names, same order after Pinocchio's own frames):
  // placement SE3(Eᵀ, r) of ᶠX_body = (E, r) in the parent joint's frame; body −1 is the root.
  for (const FixedFrame<S>& f : m.frames()) {
    const pinocchio::JointIndex parent = f.body < 0 ? root : joint_of[static_cast<std::size_t>(f.body)];
    pm.addFrame(pinocchio::FrameTpl<S>(f.name, parent, pinocchio::SE3Tpl<S>(Matrix3<S>(f.X.E.transpose()), f.X.r),
                                        pinocchio::OP_FRAME));
  }
  return peer;
}

/// A `GeneralModel` (general.hpp) as a Pinocchio model, joint for joint: spherical → `JointModelSpherical`,
/// free-flyer → `JointModelFreeFlyer`, one-DoF joints as above. Their q, v and τ are ours entry for entry (the same
/// quaternion order, body-frame velocities) when the bodies are in depth-first order, which this requires (a
/// subtree's coordinates contiguous): it returns an empty model otherwise.
template <class S>
pinocchio::ModelTpl<S> make_pinocchio_general(const GeneralModel<S>& m) {
  using Collection = pinocchio::JointCollectionDefaultTpl<S>;
  pinocchio::ModelTpl<S> pm;
  pm.gravity = pinocchio::MotionTpl<S>(m.gravity(), Vector3<S>::Zero());
  std::vector<int> stack;  // the current root-to-leaf path: each body's parent must be on it
  for (int i = 0; i < m.size(); ++i) {
    while (!stack.empty() && stack.back() != m.parent(i)) stack.pop_back();
    if (m.parent(i) >= 0 && stack.empty()) return pinocchio::ModelTpl<S>();
    stack.push_back(i);
    const Transform<S>& XT = m.tree_transform(i);
    const pinocchio::SE3Tpl<S> placement(Matrix3<S>(XT.E.transpose()), XT.r);
    const GeneralJoint<S>& j = m.joint(i);
    const pinocchio::JointModelTpl<S> joint =
        j.kind == GeneralJointKind::Spherical   ? pinocchio::JointModelTpl<S>(typename Collection::JointModelSpherical())
        : j.kind == GeneralJointKind::FreeFlyer ? pinocchio::JointModelTpl<S>(typename Collection::JointModelFreeFlyer())
                                                : pinocchio_joint<S>(j.type, j.axis);
    const auto id = pm.addJoint(pinocchio::JointIndex(m.parent(i) + 1), joint, placement, m.joint_name(i));
    const Inertia<S>& I = m.inertia(i);
    const Vector3<S> c = I.m > S(0) ? Vector3<S>(I.h / I.m) : Vector3<S>::Zero();
    const Matrix3<S> Ic = I.m > S(0) ? I.inertia_com() : I.I;
    pm.appendBodyToJoint(id, pinocchio::InertiaTpl<S>(I.m, c, Ic), pinocchio::SE3Tpl<S>::Identity());
  }
  return pm;
}

}  // namespace spatial::peers

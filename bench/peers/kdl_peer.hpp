#pragma once
/// \file kdl_peer.hpp
/// Orocos KDL as a peer: any spatial model (compile-time or run-time tree, double) converted, in this one place,
/// into a KDL::Tree (and a KDL::Chain when the model is a chain), so that KDL runs on exactly the same numbers.
///
/// Conventions at the boundary:
///  - KDL frames are ACTIVE poses: Frame(M, p) maps child coordinates to parent coordinates. Our Transform ᴮX_A =
///    (E, r) is passive, E = ᴮE_A, r = B's origin in A; so the pose of B in A is Frame(M = Eᵀ, p = r).
///  - A KDL segment = joint (at the segment's root, expressed in the parent's tip frame) followed by f_tip.
///    Our body i: ⁱX_λ = X_J(qᵢ) X_T(i), i.e. the joint acts in the joint frame placed by X_T. We therefore give
///    KDL a joint about (along) the axis Eᵀa through the point r, both in parent coordinates, and f_tip = the pose
///    of X_T: KDL's segment pose Rot(Eᵀa, q) about r ∘ Frame(Eᵀ, r) = Frame(Eᵀ Rot(a, q), r), our body frame.
///  - A KDL segment's inertia is expressed in its tip frame, i.e. our body frame: RigidBodyInertia(m, c, I_c) with
///    c and I_c (about the centre of mass) in body coordinates.
///  - KDL ignores the inertia of the tree's root; our fixed base is KDL's massless "root", every moving body is a
///    segment, so nothing is lost.
///  - KDL twists and wrenches are linear first; only joint-space quantities cross this boundary, so no 6-vector
///    needs converting.
///  - Joint numbering: KDL numbers joints in the order segments are added (q_nr); we add bodies in order and read
///    q_nr back, so `JntArray` index i is our joint i (checked by `make_kdl_peer`).

#include <spatial/spatial.hpp>

#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <memory>
#include <stdexcept>
#include <string>

namespace spatial::peers {

inline KDL::Vector to_kdl(const Vector3<double>& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

inline KDL::Rotation to_kdl(const Matrix3<double>& M) {
  return KDL::Rotation(M(0, 0), M(0, 1), M(0, 2), M(1, 0), M(1, 1), M(1, 2), M(2, 0), M(2, 1), M(2, 2));
}

/// The active pose of frame B in frame A from the passive ᴮX_A = (E, r): Frame(Eᵀ, r).
inline KDL::Frame to_kdl(const Transform<double>& X) { return KDL::Frame(to_kdl(Matrix3<double>(X.E.transpose())), to_kdl(X.r)); }

/// Body inertia in KDL's form: mass, centre of mass and rotational inertia about it, in body coordinates.
inline KDL::RigidBodyInertia to_kdl(const Inertia<double>& I) {
  const Vector3<double> c = I.m > 0.0 ? Vector3<double>(I.h / I.m) : Vector3<double>::Zero();
  const Matrix3<double> Ic = I.m > 0.0 ? I.inertia_com() : I.I;
  return KDL::RigidBodyInertia(I.m, to_kdl(c), KDL::RotationalInertia(Ic(0, 0), Ic(1, 1), Ic(2, 2), Ic(0, 1), Ic(0, 2), Ic(1, 2)));
}

/// KDL's joint for our joint i, expressed in the parent's coordinates: about/along Eᵀa through r.
template <class TreeT>
KDL::Joint kdl_joint(const Model<double, TreeT>& m, int i) {
  const Transform<double>& XT = m.tree_transform(i);
  const Vector3<double> axis = XT.E.transpose() * m.axis(i);
  const KDL::Joint::JointType type = is_revolute(m.joint_type(i)) ? KDL::Joint::RotAxis : KDL::Joint::TransAxis;
  return KDL::Joint(m.joint_name(i), to_kdl(XT.r), to_kdl(axis), type);
}

template <class TreeT>
KDL::Segment kdl_segment(const Model<double, TreeT>& m, int i) {
  return KDL::Segment(m.body_name(i), kdl_joint(m, i), to_kdl(m.tree_transform(i)), to_kdl(m.inertia(i)));
}

template <class TreeT>
bool is_chain(const Model<double, TreeT>& m) {
  for (int i = 0; i < m.size(); ++i)
    if (m.parent(i) != i - 1) return false;
  return true;
}

/// Everything KDL needs to run on one of our models. Solvers keep references to the tree and chain, so they live
/// here together (and the struct is neither copied nor moved).
struct KdlPeer {
  KDL::Tree tree{"root"};
  KDL::Chain chain;  ///< empty unless the model is a chain
  bool has_chain = false;
  KDL::Vector gravity;
  std::unique_ptr<KDL::TreeIdSolver_RNE> tree_id;
  std::unique_ptr<KDL::ChainDynParam> chain_dyn;
  std::unique_ptr<KDL::ChainFdSolver_RNE> chain_fd;

  KdlPeer() = default;
  KdlPeer(const KdlPeer&) = delete;
  KdlPeer& operator=(const KdlPeer&) = delete;
};

/// Converts a model. Throws std::runtime_error when KDL refuses it or numbers its joints differently.
template <class TreeT>
std::unique_ptr<KdlPeer> make_kdl_peer(const Model<double, TreeT>& m) {
  auto peer = std::make_unique<KdlPeer>();
  const int n = m.size();
  for (int i = 0; i < n; ++i) {
    const std::string hook = m.parent(i) < 0 ? std::string("root") : m.body_name(m.parent(i));
    if (!peer->tree.addSegment(kdl_segment(m, i), hook))
      throw std::runtime_error("KDL refused segment '" + m.body_name(i) + "' on '" + hook + "'");
  }
  if (static_cast<int>(peer->tree.getNrOfJoints()) != n)
    throw std::runtime_error("KDL tree has " + std::to_string(peer->tree.getNrOfJoints()) + " joints, model " +
                             std::to_string(n));
  for (int i = 0; i < n; ++i) {
    const auto it = peer->tree.getSegment(m.body_name(i));
    if (static_cast<int>(GetTreeElementQNr(it->second)) != i)
      throw std::runtime_error("KDL numbers joint of '" + m.body_name(i) + "' differently");
  }
  peer->gravity = to_kdl(m.gravity());
  peer->tree_id = std::make_unique<KDL::TreeIdSolver_RNE>(peer->tree, peer->gravity);
  if (is_chain(m)) {
    peer->has_chain = true;
    for (int i = 0; i < n; ++i) peer->chain.addSegment(kdl_segment(m, i));
    peer->chain_dyn = std::make_unique<KDL::ChainDynParam>(peer->chain, peer->gravity);
    peer->chain_fd = std::make_unique<KDL::ChainFdSolver_RNE>(peer->chain, peer->gravity);
  }
  return peer;
}

template <class V>
KDL::JntArray to_jnt_array(const V& v) {
  KDL::JntArray a(static_cast<unsigned>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) a(static_cast<unsigned>(i)) = double(v[i]);
  return a;
}

}  // namespace spatial::peers

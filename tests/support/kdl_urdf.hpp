#pragma once
// KDL reference for URDF models (KDL tests only; not part of the installed library): a URDF parsed by urdfdom turned
// into a KDL::Tree by the code below (not kdl_parser, and not our loader: it re-roots the tree itself, KDL-style,
// with each reversed joint placed at the old child's origin with the negated axis and the old parent hanging from it
// by the inverse joint origin), and KDL::TreeIdSolver_RNE's torques in our model's joint order. KDL ignores the root
// segment's inertia, so roots must be massless links or links rigidly fixed to the ground anyway.
//
// Include it first (before any Eigen header): kdl_bridge.hpp sets EIGEN_MALLOC_ALREADY_ALIGNED under ASan.

#include "kdl_bridge.hpp"

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/urdf_reference.hpp"

#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace spatial::testing {

/// An active pose (x_A = R x_F + p) as a KDL::Frame.
inline KDL::Frame kdl_frame(const Eigen::Isometry3d& T) {
  return KDL::Frame(kdl_bridge::to_kdl_rotation(T.linear()), kdl_bridge::to_kdl(Eigen::Vector3d(T.translation())));
}

/// A urdfdom link's inertial as a KDL inertia in the link frame (zero when it has none).
inline KDL::RigidBodyInertia kdl_link_inertia(const urdf::Link& link) {
  if (!link.inertial) return KDL::RigidBodyInertia::Zero();
  const urdf::Inertial& in = *link.inertial;
  const Eigen::Isometry3d T = origin_pose(in.origin);
  Eigen::Matrix3d Ic;
  Ic << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Matrix3d I = T.linear() * Ic * T.linear().transpose();  // about the CoM, link axes
  return kdl_bridge::to_kdl_inertia(in.mass, T.translation(), I);
}

/// The KDL tree of a URDF rooted at `root`; `locked` joints become fixed at the given positions.
inline KDL::Tree kdl_tree(const urdf::ModelInterface& m, const std::string& root,
                          const std::map<std::string, double>& locked) {
  KDL::Tree tree(root);
  std::vector<std::pair<std::string, std::string>> stack{{root, ""}};  // (link, link it was reached from)
  while (!stack.empty()) {
    const auto [name, from] = stack.back();
    stack.pop_back();
    for (const auto& [jname, j] : m.joints_) {
      const bool forward = j->parent_link_name == name, backward = j->child_link_name == name;
      if (!forward && !backward) continue;
      const std::string other = forward ? j->child_link_name : j->parent_link_name;
      if (other == from) continue;
      const Eigen::Isometry3d O = origin_pose(j->parent_to_joint_origin_transform);
      const Eigen::Vector3d a = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z).normalized();
      const bool revolute = j->type == urdf::Joint::REVOLUTE || j->type == urdf::Joint::CONTINUOUS;
      const bool moving = revolute || j->type == urdf::Joint::PRISMATIC;
      const auto lock = locked.find(jname);
      KDL::Joint joint(jname, KDL::Joint::Fixed);
      Eigen::Isometry3d tip;
      if (!moving || lock != locked.end()) {
        Eigen::Isometry3d M = Eigen::Isometry3d::Identity();  // the joint's motion at its lock position
        if (lock != locked.end()) {
          if (revolute) M.linear() = Eigen::AngleAxisd(lock->second, a).toRotationMatrix();
          else M.translation() = lock->second * a;
        }
        tip = forward ? Eigen::Isometry3d(O * M) : Eigen::Isometry3d((O * M).inverse());
      } else if (forward) {
        const Eigen::Vector3d aw = O.linear() * a;  // axis in the parent link frame, through the joint origin
        joint = KDL::Joint(jname, kdl_bridge::to_kdl(Eigen::Vector3d(O.translation())), kdl_bridge::to_kdl(aw),
                           revolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
        tip = O;
      } else {  // reversed: the old child (here, the parent) turns the old parent about -a through its origin
        joint = KDL::Joint(jname, KDL::Vector::Zero(), kdl_bridge::to_kdl(Eigen::Vector3d(-a)),
                           revolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
        tip = O.inverse();
      }
      const urdf::LinkConstSharedPtr link = m.getLink(other);
      tree.addSegment(KDL::Segment(other, joint, kdl_frame(tip), kdl_link_inertia(*link)), name);
      stack.emplace_back(other, name);
    }
  }
  return tree;
}

/// For each KDL q number, the index of the joint with the same name in `model` (throws if a KDL joint is not in it).
template <class TreeT>
std::vector<int> model_index_of_kdl_joints(const KDL::Tree& tree, const Model<double, TreeT>& model) {
  std::vector<int> out(tree.getNrOfJoints(), -1);
  for (const auto& [name, element] : tree.getSegments()) {
    const KDL::Joint& j = GetTreeElementSegment(element).getJoint();
    if (j.getType() == KDL::Joint::Fixed) continue;
    const int i = model.joint_index(j.getName());
    if (i < 0) throw std::runtime_error("KDL joint " + j.getName() + " is not in the model");
    out[GetTreeElementQNr(element)] = i;
  }
  return out;
}

/// KDL's inverse dynamics (TreeIdSolver_RNE, no external wrenches) with q, qd, qdd and the result in the model's
/// joint order; `index` from model_index_of_kdl_joints.
inline Eigen::VectorXd kdl_inverse_dynamics(const KDL::Tree& tree, const Eigen::Vector3d& gravity,
                                            const std::vector<int>& index, const Eigen::VectorXd& q,
                                            const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
  const auto n = static_cast<unsigned>(index.size());
  KDL::JntArray kq(n), kqd(n), kqdd(n), ktau(n);
  for (unsigned k = 0; k < n; ++k) {
    kq(k) = q[index[k]];
    kqd(k) = qd[index[k]];
    kqdd(k) = qdd[index[k]];
  }
  KDL::TreeIdSolver_RNE solver(tree, kdl_bridge::to_kdl(gravity));  // keeps a reference to `tree`
  if (solver.CartToJnt(kq, kqd, kqdd, KDL::WrenchMap(), ktau) < 0)
    throw std::runtime_error("KDL TreeIdSolver_RNE failed");
  Eigen::VectorXd tau(static_cast<Eigen::Index>(n));
  for (unsigned k = 0; k < n; ++k) tau[index[k]] = ktau(k);
  return tau;
}

}  // namespace spatial::testing

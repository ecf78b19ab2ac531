// URDF models against KDL: the same file parsed by urdfdom, turned into a KDL::Tree by the code below (not
// kdl_parser, and not our loader: it re-roots the tree itself, KDL-style, with each reversed joint placed at the
// old child's origin with the negated axis and the old parent hanging from it by the inverse joint origin), then
// KDL::TreeIdSolver_RNE against our rnea. KDL ignores the root segment's inertia, so every root used here is a
// massless link or a link rigidly fixed to the ground anyway.

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/random_model.hpp"
#include "support/urdf_reference.hpp"

#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using spatial::testing::origin_pose;
using spatial::testing::urdf_path;

KDL::Frame to_kdl(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d& R = T.linear();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                    KDL::Vector(T.translation().x(), T.translation().y(), T.translation().z()));
}

KDL::RigidBodyInertia link_inertia(const urdf::Link& link) {
  if (!link.inertial) return KDL::RigidBodyInertia::Zero();
  const urdf::Inertial& in = *link.inertial;
  const Eigen::Isometry3d T = origin_pose(in.origin);
  Eigen::Matrix3d Ic;
  Ic << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Matrix3d I = T.linear() * Ic * T.linear().transpose();  // about the CoM, link axes
  const Eigen::Vector3d c = T.translation();
  return KDL::RigidBodyInertia(in.mass, KDL::Vector(c.x(), c.y(), c.z()),
                               KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)));
}

/// The KDL tree of a URDF rooted at `root`; `locked` joints become fixed at the given positions.
KDL::Tree kdl_tree(const urdf::ModelInterface& m, const std::string& root, const std::map<std::string, double>& locked) {
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
        joint = KDL::Joint(jname, KDL::Vector(O.translation().x(), O.translation().y(), O.translation().z()),
                           KDL::Vector(aw.x(), aw.y(), aw.z()), revolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
        tip = O;
      } else {  // reversed: the old child (here, the parent) turns the old parent about -a through its origin
        joint = KDL::Joint(jname, KDL::Vector::Zero(), KDL::Vector(-a.x(), -a.y(), -a.z()),
                           revolute ? KDL::Joint::RotAxis : KDL::Joint::TransAxis);
        tip = O.inverse();
      }
      const urdf::LinkConstSharedPtr link = m.getLink(other);
      tree.addSegment(KDL::Segment(other, joint, to_kdl(tip), link_inertia(*link)), name);
      stack.emplace_back(other, name);
    }
  }
  return tree;
}

void compare(const std::string& file, const std::string& root, const std::map<std::string, double>& locked,
             unsigned seed) {
  SCOPED_TRACE(file + " rooted at " + (root.empty() ? std::string("its URDF root") : root));
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path(file));
  uio::LoadOptions opt;
  opt.root = root;
  for (const auto& l : locked) opt.locked.push_back(l);
  const uio::LoadedModel ours = uio::load_file(urdf_path(file), opt);
  const int n = ours.model.size();

  const KDL::Tree tree = kdl_tree(*urdf, ours.root, locked);
  ASSERT_EQ(static_cast<int>(tree.getNrOfJoints()), n);
  std::vector<int> ours_of_kdl(static_cast<std::size_t>(n), -1);
  for (const auto& [name, element] : tree.getSegments()) {
    const KDL::Joint& j = GetTreeElementSegment(element).getJoint();
    if (j.getType() == KDL::Joint::Fixed) continue;
    const int i = ours.model.joint_index(j.getName());
    ASSERT_GE(i, 0) << j.getName();
    ours_of_kdl[GetTreeElementQNr(element)] = i;
  }
  const Eigen::Vector3d g = ours.model.gravity();
  KDL::TreeIdSolver_RNE solver(tree, KDL::Vector(g.x(), g.y(), g.z()));  // the tree outlives the solver

  Data<double> d(ours.model);
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::VectorXd q = spatial::testing::random_vector(n, rng, 1.0);
    const Eigen::VectorXd qd = trial == 0 ? Eigen::VectorXd::Zero(n) : spatial::testing::random_vector(n, rng, 2.0);
    const Eigen::VectorXd qdd = trial == 0 ? Eigen::VectorXd::Zero(n) : spatial::testing::random_vector(n, rng, 3.0);
    KDL::JntArray kq(n), kqd(n), kqdd(n), ktau(n);
    for (int k = 0; k < n; ++k) {
      const int i = ours_of_kdl[static_cast<std::size_t>(k)];
      kq(k) = q[i];
      kqd(k) = qd[i];
      kqdd(k) = qdd[i];
    }
    ASSERT_GE(solver.CartToJnt(kq, kqd, kqdd, KDL::WrenchMap(), ktau), 0);
    const Eigen::VectorXd tau = rnea(ours.model, d, q, qd, qdd);
    const double scale = std::max(1.0, tau.cwiseAbs().maxCoeff());
    for (int k = 0; k < n; ++k) {
      const int i = ours_of_kdl[static_cast<std::size_t>(k)];
      EXPECT_NEAR(tau[i], ktau(k), 1e-12 * scale) << ours.model.joint_name(i) << " trial " << trial;
    }
  }
}

TEST(KdlUrdf, Hoap3RootedAtThePelvis) { compare("hoap3.urdf", "", {}, 1); }

TEST(KdlUrdf, Hoap3RootedAtAFoot) {
  compare("hoap3.urdf", "R_SOLE", {}, 2);
  compare("hoap3.urdf", "L_FOOT", {}, 3);
  // The study's single-support model: head and wrists locked, 21 DoF.
  const std::map<std::string, double> locked = {{"CHEST_H_PAN_joint", 0.1}, {"H_PAN_H_TILT_joint", -0.2},
                                                {"H_TILT_H_ROLL_joint", 0.05}, {"R_EB_R_WR_joint", 0.3},
                                                {"L_EB_L_WR_joint", -0.4}};
  compare("hoap3.urdf", "R_SOLE", locked, 4);
  compare("hoap3.urdf", "L_SOLE", locked, 5);
}

TEST(KdlUrdf, Hoap3ElsewhereAndTestRobots) {
  compare("hoap3.urdf", "CHEST", {}, 6);
  compare("hoap3.urdf", "L_HAND", {}, 7);
  compare("test/serial_arm.urdf", "", {}, 8);
  compare("test/serial_arm.urdf", "tcp", {}, 9);
  compare("test/branched.urdf", "", {}, 10);
  compare("test/branched.urdf", "foot", {{"neck", 0.7}}, 11);
  compare("test/all_joints.urdf", "", {}, 12);
  compare("test/all_joints.urdf", "a10", {}, 13);
  compare("test/all_joints.urdf", "b2", {{"j_pri_x", 0.1}, {"j_cont_oblique", -0.6}}, 14);
  compare("double_pendulum.urdf", "", {}, 15);
}

}  // namespace

// URDF loader: conventions (rpy, joint axes and signs, passive tree transforms), merging of fixed and locked
// joints, joint types, frames, options (root, locked, subtree, gravity), the compile-time conversion, and every
// kind of bad input.

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/random_model.hpp"
#include "support/urdf_reference.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::reference_link_poses;
using spatial::testing::rpy_matrix;
using spatial::testing::urdf_path;
namespace uio = spatial::urdf_io;

const double kPi = 3.141592653589793;

std::string one_joint(const std::string& type, const std::string& xyz, const std::string& rpy,
                      const std::string& axis, const std::string& extra = "") {
  return R"(<robot name="t"><link name="a"/>
    <link name="b"><inertial><origin xyz="0.1 0.2 0.3"/><mass value="2"/>
      <inertia ixx="0.01" ixy="0.001" ixz="0" iyy="0.02" iyz="0" izz="0.015"/></inertial></link>
    <joint name="j" type=")" +
         type + R"("><parent link="a"/><child link="b"/><origin xyz=")" + xyz + R"(" rpy=")" + rpy +
         R"("/><axis xyz=")" + axis + R"("/><limit lower="-1" upper="1" effort="3" velocity="4"/>)" + extra +
         "</joint></robot>";
}

std::map<std::string, double> by_name(const uio::LoadedModel& m, const Eigen::VectorXd& q) {
  std::map<std::string, double> out;
  for (int i = 0; i < m.model.size(); ++i) out[m.model.joint_name(i)] = q[i];
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Conventions on hand-made cases

TEST(UrdfConventions, RpyIsFixedAxisRollPitchYawAndTreeTransformIsPassive) {
  const double r = 0.3, p = -0.4, y = 0.5;
  const auto m = uio::load_string(one_joint("revolute", "0.1 -0.2 0.3", "0.3 -0.4 0.5", "0 0 1"));
  ASSERT_EQ(m.model.size(), 1);
  // Written out here: R = Rz(y) Ry(p) Rx(r); the joint frame's axes in the parent are R's columns.
  const double cr = std::cos(r), sr = std::sin(r), cp = std::cos(p), sp = std::sin(p), cy = std::cos(y),
               sy = std::sin(y);
  Eigen::Matrix3d R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  const Transform<double>& X = m.model.tree_transform(0);
  EXPECT_LT((X.E - R.transpose()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((X.r - Eigen::Vector3d(0.1, -0.2, 0.3)).cwiseAbs().maxCoeff(), 1e-16);
  EXPECT_EQ(m.model.joint_type(0), JointType::RevoluteZ);
  // A point given in the child frame at q = 0 is at R p + xyz in the parent.
  Data<double> d(m.model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1);
  forward_kinematics(m.model, d, q);
  const Eigen::Vector3d pc(0.7, -0.1, 0.2);
  EXPECT_LT((body_pose(d, 0) * pc - (R * pc + Eigen::Vector3d(0.1, -0.2, 0.3))).norm(), 1e-15);
}

TEST(UrdfConventions, PositiveAndNegativeAxesRotateTheChildByPlusOrMinusQ) {
  const double q = 0.3;
  for (bool aligned : {true, false}) {
    uio::LoadOptions opt;
    opt.axis_aligned = aligned;
    struct Case {
      const char* axis;
      Eigen::Vector3d dir;
    };
    for (const Case& c : {Case{"0 0 1", {0, 0, 1}}, Case{"0 0 -1", {0, 0, -1}}, Case{"-1 0 0", {-1, 0, 0}},
                          Case{"0 -2 0", {0, -1, 0}}, Case{"1 1 0", Eigen::Vector3d(1, 1, 0).normalized()}}) {
      const auto m = uio::load_string(one_joint("revolute", "0 0 0", "0 0 0", c.axis), opt);
      Data<double> d(m.model);
      Eigen::VectorXd qv = Eigen::VectorXd::Constant(1, q);
      forward_kinematics(m.model, d, qv);
      const Eigen::Isometry3d T = uio::link_pose(m, d, "b");
      // Active rotation of the child by +q about the axis as written (right-hand rule).
      const Eigen::Matrix3d expected = Eigen::AngleAxisd(q, c.dir).toRotationMatrix();
      EXPECT_LT((T.linear() - expected).cwiseAbs().maxCoeff(), 1e-15) << c.axis << " aligned=" << aligned;
      EXPECT_LT(T.translation().norm(), 1e-16);
    }
  }
}

TEST(UrdfConventions, PrismaticAxesTranslateTheChildByQ) {
  const double q = 0.25;
  for (bool aligned : {true, false}) {
    uio::LoadOptions opt;
    opt.axis_aligned = aligned;
    for (const auto& [axis, dir] : std::vector<std::pair<std::string, Eigen::Vector3d>>{
             {"0 0 -1", {0, 0, -1}}, {"0 3 0", {0, 1, 0}}, {"0.6 0 -0.8", {0.6, 0, -0.8}}}) {
      const auto m = uio::load_string(one_joint("prismatic", "1 2 3", "0 0 0", axis), opt);
      Data<double> d(m.model);
      Eigen::VectorXd qv = Eigen::VectorXd::Constant(1, q);
      forward_kinematics(m.model, d, qv);
      const Eigen::Isometry3d T = uio::link_pose(m, d, "b");
      EXPECT_LT((T.translation() - (Eigen::Vector3d(1, 2, 3) + q * dir)).norm(), 1e-15) << axis;
      EXPECT_LT((T.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-16);
    }
  }
}

TEST(UrdfConventions, InertialOriginWithRpyIsRotatedIntoLinkAxes) {
  const std::string xml = R"(<robot name="t"><link name="a"/>
    <link name="b"><inertial><origin xyz="0.1 -0.2 0.05" rpy="0 0 1.5707963267948966"/><mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="b"/></joint></robot>)";
  const auto m = uio::load_string(xml);
  const Inertia<double>& I = m.model.inertia(0);
  EXPECT_DOUBLE_EQ(I.m, 2.0);
  EXPECT_LT((I.com() - Eigen::Vector3d(0.1, -0.2, 0.05)).norm(), 1e-15);
  // A quarter turn about z swaps the x and y principal moments.
  Eigen::Matrix3d expected = Eigen::Vector3d(0.02, 0.01, 0.025).asDiagonal();
  EXPECT_LT((I.inertia_com() - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(m.model.joint_type(0), JointType::RevoluteX);  // default URDF axis: x
}

// ---------------------------------------------------------------------------------------------------------------
// Fixed joints: exact merging, frames

TEST(UrdfMerge, FixedChildInertiaIsAddedExactly) {
  const auto m = uio::load_file(urdf_path("test/serial_arm.urdf"));
  ASSERT_EQ(m.model.size(), 6);
  const int six = m.model.body_index("link6");
  ASSERT_EQ(six, 5);
  // link6: 0.3 kg at (0.01, 0, 0), Ic = 2e-4 1. gripper: 0.5 kg, frame at (0.04, 0, 0) turned by Ry(pi/2), CoM
  // (0, 0, 0.03) in it -> (0.07, 0, 0) in link6; its Ic is diag(4e-4, 3e-4, 2e-4) turned by Rx(0.2), then Ry(pi/2).
  const double m1 = 0.3, m2 = 0.5;
  const Eigen::Vector3d c1(0.01, 0, 0), c2(0.07, 0, 0);
  const Eigen::Vector3d c = (m1 * c1 + m2 * c2) / (m1 + m2);
  const Eigen::Matrix3d R2 = rpy_matrix(0, kPi / 2, 0) * rpy_matrix(0.2, 0, 0);
  const Eigen::Matrix3d I2 = R2 * Eigen::Vector3d(4e-4, 3e-4, 2e-4).asDiagonal() * R2.transpose();
  auto shift = [](double mass, const Eigen::Vector3d& d) {  // parallel-axis term m (|d|^2 1 - d d^T)
    return mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  };
  const Eigen::Matrix3d Ic = 2e-4 * Eigen::Matrix3d::Identity() + shift(m1, c1 - c) + I2 + shift(m2, c2 - c);
  const Inertia<double>& I = m.model.inertia(six);
  EXPECT_NEAR(I.m, 0.8, 1e-15);
  EXPECT_LT((I.com() - c).norm(), 1e-15);
  EXPECT_LT((I.inertia_com() - Ic).cwiseAbs().maxCoeff(), 1e-16);
  // Frames: gripper and tcp on link6; the root link on the base.
  ASSERT_EQ(m.model.frames().size(), 3u);
  EXPECT_EQ(m.model.frames()[0].name, "base_link");
  EXPECT_EQ(m.model.frames()[0].body, -1);
  EXPECT_EQ(m.model.frames()[2].name, "tcp");
  EXPECT_EQ(m.model.frames()[2].body, six);
  // tcp at (0.04, 0, 0) + Ry(pi/2) (0, 0, 0.1) = (0.14, 0, 0) in link6.
  Data<double> d(m.model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  forward_kinematics(m.model, d, q);
  const Eigen::Isometry3d tcp = frame_pose(m.model, d, 2), l6 = body_pose(d, six);
  EXPECT_LT(((l6.inverse() * tcp).translation() - Eigen::Vector3d(0.14, 0, 0)).norm(), 1e-15);
}

TEST(UrdfMerge, ChainsOfFixedLinksAndMassBookkeeping) {
  const auto m = uio::load_file(urdf_path("test/branched.urdf"));
  EXPECT_EQ(m.model.size(), 8);
  // trunk (6 kg) is fixed to the massless root: it is on the base.
  EXPECT_NEAR(m.model.base_mass(), 6.0, 1e-15);
  EXPECT_NEAR(m.base_inertia.m, 6.0, 1e-15);
  EXPECT_NEAR(uio::whole_body_mass(m), 18.65, 1e-13);
  // l_elbow's parent body is l_upper_arm, which carries both spacers (fixed in a row).
  const int upper = m.model.body_index("l_upper_arm"), fore = m.model.body_index("l_forearm");
  EXPECT_EQ(m.model.parent(fore), upper);
  EXPECT_NEAR(m.model.inertia(upper).m, 1.4 + 0.2 + 0.25, 1e-15);
  // The massless virtual link between the shoulder axes is a body with no mass; its subtree has mass.
  const int virt = m.model.body_index("r_shoulder_virtual");
  EXPECT_EQ(m.model.inertia(virt).m, 0.0);
  EXPECT_GT(m.model.subtree_mass(virt), 0.0);
  EXPECT_TRUE(m.model.massless_joints().empty());
  // Every link is located: compare with the independent forward kinematics.
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path("test/branched.urdf"));
  std::mt19937 rng(7);
  const Eigen::VectorXd q = spatial::testing::random_vector(8, rng, 1.0);
  const auto ref = reference_link_poses(*urdf, by_name(m, q));
  Data<double> d(m.model);
  forward_kinematics(m.model, d, q);
  EXPECT_EQ(m.links.size(), ref.size());
  for (const auto& L : m.links) {
    const Eigen::Isometry3d T = uio::link_pose(m, d, L.name);
    EXPECT_LT((T.matrix() - ref.at(L.name).matrix()).cwiseAbs().maxCoeff(), 1e-14) << L.name;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Joint types

TEST(UrdfJoints, TypesAndAxesOfEveryKind) {
  const std::string path = urdf_path("test/all_joints.urdf");
  const auto fast = uio::load_file(path);
  uio::LoadOptions plain;
  plain.axis_aligned = false;
  const auto slow = uio::load_file(path, plain);
  ASSERT_EQ(fast.model.size(), 13);
  ASSERT_EQ(slow.model.size(), 13);
  struct Expect {
    const char* joint;
    JointType fast, slow;
    Eigen::Vector3d slow_axis;
  };
  const Eigen::Vector3d ob = Eigen::Vector3d(1, 2, 2) / 3.0;
  const std::vector<Expect> expect = {
      {"j_rev_x", JointType::RevoluteX, JointType::RevoluteX, {1, 0, 0}},
      {"j_rev_neg_y", JointType::RevoluteY, JointType::RevoluteAxis, {0, -1, 0}},
      {"j_cont_z", JointType::RevoluteZ, JointType::RevoluteZ, {0, 0, 1}},
      {"j_rev_neg_x", JointType::RevoluteX, JointType::RevoluteAxis, {-1, 0, 0}},
      {"j_pri_x", JointType::PrismaticX, JointType::PrismaticX, {1, 0, 0}},
      {"j_pri_neg_z", JointType::PrismaticZ, JointType::PrismaticAxis, {0, 0, -1}},
      {"j_cont_oblique", JointType::RevoluteAxis, JointType::RevoluteAxis, ob},
      {"j_pri_oblique", JointType::PrismaticAxis, JointType::PrismaticAxis, {0.6, 0, -0.8}},
      {"j_rev_neg_z", JointType::RevoluteZ, JointType::RevoluteAxis, {0, 0, -1}},
      {"j_pri_y", JointType::PrismaticY, JointType::PrismaticY, {0, 1, 0}},
      {"j_cont_neg_y", JointType::RevoluteY, JointType::RevoluteAxis, {0, -1, 0}},
      {"j_rev_y", JointType::RevoluteY, JointType::RevoluteY, {0, 1, 0}},
      {"j_rev_z", JointType::RevoluteZ, JointType::RevoluteZ, {0, 0, 1}},
  };
  for (const Expect& e : expect) {
    const int i = fast.model.joint_index(e.joint), k = slow.model.joint_index(e.joint);
    ASSERT_GE(i, 0) << e.joint;
    ASSERT_EQ(i, k);
    EXPECT_EQ(fast.model.joint_type(i), e.fast) << e.joint;
    EXPECT_EQ(slow.model.joint_type(i), e.slow) << e.joint;
    EXPECT_LT((slow.model.axis(i) - e.slow_axis).norm(), 1e-15) << e.joint;
    EXPECT_FALSE(fast.joints[static_cast<std::size_t>(i)].reversed);
  }
  // Document order, depth first: the first chain (its fixed joint is not a body), then the branch from a3, then
  // the branch from the base.
  EXPECT_EQ(fast.model.joint_name(0), "j_rev_x");
  EXPECT_EQ(fast.model.joint_name(7), "j_pri_oblique");
  EXPECT_EQ(fast.model.joint_name(9), "j_pri_y");
  EXPECT_EQ(fast.model.parent(9), 2);
  EXPECT_EQ(fast.model.joint_name(11), "j_rev_y");
  EXPECT_EQ(fast.model.parent(11), -1);
  // Limits: continuous joints have none.
  const auto& cont = fast.joints[static_cast<std::size_t>(fast.model.joint_index("j_cont_z"))];
  EXPECT_EQ(cont.urdf_type, "continuous");
  EXPECT_EQ(cont.lower, -std::numeric_limits<double>::infinity());
  const auto& pri = fast.joints[static_cast<std::size_t>(fast.model.joint_index("j_pri_x"))];
  EXPECT_EQ(pri.urdf_type, "prismatic");
  EXPECT_EQ(pri.lower, -0.3);
  EXPECT_EQ(pri.upper, 0.3);
  EXPECT_EQ(pri.effort, 10.0);
  EXPECT_EQ(pri.velocity, 2.0);
}

TEST(UrdfJoints, FlippedBodyFramesDoNotChangeKinematicsOrDynamics) {
  const std::string path = urdf_path("test/all_joints.urdf");
  uio::LoadOptions plain;
  plain.axis_aligned = false;
  const auto fast = uio::load_file(path);
  const auto slow = uio::load_file(path, plain);
  const auto urdf = spatial::testing::parse_urdf_or_throw(path);
  Data<double> df(fast.model), ds(slow.model);
  std::mt19937 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = spatial::testing::random_vector(13, rng, 1.0);
    const Eigen::VectorXd qd = spatial::testing::random_vector(13, rng, 2.0);
    const Eigen::VectorXd qdd = spatial::testing::random_vector(13, rng, 3.0);
    const Eigen::VectorXd tf = rnea(fast.model, df, q, qd, qdd);
    const Eigen::VectorXd ts = rnea(slow.model, ds, q, qd, qdd);
    EXPECT_LT((tf - ts).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, ts.cwiseAbs().maxCoeff()));
    crba(fast.model, df, q);
    crba(slow.model, ds, q);
    EXPECT_LT((df.H - ds.H).cwiseAbs().maxCoeff(), 1e-14);
    // Every link where the independent forward kinematics puts it.
    const auto ref = reference_link_poses(*urdf, by_name(fast, q));
    forward_kinematics(fast.model, df, q);
    forward_kinematics(slow.model, ds, q);
    for (const auto& [name, T] : ref) {
      EXPECT_LT((uio::link_pose(fast, df, name).matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-14) << name;
      EXPECT_LT((uio::link_pose(slow, ds, name).matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-14) << name;
    }
  }
}

TEST(UrdfJoints, ReRootedLinkPosesMatchTheIndependentKinematics) {
  // For every test robot and several roots: the pose of every link relative to the new root equals the
  // URDF's own forward kinematics, T_root^-1 T_link.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"test/all_joints.urdf", {"a10", "a5", "b2", "c3", "a8"}},
      {"test/branched.urdf", {"foot", "r_hand", "l_spacer1", "camera", "r_shoulder_virtual"}},
      {"test/serial_arm.urdf", {"tcp", "link3"}},
      {"hoap3.urdf", {"R_SOLE", "L_FOOT", "R_KN", "L_HAND", "H_ROLL"}},
  };
  std::mt19937 rng(5);
  for (const auto& [file, roots] : cases) {
    const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path(file));
    for (const std::string& root : roots) {
      for (bool aligned : {true, false}) {
        uio::LoadOptions opt;
        opt.root = root;
        opt.axis_aligned = aligned;
        const auto m = uio::load_file(urdf_path(file), opt);
        EXPECT_EQ(m.root, root);
        const Eigen::VectorXd q = spatial::testing::random_vector(m.model.size(), rng, 0.8);
        const auto ref = reference_link_poses(*urdf, by_name(m, q));
        const Eigen::Isometry3d T0inv = ref.at(root).inverse();
        Data<double> d(m.model);
        forward_kinematics(m.model, d, q);
        for (const auto& [name, T] : ref) {
          const Eigen::Isometry3d mine = uio::link_pose(m, d, name);
          EXPECT_LT((mine.matrix() - (T0inv * T).matrix()).cwiseAbs().maxCoeff(), 1e-13)
              << file << " root " << root << " link " << name;
        }
        if (aligned) {
          for (int i = 0; i < m.model.size(); ++i) {  // every joint of these robots is axis-aligned except two
            if (m.model.joint_name(i) != "j_cont_oblique" && m.model.joint_name(i) != "j_pri_oblique") {
              EXPECT_FALSE(has_axis(m.model.joint_type(i))) << m.model.joint_name(i);
            }
          }
        }
      }
    }
  }
}

TEST(UrdfJoints, ReversedJointsAreMarked) {
  uio::LoadOptions opt;
  opt.root = "R_SOLE";
  const auto m = uio::load_file(urdf_path("hoap3.urdf"), opt);
  const std::vector<std::string> path = {"R_AFE_R_AAA_joint", "R_KN_R_AFE_joint",  "R_LFE_R_KN_joint",
                                         "R_LAA_R_LFE_joint", "R_LR_R_LAA_joint", "WAIST_R_LR_joint"};
  for (int i = 0; i < m.model.size(); ++i) {
    const bool on_path = std::find(path.begin(), path.end(), m.model.joint_name(i)) != path.end();
    EXPECT_EQ(m.joints[static_cast<std::size_t>(i)].reversed, on_path) << m.model.joint_name(i);
    EXPECT_EQ(m.joints[static_cast<std::size_t>(i)].name, m.model.joint_name(i));
  }
  // Model order: the stance leg upwards, then what hangs from the pelvis.
  for (std::size_t k = 0; k < path.size(); ++k) EXPECT_EQ(m.model.joint_name(static_cast<int>(k)), path[k]);
  EXPECT_EQ(m.model.body_name(5), "WAIST");
  // Limits follow the joint (same q).
  const auto& knee = m.joints[2];
  EXPECT_EQ(knee.name, "R_LFE_R_KN_joint");
  EXPECT_EQ(knee.lower, 0.0873);
  EXPECT_EQ(knee.upper, 2.2689);
  EXPECT_EQ(knee.effort, 4.5);
}

// ---------------------------------------------------------------------------------------------------------------
// Options

TEST(UrdfOptions, GravityDefaultSetAndFromUrdfRoot) {
  const std::string path = urdf_path("hoap3.urdf");
  EXPECT_EQ(uio::load_file(path).model.gravity(), Eigen::Vector3d(0, 0, -9.81));
  uio::LoadOptions opt;
  opt.gravity = Eigen::Vector3d(0.5, -1, -9.7);
  EXPECT_EQ(uio::load_file(path, opt).model.gravity(), Eigen::Vector3d(0.5, -1, -9.7));
  // R_FOOT has x up at q = 0: gravity given in the URDF root frame becomes -x there.
  uio::LoadOptions foot;
  foot.root = "R_FOOT";
  foot.gravity_frame = uio::GravityFrame::UrdfRoot;
  const auto f = uio::load_file(path, foot);
  EXPECT_LT((f.model.gravity() - Eigen::Vector3d(-9.81, 0, 0)).norm(), 1e-14);
  // ... and then it is the same robot as rooted at the z-up sole frame with the default gravity.
  uio::LoadOptions sole;
  sole.root = "R_SOLE";
  const auto s = uio::load_file(path, sole);
  EXPECT_EQ(s.model.gravity(), Eigen::Vector3d(0, 0, -9.81));
  Data<double> df(f.model), ds(s.model);
  std::mt19937 rng(3);
  const Eigen::VectorXd q = spatial::testing::random_vector(26, rng, 0.5);
  const Eigen::VectorXd tf = gravity_torques(f.model, df, q), ts = gravity_torques(s.model, ds, q);
  EXPECT_LT((tf - ts).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_GT(ts.cwiseAbs().maxCoeff(), 1.0);
}

TEST(UrdfOptions, LockedJointsEqualHeldJoints) {
  // Locking the waist at 0.3 rad, a shoulder joint in the middle of the arm at 0.4 rad and the legs at various
  // angles is the full model with those joints held still at those positions: the torques of the remaining joints
  // agree for any motion of them.
  const std::string path = urdf_path("hoap3.urdf");
  const auto full = uio::load_file(path);
  uio::LoadOptions opt;
  opt.locked = {{"WAIST_CHEST_joint", 0.3}, {"R_SAA_R_SHR_joint", 0.4}};
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int i = 0; i < full.model.size(); ++i) {
    const std::string& body = full.model.body_name(i);
    for (const char* leg : {"LR", "LAA", "LFE", "KN", "AFE", "AAA"})
      if (body == std::string("R_") + leg || body == std::string("L_") + leg)
        opt.locked.emplace_back(full.model.joint_name(i), u(rng));
  }
  const auto locked = uio::load_file(path, opt);
  ASSERT_EQ(locked.model.size(), 26 - 2 - 12);
  EXPECT_EQ(locked.locked.size(), 14u);
  EXPECT_NEAR(uio::whole_body_mass(locked), 8.8024, 1e-13);
  Data<double> dl(locked.model), dfull(full.model);
  const int n = locked.model.size();
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd q = spatial::testing::random_vector(n, rng, 1.0);
    const Eigen::VectorXd qd = spatial::testing::random_vector(n, rng, 1.0);
    const Eigen::VectorXd qdd = spatial::testing::random_vector(n, rng, 1.0);
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(26), QD = Eigen::VectorXd::Zero(26), QDD = Eigen::VectorXd::Zero(26);
    for (const auto& [name, value] : opt.locked) Q[full.model.joint_index(name)] = value;
    for (int i = 0; i < n; ++i) {
      const int k = full.model.joint_index(locked.model.joint_name(i));
      Q[k] = q[i];
      QD[k] = qd[i];
      QDD[k] = qdd[i];
    }
    const Eigen::VectorXd tl = rnea(locked.model, dl, q, qd, qdd);
    const Eigen::VectorXd tf = rnea(full.model, dfull, Q, QD, QDD);
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(tl[i], tf[full.model.joint_index(locked.model.joint_name(i))], 1e-13) << locked.model.joint_name(i);
  }
}

TEST(UrdfOptions, TorsoBySubtreeOrByRootingAndLockingIsTheSame) {
  const std::string path = urdf_path("hoap3.urdf");
  const std::vector<std::string> head_wrists = {"CHEST_H_PAN_joint", "H_PAN_H_TILT_joint", "H_TILT_H_ROLL_joint",
                                                "R_EB_R_WR_joint", "L_EB_L_WR_joint"};
  uio::LoadOptions sub;
  sub.subtree = "CHEST";
  for (const auto& j : head_wrists) sub.locked.emplace_back(j, 0.0);
  sub.locked.emplace_back("R_KN_R_AFE_joint", 0.0);  // outside the subtree: ignored
  const auto a = uio::load_file(path, sub);
  uio::LoadOptions rooted;
  rooted.root = "CHEST";
  rooted.locked = sub.locked;
  const auto full = uio::load_file(path);
  for (int i = 0; i < full.model.size(); ++i) {
    const std::string& n = full.model.joint_name(i);
    if (n.find("SFE") == std::string::npos && n.find("SAA") == std::string::npos &&
        n.find("SHR") == std::string::npos && n.find("_EB_joint") == std::string::npos &&
        std::find(head_wrists.begin(), head_wrists.end(), n) == head_wrists.end())
      rooted.locked.emplace_back(n, 0.0);
  }
  const auto b = uio::load_file(path, rooted);
  ASSERT_EQ(a.model.size(), 8);
  ASSERT_EQ(b.model.size(), 8);
  EXPECT_EQ(a.root, "CHEST");
  EXPECT_EQ(b.root, "CHEST");
  EXPECT_EQ(a.locked.size(), 5u);  // the ankle is not in the subtree
  EXPECT_EQ(a.link_index("R_FOOT"), -1);
  EXPECT_GE(b.link_index("R_FOOT"), 0);
  // Both: the arms on a fixed chest. Moving: 2 x (0.21 + 0.234 + 0.1965 + 0.216) kg.
  EXPECT_NEAR(a.model.total_mass(), 2 * 0.8565, 1e-13);
  EXPECT_NEAR(b.model.total_mass(), 2 * 0.8565, 1e-13);
  EXPECT_NEAR(a.model.base_mass(), 3.26 + 0.071 + 0.412, 1e-13);
  EXPECT_NEAR(b.model.base_mass(), 8.8024 - 2 * 0.8565, 1e-13);
  Data<double> da(a.model), db(b.model), dfull(full.model);
  std::mt19937 rng(8);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd q = spatial::testing::random_vector(8, rng, 1.0);
    const Eigen::VectorXd qd = spatial::testing::random_vector(8, rng, 1.0);
    const Eigen::VectorXd qdd = spatial::testing::random_vector(8, rng, 1.0);
    for (int i = 0; i < 8; ++i) ASSERT_EQ(a.model.joint_name(i), b.model.joint_name(i));
    const Eigen::VectorXd ta = rnea(a.model, da, q, qd, qdd);
    const Eigen::VectorXd tb = rnea(b.model, db, q, qd, qdd);
    EXPECT_LT((ta - tb).cwiseAbs().maxCoeff(), 1e-14);
    // The full model with the chest still (waist 0, legs fixed base) gives the same arm torques.
    Eigen::VectorXd Q = Eigen::VectorXd::Zero(26), QD = Q, QDD = Q;
    for (int i = 0; i < 8; ++i) {
      const int k = full.model.joint_index(a.model.joint_name(i));
      Q[k] = q[i];
      QD[k] = qd[i];
      QDD[k] = qdd[i];
    }
    const Eigen::VectorXd tf = rnea(full.model, dfull, Q, QD, QDD);
    for (int i = 0; i < 8; ++i) EXPECT_NEAR(ta[i], tf[full.model.joint_index(a.model.joint_name(i))], 1e-14);
  }
}

TEST(UrdfOptions, SubtreeKeepsOnlyTheLinksBelowAndUsesTheRootForDirection) {
  const std::string path = urdf_path("test/branched.urdf");
  uio::LoadOptions opt;
  opt.subtree = "thigh";
  const auto leg = uio::load_file(path, opt);
  ASSERT_EQ(leg.model.size(), 1);
  EXPECT_EQ(leg.model.joint_name(0), "knee");
  EXPECT_EQ(leg.root, "thigh");
  EXPECT_NEAR(uio::whole_body_mass(leg), 3.0 + 2.0 + 0.8, 1e-14);
  // Rooted at the foot, the subtree below the thigh is everything but the shank and the foot: the trunk (through
  // the reversed hip), both arms and the head.
  opt.root = "foot";
  const auto up = uio::load_file(path, opt);
  ASSERT_EQ(up.model.size(), 7);
  EXPECT_EQ(up.model.joint_name(0), "hip");
  EXPECT_TRUE(up.joints[0].reversed);
  EXPECT_EQ(up.link_index("shank"), -1);
  EXPECT_GE(up.link_index("camera"), 0);
  EXPECT_NEAR(uio::whole_body_mass(up), 18.65 - 2.0 - 0.8, 1e-13);
}

// ---------------------------------------------------------------------------------------------------------------
// Compile-time models, singular models

TEST(UrdfStatic, ToStaticGivesTheSameNumbersAndReportsMismatches) {
  const auto m = uio::load_file(urdf_path("test/serial_arm.urdf"));
  using Arm = Tree<Parents<-1, 0, 1, 2, 3, 4>, Joints<JointType::RevoluteZ, JointType::RevoluteY, JointType::RevoluteY,
                                                      JointType::RevoluteX, JointType::RevoluteY, JointType::RevoluteX>>;
  const Model<double, Arm> ms = uio::to_static<Arm>(m);
  Data<double, Arm> ds(ms);
  Data<double> d(m.model);
  std::mt19937 rng(4);
  const Eigen::VectorXd q = spatial::testing::random_vector(6, rng), qd = spatial::testing::random_vector(6, rng),
                        qdd = spatial::testing::random_vector(6, rng);
  Eigen::Matrix<double, 6, 1> qs = q, qds = qd, qdds = qdd;
  const Eigen::VectorXd t = rnea(m.model, d, q, qd, qdd);
  const Eigen::Matrix<double, 6, 1> ts = rnea(ms, ds, qs, qds, qdds);
  EXPECT_LT((t - ts).cwiseAbs().maxCoeff(), 1e-14 * t.cwiseAbs().maxCoeff());
  forward_kinematics(ms, ds, qs);
  forward_kinematics(m.model, d, q);
  EXPECT_LT((uio::link_pose(m, ds, "tcp").matrix() - uio::link_pose(m, d, "tcp").matrix()).cwiseAbs().maxCoeff(),
            1e-15);

  using Wrong = Tree<Parents<-1, 0, 1, 2, 3, 4>, Joints<JointType::RevoluteZ, JointType::RevoluteZ, JointType::RevoluteY,
                                                        JointType::RevoluteX, JointType::RevoluteY, JointType::RevoluteX>>;
  try {
    (void)uio::to_static<Wrong>(m);
    FAIL() << "expected ModelError";
  } catch (const ModelError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("serial_arm.urdf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("shoulder_pitch"), std::string::npos) << msg;
  }
  using Short = Tree<Parents<-1, 0>, Joints<JointType::RevoluteZ, JointType::RevoluteY>>;
  EXPECT_THROW((void)uio::to_static<Short>(m), ModelError);
}

TEST(UrdfStatic, MasslessJointsAreReportedAndLockingThemHelps) {
  const auto m = uio::load_file(urdf_path("hoap3.urdf"));
  const std::vector<int> bad = m.model.massless_joints();
  ASSERT_EQ(bad.size(), 2u);
  EXPECT_EQ(m.model.joint_name(bad[0]), "R_EB_R_WR_joint");
  EXPECT_EQ(m.model.joint_name(bad[1]), "L_EB_L_WR_joint");
  try {
    uio::check_nonsingular(m);
    FAIL() << "expected ModelError";
  } catch (const ModelError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("R_EB_R_WR_joint"), std::string::npos) << msg;
    EXPECT_NE(msg.find("L_EB_L_WR_joint"), std::string::npos) << msg;
    EXPECT_NE(msg.find("lock"), std::string::npos) << msg;
  }
  uio::LoadOptions opt;
  opt.locked = {{"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}};
  const auto ok = uio::load_file(urdf_path("hoap3.urdf"), opt);
  EXPECT_NO_THROW(uio::check_nonsingular(ok));
  EXPECT_EQ(ok.model.size(), 24);
}

// ---------------------------------------------------------------------------------------------------------------
// Bad input: an exception naming the file, the culprit and the reason; never a crash or a half-built model.

void expect_error(const std::string& path, const std::vector<std::string>& words, const uio::LoadOptions& opt = {}) {
  try {
    const auto m = uio::load_file(path, opt);
    ADD_FAILURE() << path << ": expected ModelError, got a model with " << m.model.size() << " bodies";
  } catch (const ModelError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
    for (const std::string& w : words) EXPECT_NE(msg.find(w), std::string::npos) << "'" << w << "' not in: " << msg;
  }
}

TEST(UrdfErrors, BadFiles) {
  const std::string bad = urdf_path("test/bad/");
  expect_error(bad + "does_not_exist.urdf", {"no such file"});
  expect_error(urdf_path("test/bad"), {"directory"});
  expect_error(bad + "empty.urdf", {"not a valid URDF", "empty"});
  expect_error(bad + "malformed.urdf", {"not a valid URDF"});
  expect_error(bad + "no_robot.urdf", {"not a valid URDF", "robot"});
  expect_error(bad + "two_roots.urdf", {"root", "[a]", "[c]"});
  expect_error(bad + "loop.urdf", {"'c'", "two joints", "'j2'", "'j3'", "loop"});
  expect_error(bad + "detached_loop.urdf", {"'b'", "not connected", "loop"});
  expect_error(bad + "floating.urdf", {"'free'", "floating", "not supported"});
  expect_error(bad + "planar.urdf", {"'slide'", "planar", "not supported"});
  expect_error(bad + "unknown_type.urdf", {"[j]", "spherical"});
  expect_error(bad + "negative_mass.urdf", {"link 'b'", "negative mass", "-0.5"});
  expect_error(bad + "not_psd.urdf", {"link 'b'", "positive semi-definite"});
  uio::LoadOptions strict;
  strict.strict_inertia = true;  // by default this file loads with a warning (UrdfInertia below)
  expect_error(bad + "triangle.urdf", {"link 'b'", "triangle inequality"}, strict);
  expect_error(bad + "nan_mass.urdf", {"[b]", "mass [nan]"});
  expect_error(bad + "inf_inertia.urdf", {"[b]", "ixx"});
  expect_error(bad + "inf_origin.urdf", {"[j]", "inf"});
  expect_error(bad + "overflow.urdf", {"link 'b'", "NaN or Inf"});
  expect_error(bad + "zero_axis.urdf", {"joint 'j'", "axis is zero"});
  expect_error(bad + "missing_link.urdf", {"[ghost]", "[j]"});
  expect_error(bad + "mimic.urdf", {"joint 'j2'", "mimic", "not supported"});
  expect_error(bad + "inverted_limits.urdf", {"joint 'j'", "lower limit is above the upper limit"});
}

// ---------------------------------------------------------------------------------------------------------------
// Imperfect inertias of published robots: principal moments breaking the triangle inequality load with a warning
// (or are refused with LoadOptions::strict_inertia); what breaks the algorithms is refused in both modes.

/// Links a (root), foot (moved by joint 'ankle', inertia as given) and sensor (fixed on foot, inertia as given).
std::string imperfect_robot(const std::string& foot_inertia, const std::string& foot_mass = "2",
                            const std::string& sensor_inertia = R"(ixx="0.01" iyy="0.01" izz="0.01")") {
  return R"(<robot name="t"><link name="a"/>
    <link name="foot"><inertial><origin xyz="0.1 0 0" rpy="0.2 0.3 0.4"/><mass value=")" + foot_mass + R"("/>
      <inertia )" + foot_inertia + R"( ixy="0" ixz="0" iyz="0"/></inertial></link>
    <link name="sensor"><inertial><mass value="0.5"/><inertia )" + sensor_inertia + R"( ixy="0" ixz="0" iyz="0"/>
      </inertial></link>
    <joint name="ankle" type="revolute"><parent link="a"/><child link="foot"/><origin xyz="0 0 0.2"/>
      <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="3" velocity="4"/></joint>
    <joint name="mount" type="fixed"><parent link="foot"/><child link="sensor"/><origin xyz="0 0 -0.05"/></joint>
    </robot>)";
}
const char* kTriangle = R"(ixx="0.3" iyy="0.5" izz="1.0")";  // I1 + I2 = 0.8 < I3 = 1: short by 0.2, 20 %
const char* kFine = R"(ixx="0.3" iyy="0.5" izz="0.7")";

uio::LoadOptions strict_inertia() {
  uio::LoadOptions o;
  o.strict_inertia = true;
  return o;
}

TEST(UrdfInertia, TriangleInequalityLoadsWithOneWarningNamingTheLinkAndTheAmount) {
  const auto m = uio::load_string(imperfect_robot(kTriangle), {}, "robot.urdf");
  ASSERT_EQ(m.warnings.size(), 1u);
  const std::string& w = m.warnings[0];
  EXPECT_EQ(w.rfind("robot.urdf: link 'foot': principal moments violate the triangle inequality: ", 0), 0u) << w;
  for (const char* s : {"I1 + I2 = 0.8 < I3 = 1 kg m^2", "short by 0.2", "20 %"})
    EXPECT_NE(w.find(s), std::string::npos) << "'" << s << "' not in: " << w;
  // Loaded as written: the same model as with a fine inertia apart from that body's rotational inertia.
  ASSERT_EQ(m.model.size(), 1);
  EXPECT_DOUBLE_EQ(m.model.inertia(0).m, 2.5);
  EXPECT_EQ(m.model.joint_name(0), "ankle");
  const auto fine = uio::load_string(imperfect_robot(kFine));
  EXPECT_TRUE(fine.warnings.empty());
  EXPECT_EQ(fine.model.inertia(0).h, m.model.inertia(0).h);
  Data<double> d(m.model);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.4), qd = q, qdd = q;
  EXPECT_TRUE(rnea(m.model, d, q, qd, qdd).allFinite());
  EXPECT_GT(crba(m.model, d, q)(0, 0), 0.0);
  // One warning per link, whatever the link becomes: merged through a fixed joint, or walked backwards.
  const auto merged = uio::load_string(imperfect_robot(kFine, "2", kTriangle));
  ASSERT_EQ(merged.warnings.size(), 1u);
  EXPECT_EQ(merged.warnings[0].rfind("<string>: link 'sensor': principal moments violate", 0), 0u) << merged.warnings[0];
  uio::LoadOptions reroot;
  reroot.root = "sensor";
  const auto reversed = uio::load_string(imperfect_robot(kTriangle), reroot);
  ASSERT_EQ(reversed.warnings.size(), 1u);
  EXPECT_NE(reversed.warnings[0].find("link 'foot'"), std::string::npos) << reversed.warnings[0];
  EXPECT_TRUE(reversed.joints[0].reversed);
  // A link with zero mass and such an inertia too.
  EXPECT_EQ(uio::load_string(imperfect_robot(kTriangle, "0")).warnings.size(), 1u);
  // The file in test/bad/ (0.01 + 0.01 < 0.03).
  const auto file = uio::load_file(urdf_path("test/bad/triangle.urdf"));
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_EQ(file.warnings[0].rfind(urdf_path("test/bad/triangle.urdf") + ": link 'b': ", 0), 0u) << file.warnings[0];
  EXPECT_NE(file.warnings[0].find("33.3 %"), std::string::npos) << file.warnings[0];
}

TEST(UrdfInertia, StrictModeRefusesTheTriangleInequalityNamingTheLink) {
  for (const auto& [xml, link] : std::vector<std::pair<std::string, std::string>>{
           {imperfect_robot(kTriangle), "foot"}, {imperfect_robot(kFine, "2", kTriangle), "sensor"}}) {
    try {
      const auto m = uio::load_string(xml, strict_inertia(), "robot.urdf");
      ADD_FAILURE() << "strict mode loaded a model with " << m.warnings.size() << " warnings";
    } catch (const ModelError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("robot.urdf: link '" + link + "': principal moments violate the triangle inequality", 0), 0u)
          << msg;
      EXPECT_NE(msg.find("short by 0.2"), std::string::npos) << msg;
    }
  }
  // A parsed model (load_model) too.
  urdf::ModelInterfaceSharedPtr parsed = urdf::parseURDF(imperfect_robot(kTriangle));
  ASSERT_TRUE(parsed);
  EXPECT_EQ(uio::load_model(*parsed).warnings.size(), 1u);
  EXPECT_THROW((void)uio::load_model(*parsed, strict_inertia()), ModelError);
  // Strict mode changes nothing for inertias that are fine.
  const auto fine = uio::load_string(imperfect_robot(kFine), strict_inertia());
  EXPECT_TRUE(fine.warnings.empty());
  EXPECT_EQ(fine.model.inertia(0).I, uio::load_string(imperfect_robot(kFine)).model.inertia(0).I);
  const auto hoap = uio::load_file(urdf_path("hoap3.urdf"), strict_inertia());
  EXPECT_TRUE(hoap.warnings.empty());
  EXPECT_TRUE(uio::load_file(urdf_path("hoap3.urdf")).warnings.empty());
}

TEST(UrdfInertia, WhatBreaksTheAlgorithmsIsRefusedInBothModes) {
  const std::string bad = urdf_path("test/bad/");
  for (const uio::LoadOptions& opt : {uio::LoadOptions{}, strict_inertia()}) {
    SCOPED_TRACE(opt.strict_inertia ? "strict" : "default");
    expect_error(bad + "not_psd.urdf", {"link 'b'", "positive semi-definite"}, opt);
    expect_error(bad + "negative_mass.urdf", {"link 'b'", "negative mass"}, opt);
    expect_error(bad + "nan_mass.urdf", {"[b]", "mass [nan]"}, opt);
    expect_error(bad + "overflow.urdf", {"link 'b'", "NaN or Inf"}, opt);
    // Not positive semi-definite and breaking the triangle inequality: the error wins.
    for (const char* inertia : {R"(ixx="-0.1" iyy="0.5" izz="1.0")", R"(ixx="0.1" iyy="0.1" izz="0.1" ixy="0.5")"}) {
      std::string xml = imperfect_robot(inertia);
      if (std::string(inertia).find("ixy") != std::string::npos) xml.replace(xml.find(R"(ixy="0" )"), 8, "");
      try {
        (void)uio::load_string(xml, opt);
        ADD_FAILURE() << "accepted " << inertia;
      } catch (const ModelError& e) {
        EXPECT_NE(std::string(e.what()).find("link 'foot': rotational inertia about the centre of mass is not positive "
                                             "semi-definite"),
                  std::string::npos)
            << e.what();
      }
    }
    try {
      (void)uio::load_string(imperfect_robot(kTriangle, "-1"), opt);
      ADD_FAILURE() << "accepted a negative mass";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("link 'foot': negative mass"), std::string::npos) << e.what();
    }
  }
}

TEST(UrdfErrors, BadOptions) {
  const std::string hoap = urdf_path("hoap3.urdf");
  uio::LoadOptions o;
  o.root = "R_SHOE";
  expect_error(hoap, {"root", "unknown link 'R_SHOE'"}, o);
  o = {};
  o.subtree = "TAIL";
  expect_error(hoap, {"subtree", "unknown link 'TAIL'"}, o);
  o = {};
  o.locked = {{"R_KNEE", 0.0}};
  expect_error(hoap, {"locked", "unknown joint 'R_KNEE'"}, o);
  o = {};
  o.locked = {{"R_LFE_R_KN_joint", std::nan("")}};
  expect_error(hoap, {"locked", "'R_LFE_R_KN_joint'", "non-finite"}, o);
  o = {};
  o.locked = {{"R_LFE_R_KN_joint", 0.1}, {"R_LFE_R_KN_joint", 0.2}};
  expect_error(hoap, {"'R_LFE_R_KN_joint'", "twice"}, o);
  o = {};
  o.gravity = Eigen::Vector3d(0, 0, std::numeric_limits<double>::infinity());
  expect_error(hoap, {"gravity", "NaN or Inf"}, o);
  o = {};
  o.locked = {{"free", 0.0}};
  expect_error(urdf_path("test/bad/floating.urdf"), {"'free'", "floating", "not supported"}, o);
  // A mimic joint is fine once locked.
  o.locked = {{"j2", 0.5}};
  EXPECT_EQ(uio::load_file(urdf_path("test/bad/mimic.urdf"), o).model.size(), 1);
}

TEST(UrdfErrors, StringsNameTheirSource) {
  try {
    (void)uio::load_string("<robot name='x'><link name='a'/>", {}, "my-robot");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("my-robot: not a valid URDF", 0), 0u) << e.what();
  }
  try {
    (void)uio::load_string(one_joint("revolute", "0 0 0", "0 0 0", "0 0 0"));
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("<string>: joint 'j'", 0), 0u) << e.what();
  }
}

TEST(UrdfErrors, ValuesUrdfdomLetThroughAreCheckedToo) {
  // urdfdom rejects "nan" and "inf" in the text, but a model can reach the loader by other ways: poke non-finite
  // numbers into a parsed model and check that the loader names them.
  const std::string path = urdf_path("test/serial_arm.urdf");
  const double nan = std::nan("");
  struct Poke {
    std::string word;
    std::function<void(urdf::ModelInterface&)> f;
  };
  const std::vector<Poke> pokes = {
      {"link 'link3': <inertial> contains NaN", [&](urdf::ModelInterface& m) { m.links_["link3"]->inertial->ixy = nan; }},
      {"link 'link2': <inertial> contains NaN", [&](urdf::ModelInterface& m) { m.links_["link2"]->inertial->mass = HUGE_VAL; }},
      {"link 'link4': <inertial> contains NaN",
       [&](urdf::ModelInterface& m) { m.links_["link4"]->inertial->origin.position.y = nan; }},
      {"joint 'elbow': <origin> contains NaN",
       [&](urdf::ModelInterface& m) { m.joints_["elbow"]->parent_to_joint_origin_transform.rotation.w = nan; }},
      {"joint 'wrist_roll': <axis> contains NaN", [&](urdf::ModelInterface& m) { m.joints_["wrist_roll"]->axis.z = nan; }},
      {"joint 'wrist_pitch': <limit> contains NaN",
       [&](urdf::ModelInterface& m) { m.joints_["wrist_pitch"]->limits->upper = nan; }},
      {"joint 'wrist_yaw': negative effort", [&](urdf::ModelInterface& m) { m.joints_["wrist_yaw"]->limits->effort = -1; }},
      {"link 'link5': negative mass", [&](urdf::ModelInterface& m) { m.links_["link5"]->inertial->mass = -1e-9; }},
  };
  for (const Poke& p : pokes) {
    urdf::ModelInterfaceSharedPtr m = spatial::testing::parse_urdf_or_throw(path);
    p.f(*m);
    try {
      (void)uio::load_model(*m, {}, "poked");
      ADD_FAILURE() << "expected ModelError for " << p.word;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("poked: " + p.word), std::string::npos) << e.what();
    }
  }
  // Unpoked, load_model works (children in joint-name order, here the same chain).
  const auto ok = uio::load_model(*spatial::testing::parse_urdf_or_throw(path));
  EXPECT_EQ(ok.model.size(), 6);
}

class CountingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string&, console_bridge::LogLevel, const char*, int) override { ++count; }
  int count = 0;
};

TEST(UrdfErrors, UrdfdomLogIsCapturedAndTheHandlerRestored) {
  CountingHandler mine;
  console_bridge::OutputHandler* before = console_bridge::getOutputHandler();
  console_bridge::useOutputHandler(&mine);
  const console_bridge::LogLevel level = console_bridge::getLogLevel();
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  EXPECT_THROW((void)uio::load_file(urdf_path("test/bad/nan_mass.urdf")), ModelError);
  EXPECT_EQ(mine.count, 0);  // urdfdom's errors went into the exception, not to the user's handler
  EXPECT_EQ(console_bridge::getOutputHandler(), &mine);
  EXPECT_EQ(console_bridge::getLogLevel(), console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_DEBUG);
  CONSOLE_BRIDGE_logError("after");
  EXPECT_EQ(mine.count, 1);
  console_bridge::setLogLevel(level);
  console_bridge::useOutputHandler(before);
}

}  // namespace

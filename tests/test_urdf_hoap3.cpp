// urdf/hoap3.urdf and urdf/double_pendulum.urdf against the data sheet (../shared/hoap3/DATASHEET.md) and the
// reference study's models.

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/urdf_reference.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using spatial::testing::urdf_path;

const double kMass = 8.8024;  // data sheet: sum of the manufacturer's link masses (chest with CPU and WLAN)

uio::LoadedModel hoap3(const uio::LoadOptions& o = {}) { return uio::load_file(urdf_path("hoap3.urdf"), o); }

uio::LoadOptions stance(const std::string& side) {
  uio::LoadOptions o;
  o.root = side + "_SOLE";
  for (const char* j : {"CHEST_H_PAN_joint", "H_PAN_H_TILT_joint", "H_TILT_H_ROLL_joint", "R_EB_R_WR_joint",
                        "L_EB_L_WR_joint"})
    o.locked.emplace_back(j, 0.0);
  return o;
}

TEST(Hoap3, StructureAndLimits) {
  const auto m = hoap3();
  ASSERT_EQ(m.model.size(), 26);  // legs 2x6, arms 2x5, waist, head 3
  EXPECT_EQ(m.root, "base_link");
  int revolute = 0;
  for (const auto& j : m.joints) {
    revolute += j.urdf_type == "revolute";
    EXPECT_TRUE(j.has_limits);
    EXPECT_LE(j.lower, j.upper) << j.name;
    EXPECT_EQ(j.velocity, 0.0) << j.name;  // unknown
  }
  EXPECT_EQ(revolute, 26);
  auto joint = [&](const std::string& n) { return m.joints[static_cast<std::size_t>(m.joint_index(n))]; };
  // Maximum torques from the data sheet; 0 = unknown (head).
  EXPECT_EQ(joint("WAIST_R_LR_joint").effort, 3.0);    // hip yaw
  EXPECT_EQ(joint("R_LR_R_LAA_joint").effort, 4.5);    // hip roll
  EXPECT_EQ(joint("R_LAA_R_LFE_joint").effort, 3.0);   // hip pitch
  EXPECT_EQ(joint("R_LFE_R_KN_joint").effort, 4.5);    // knee
  EXPECT_EQ(joint("R_KN_R_AFE_joint").effort, 4.5);    // ankle pitch
  EXPECT_EQ(joint("R_AFE_R_AAA_joint").effort, 3.0);   // ankle roll
  EXPECT_EQ(joint("WAIST_CHEST_joint").effort, 4.5);   // waist
  EXPECT_EQ(joint("L_SHR_L_EB_joint").effort, 3.0);    // elbow
  EXPECT_EQ(joint("L_EB_L_WR_joint").effort, 0.36);    // wrist
  EXPECT_EQ(joint("H_PAN_H_TILT_joint").effort, 0.0);  // head: unknown
  EXPECT_EQ(joint("L_LFE_L_KN_joint").lower, 0.0873);
  EXPECT_EQ(joint("L_LFE_L_KN_joint").upper, 2.2689);
  // Fixed frames: feet, soles, hands, head and eyes.
  for (const char* f : {"R_FOOT", "L_FOOT", "R_SOLE", "L_SOLE", "R_HAND", "L_HAND", "HEAD", "EYE", "REYE", "LEYE"}) {
    bool found = false;
    for (const auto& fr : m.model.frames()) found = found || fr.name == f;
    EXPECT_TRUE(found) << f;
  }
}

TEST(Hoap3, TotalMassAndCentreOfMassMatchTheDataSheet) {
  const auto m = hoap3();
  EXPECT_NEAR(uio::whole_body_mass(m), kMass, 1e-13);
  EXPECT_NEAR(m.model.base_mass(), 0.417, 1e-15);  // the pelvis is fixed to base_link
  Data<double> d(m.model);
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(26);
  const Eigen::Vector3d c = uio::whole_body_com(m, d, q);  // base_link: at the waist joint, x forward, z up
  // The data sheet rounds to the millimetre: the true value is within half a millimetre of it.
  const double tol = 0.5e-3;
  EXPECT_NEAR(c.x(), -0.035, tol);
  EXPECT_NEAR(c.y(), 0.000, tol);
  EXPECT_NEAR(c.z(), 0.012, tol);
  // Soles: both 0.305 m below the waist joint, parallel to base_link at q = 0.
  for (const char* sole : {"R_SOLE", "L_SOLE"}) {
    const Eigen::Isometry3d T = uio::link_pose(m, d, sole);
    EXPECT_NEAR(T.translation().z(), -0.305, 1e-15) << sole;
    EXPECT_LT((T.linear() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15) << sole;
    EXPECT_NEAR(c.z() - T.translation().z(), 0.317, tol) << sole;
  }
}

TEST(Hoap3, ReferenceModelsHaveTheStudysSizes) {
  // Torso: 8 DoF, base at the chest.
  uio::LoadOptions torso;
  torso.subtree = "CHEST";
  torso.locked = {{"CHEST_H_PAN_joint", 0}, {"H_PAN_H_TILT_joint", 0}, {"H_TILT_H_ROLL_joint", 0},
                  {"R_EB_R_WR_joint", 0}, {"L_EB_L_WR_joint", 0}};
  const auto t = hoap3(torso);
  EXPECT_EQ(t.model.size(), 8);
  EXPECT_TRUE(t.model.massless_joints().empty());
  // Stance on the right foot: 21 DoF. The stance leg is a chain up to the pelvis (WAIST); the waist joint and the
  // swing leg leave the pelvis; the arms leave the chest. (The study attaches the swing leg to the body after the
  // waist joint; the physical tree, followed here, hangs it from the pelvis.)
  const auto s = hoap3(stance("R"));
  ASSERT_EQ(s.model.size(), 21);
  EXPECT_TRUE(s.model.massless_joints().empty());
  const std::vector<int> parents = {-1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 6, 11, 12, 13, 5, 15, 16, 17, 18, 19};
  for (int i = 0; i < 21; ++i) EXPECT_EQ(s.model.parent(i), parents[static_cast<std::size_t>(i)]) << i;
  EXPECT_EQ(s.model.body_name(5), "WAIST");
  EXPECT_EQ(s.model.joint_name(6), "WAIST_CHEST_joint");
  EXPECT_EQ(s.model.joint_name(15), "WAIST_L_LR_joint");
  for (int i = 0; i < 21; ++i) EXPECT_FALSE(has_axis(s.model.joint_type(i))) << s.model.joint_name(i);
  EXPECT_EQ(s.model.gravity(), Eigen::Vector3d(0, 0, -9.81));
  const auto l = hoap3(stance("L"));
  EXPECT_EQ(l.model.size(), 21);
  EXPECT_EQ(l.model.joint_name(0), "L_AFE_L_AAA_joint");
}

TEST(Hoap3, StanceAnkleTorquesAreWeightTimesLeverArm) {
  // Rooted at the right sole, at rest at q = 0, the ankle joints carry everything above them. Independently of the
  // loader and of the algorithms, from urdfdom's numbers and our own forward kinematics: the supported mass m, its
  // centre of mass c, the ankle axis point p and direction a (reversed: the stance model walks the ankle joints
  // from the foot up). The joint torque holding the weight W = m g is τ = a · ((c − p) × (−m g)).
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path("hoap3.urdf"));
  const auto pose = spatial::testing::reference_link_poses(*urdf, {});
  const Eigen::Vector3d g(0, 0, -9.81);  // base_link and R_SOLE are parallel at q = 0
  auto supported = [&](const std::vector<std::string>& below, double& mass) {
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    mass = 0;
    for (const auto& [name, link] : urdf->links_) {
      if (!link->inertial || std::find(below.begin(), below.end(), name) != below.end()) continue;
      const auto& o = link->inertial->origin.position;
      first += link->inertial->mass * (pose.at(name) * Eigen::Vector3d(o.x, o.y, o.z));
      mass += link->inertial->mass;
    }
    return Eigen::Vector3d(first / mass);
  };
  auto axis = [&](const std::string& joint) {
    const auto j = urdf->getJoint(joint);
    return Eigen::Vector3d(pose.at(j->child_link_name).linear() * Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z));
  };
  const auto s = hoap3(stance("R"));
  Data<double> d(s.model);
  const Eigen::VectorXd tau = gravity_torques(s.model, d, Eigen::VectorXd::Zero(21));

  double m_roll = 0, m_pitch = 0;
  const Eigen::Vector3d c_roll = supported({"R_AAA"}, m_roll);            // above the ankle roll joint
  const Eigen::Vector3d c_pitch = supported({"R_AAA", "R_AFE"}, m_pitch);  // above the ankle pitch joint
  EXPECT_NEAR(m_roll, kMass - 0.154, 1e-13);
  EXPECT_NEAR(m_pitch, kMass - 0.154 - 0.195, 1e-13);
  const Eigen::Vector3d p = pose.at("R_AFE").translation();  // both ankle axes meet here
  const Eigen::Vector3d a_roll = -axis("R_AFE_R_AAA_joint"), a_pitch = -axis("R_KN_R_AFE_joint");
  EXPECT_LT((a_roll - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-15);  // roll: about -x, pitch: about -y
  EXPECT_LT((a_pitch - Eigen::Vector3d(0, -1, 0)).norm(), 1e-15);
  const double tau_roll = a_roll.dot((c_roll - p).cross(-m_roll * g));
  const double tau_pitch = a_pitch.dot((c_pitch - p).cross(-m_pitch * g));
  // Weight times the horizontal lever arm: τ_roll = −W (c − p)_y, τ_pitch = W (c − p)_x.
  EXPECT_NEAR(tau_roll, -m_roll * 9.81 * (c_roll - p).y(), 1e-14);
  EXPECT_NEAR(tau_pitch, m_pitch * 9.81 * (c_pitch - p).x(), 1e-14);
  ASSERT_EQ(s.model.joint_name(0), "R_AFE_R_AAA_joint");
  ASSERT_EQ(s.model.joint_name(1), "R_KN_R_AFE_joint");
  EXPECT_NEAR(tau[0], tau_roll, 1e-13);
  EXPECT_NEAR(tau[1], tau_pitch, 1e-13);
  // Magnitudes: the ankle roll holds 84.8 N about 39-44 mm to the side; the pitch lever arm is a fraction of a mm.
  EXPECT_NEAR(tau[0], -3.40, 0.01);
  EXPECT_LT(std::abs(tau[1]), 0.01);
}

TEST(Hoap3, DoublePendulumIsDerivedFromTheWholeBody) {
  const auto dp = uio::load_file(urdf_path("double_pendulum.urdf"));
  ASSERT_EQ(dp.model.size(), 2);
  EXPECT_EQ(dp.model.joint_type(0), JointType::RevoluteY);
  EXPECT_EQ(dp.model.joint_type(1), JointType::RevoluteY);
  EXPECT_EQ(dp.model.joint_name(0), "ankle_pitch");
  EXPECT_EQ(dp.model.joint_name(1), "hip_pitch");
  // The numbers again, from the whole-body model rooted at the right sole (z up), q = 0.
  const auto s = hoap3(stance("R"));
  Data<double> d(s.model);
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(21);
  const Eigen::Vector3d com = uio::whole_body_com(s, d, q0);
  const Eigen::Vector3d ankle = uio::link_pose(s, d, "R_AFE").translation();  // ankle pitch joint frame origin
  const Eigen::Vector3d hip = uio::link_pose(s, d, "R_LFE").translation();    // hip pitch joint frame origin
  const double m1 = 0.519 + 0.328 + 0.195 + 0.154;                           // R_LFE, R_KN, R_AFE, R_AAA
  auto sagittal = [](const Eigen::Vector3d& v) { return Eigen::Vector3d(v.x(), 0, v.z()); };
  const double tol = 1e-12;  // the generator rounds to 1e-12
  EXPECT_LT((dp.model.tree_transform(0).r - sagittal(ankle)).norm(), tol);
  EXPECT_LT((dp.model.tree_transform(1).r - sagittal(hip - ankle)).norm(), tol);
  EXPECT_NEAR(dp.model.tree_transform(1).r.norm(), 0.21, tol);  // l1 = thigh + shank
  EXPECT_NEAR(dp.model.inertia(0).m, m1, tol);
  EXPECT_NEAR(dp.model.inertia(1).m, kMass - m1, tol);
  EXPECT_NEAR(uio::whole_body_mass(dp), kMass, tol);
  EXPECT_LT((dp.model.inertia(0).com() - sagittal(hip - ankle)).norm(), tol);
  EXPECT_LT((dp.model.inertia(1).com() - sagittal(com - hip)).norm(), tol);
  EXPECT_NEAR(dp.model.inertia(1).com().norm(), 0.0674296292, 1e-9);  // l2
  // Point masses: no rotational inertia about their centres.
  EXPECT_LT(dp.model.inertia(0).inertia_com().norm(), 1e-18);
  EXPECT_LT(dp.model.inertia(1).inertia_com().norm(), 1e-18);
  // Its centre of mass at q = 0 is m2 at the robot's (sagittal) centre of mass and m1 at the hip.
  Data<double> dd(dp.model);
  const Eigen::Vector3d c = uio::whole_body_com(dp, dd, Eigen::VectorXd::Zero(2));
  EXPECT_LT((c - (m1 * sagittal(hip) + (kMass - m1) * sagittal(com)) / kMass).norm(), 1e-12);
  // A static check: leaning forward by θ, the joints hold the weights' moments, τ = −g Σ m x (x: the horizontal
  // lever arm in front of the joint).
  const double th = 0.1;
  Eigen::Vector2d qq(th, 0.0);
  const Eigen::VectorXd tau = gravity_torques(dp.model, dd, qq);
  const Eigen::Vector3d r1 = dp.model.tree_transform(1).r, r2 = dp.model.inertia(1).com();
  const Eigen::Matrix3d Ry = Eigen::AngleAxisd(th, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const double lever1 = (Ry * r1).x(), lever2 = (Ry * (r1 + r2)).x(), lever_hip = (Ry * r2).x();
  EXPECT_GT(lever2, 0.02);
  EXPECT_NEAR(tau[0], -9.81 * (m1 * lever1 + (kMass - m1) * lever2), 1e-12);
  EXPECT_NEAR(tau[1], -9.81 * (kMass - m1) * lever_hip, 1e-12);
}

}  // namespace

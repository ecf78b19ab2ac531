// Floating-base models from URDF (LoadOptions::floating, URDF `floating` joints) and the generated
// hoap3_floating model:
//  - the HOAP-3 free-flying at the pelvis has the whole robot's mass and centre of mass;
//  - rooted at a sole and floating, with the free-flyer locked at the identity (the sole at the world origin, at
//    rest), its joint rows are the stance model's: τ = RNEA rows 6…, H = the lower-right block, and q̈ from the
//    lower-right block equals the stance model's forward dynamics;
//  - a URDF floating joint from a massless "world" link loads floating from its child; one from a massive link is
//    refused, naming the joint.

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>
#include <spatial/models/hoap3_floating.hpp>

#include "support/random_model.hpp"
#include "support/reference.hpp"
#include "support/urdf_reference.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

using namespace spatial;
using spatial::testing::rel_diff;
using spatial::testing::urdf_path;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

std::vector<std::pair<std::string, double>> head_and_wrists() {
  return {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
          {"R_EB_R_WR_joint", 0.0},   {"L_EB_L_WR_joint", 0.0}};
}

urdf_io::LoadedModel load_hoap3(const std::string& root, bool floating) {
  urdf_io::LoadOptions o;
  o.root = root;
  o.locked = head_and_wrists();
  o.floating = floating;
  return urdf_io::load_file(urdf_path("hoap3.urdf"), o);
}

Vec random_joints(const urdf_io::LoadedModel& m, std::mt19937& rng) {
  Vec q(m.model.size());
  for (int i = 0; i < m.model.size(); ++i) {
    const auto& j = m.joints[static_cast<std::size_t>(i)];
    q[i] = std::uniform_real_distribution<double>(j.lower, j.upper)(rng);
  }
  return q;
}

TEST(FloatingUrdf, Hoap3AtThePelvisHasTheWholeRobot) {
  const auto loaded = load_hoap3("", true);
  ASSERT_TRUE(loaded.floating);
  const FloatingModel<double> m = urdf_io::floating_model(loaded);
  EXPECT_EQ(m.njoints(), 21);
  EXPECT_EQ(m.nq(), 28);
  EXPECT_EQ(m.nv(), 27);
  EXPECT_EQ(m.root_name(), "base_link");
  EXPECT_NEAR(m.total_mass(), 8.8024, 1e-12);
  // The centre of mass at the neutral root pose is the fixed pelvis model's whole-body CoM.
  const auto fixed = load_hoap3("", false);
  EXPECT_FALSE(fixed.floating);
  EXPECT_THROW(urdf_io::floating_model(fixed), ModelError);
  FloatingData<double> d(m);
  Data<double> fd(fixed.model);
  std::mt19937 rng(3);
  for (int t = 0; t < 5; ++t) {
    Vec q = neutral(m);
    q.tail(21) = random_joints(loaded, rng);
    const Vector3<double> c = center_of_mass(m, d, q);
    EXPECT_LT((c - urdf_io::whole_body_com(fixed, fd, q.tail(21))).norm(), 1e-15);
  }
}

TEST(FloatingUrdf, LockedFreeFlyerAtTheSoleIsTheStanceModel) {
  const auto floating = load_hoap3("R_SOLE", true);
  const auto stance = load_hoap3("R_SOLE", false);
  const FloatingModel<double> m = urdf_io::floating_model(floating);
  FloatingData<double> d(m);
  Data<double> sd(stance.model);
  std::mt19937 rng(5);
  const int n = stance.model.size();
  for (int t = 0; t < 20; ++t) {
    const Vec qj = random_joints(stance, rng);
    const Vec qdj = spatial::testing::random_vector(n, rng, 2.0);
    const Vec qddj = spatial::testing::random_vector(n, rng, 5.0);
    Vec q = neutral(m), v = Vec::Zero(m.nv()), a = Vec::Zero(m.nv());
    q.tail(n) = qj;
    v.tail(n) = qdj;
    a.tail(n) = qddj;
    const Vec tau = rnea(m, d, q, v, a);
    const Vec tau_s = rnea(stance.model, sd, qj, qdj, qddj);
    EXPECT_LT(rel_diff(Vec(tau.tail(n)), tau_s), 1e-15) << t;
    const Mat H = crba(m, d, q);
    const Mat H_s = crba(stance.model, sd, qj);
    EXPECT_LT(rel_diff(Mat(H.bottomRightCorner(n, n)), H_s), 1e-15) << t;
    // Forward dynamics with the root held: H_jj q̈ = τ − C_j.
    const Vec C = bias_forces(m, d, q, v);
    const Vec qdd = Mat(H.bottomRightCorner(n, n)).ldlt().solve(Vec(tau_s - C.tail(n)));
    const Vec qdd_s = aba(stance.model, sd, qj, qdj, tau_s);
    EXPECT_LT(rel_diff(qdd, qdd_s), 1e-11) << t;
    EXPECT_LT(rel_diff(qdd_s, qddj), 1e-11) << t;
  }
}

TEST(FloatingUrdf, FloatingJointFromAMasslessWorldLink) {
  const std::string urdf = R"(<robot name="r">
    <link name="world"/>
    <joint name="free" type="floating"><parent link="world"/><child link="trunk"/></joint>
    <link name="trunk"><inertial><mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="hinge" type="revolute"><parent link="trunk"/><child link="arm"/><origin xyz="0.1 0 0"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <link name="arm"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  </robot>)";
  const auto loaded = urdf_io::load_string(urdf);
  EXPECT_TRUE(loaded.floating);
  EXPECT_EQ(loaded.root, "trunk");
  const auto m = urdf_io::floating_model(loaded);
  EXPECT_EQ(m.nq(), 8);
  EXPECT_EQ(m.nv(), 7);
  EXPECT_DOUBLE_EQ(m.root_inertia().m, 2.0);
  EXPECT_DOUBLE_EQ(m.total_mass(), 3.0);

  std::string massive = urdf;
  massive.replace(massive.find("<link name=\"world\"/>"), 20,
                  "<link name=\"world\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" iyy=\"0.1\" izz=\"0.1\" "
                  "ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>");
  try {
    urdf_io::load_string(massive, {}, "massive.urdf");
    FAIL() << "a floating joint from a massive link was accepted";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'free'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("massive.urdf"), std::string::npos) << e.what();
  }
}

TEST(FloatingUrdf, GeneratedModelIsTheLoadedModel) {
  namespace fb = spatial::models::hoap3_floating;
  const auto loaded = load_hoap3("", true);
  const auto rt = urdf_io::floating_model(loaded);
  const auto ct = fb::floating_model();
  static_assert(decltype(ct)::NV == 27, "27 velocity coordinates");
  EXPECT_EQ(ct.root_name(), rt.root_name());
  EXPECT_EQ(ct.total_mass(), rt.total_mass());
  FloatingData<double, fb::Tree> cd(ct);
  FloatingData<double> rd(rt);
  std::mt19937 rng(9);
  Vec lo(fb::dof), hi(fb::dof);
  for (int i = 0; i < fb::dof; ++i) lo[i] = fb::lower[i], hi[i] = fb::upper[i];
  for (int t = 0; t < 10; ++t) {
    const Vec q = random_configuration(rt, lo, hi, rng);
    const Vec v = spatial::testing::random_vector(rt.nv(), rng);
    const Vec a = spatial::testing::random_vector(rt.nv(), rng);
    const Eigen::Matrix<double, 28, 1> qs = q;
    const Eigen::Matrix<double, 27, 1> vs = v, as = a;
    EXPECT_LT(rel_diff(Vec(rnea(ct, cd, qs, vs, as)), Vec(rnea(rt, rd, q, v, a))), 1e-14);
    EXPECT_LT(rel_diff(Mat(crba(ct, cd, qs)), Mat(crba(rt, rd, q))), 1e-14);
    EXPECT_LT(rel_diff(Vec(aba(ct, cd, qs, vs, as)), Vec(aba(rt, rd, q, v, a))), 1e-12);
  }
}

}  // namespace

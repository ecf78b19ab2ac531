// Re-rooting does not change physics.
//
// Model B: the robot rooted at a link r1 (held still). Model A: the robot rooted at its URDF root r0, which hangs
// from the world through a virtual 6-DoF chain (prismatic x, y, z, then revolute z, y, x: the pose of r0 is
// Trans(p) Rz(α) Ry(β) Rx(γ)). For a smooth joint trajectory q(t) of B, A's virtual joints are driven so that r0
// moves exactly as it does in B, i.e. so that r1 stays still in A too:
//   - positions: p, α, β, γ from r0's pose in B (forward kinematics of B);
//   - rates: q̇_v = J⁻¹ v_r0 and q̈_v = J⁻¹ (a_r0 − J̇ q̇_v), where v_r0, a_r0 are r0's spatial velocity and
//     acceleration in B and J (the virtual chain's Jacobian) and J̇ q̇_v come from A's own recursions. This is
//     exact: no finite differences.
// In B the ground holds r1; in A the virtual joints must then be *unactuated* and the ground's wrench acts on r1.
// That wrench F is the one that makes the six virtual-joint torques of A vanish (RNEA is affine in the external
// force, so F solves a 6×6 linear system). Then every real joint torque of A equals B's, and F equals B's base
// reaction plus the weight of the links merged into B's base.
// Tolerance: only rounding separates the two sides (RNEA over ≤ 32 bodies, two 6×6 solves with condition numbers
// ≲ 10³ here), so the differences are ~1e-13 of the torque scale; we allow 1e-11 of it, still nine orders of
// magnitude below any modelling error (a wrong sign, frame or inertia changes torques by ≥ 1e-3 of the scale).

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/random_model.hpp"
#include "support/urdf_reference.hpp"

#include <Eigen/LU>

#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using spatial::testing::urdf_path;

/// The URDF text with a virtual 6-DoF chain from a new root link "vb_world" to the URDF's root link.
std::string with_virtual_base(const std::string& xml, const std::string& urdf_root) {
  const std::string limit = R"(<limit lower="-100" upper="100" effort="0" velocity="0"/>)";
  auto joint = [&](const std::string& name, const std::string& type, const std::string& parent,
                   const std::string& child, const std::string& axis) {
    return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" +
           child + "\"/><axis xyz=\"" + axis + "\"/>" + (type == "prismatic" ? limit : std::string()) + "</joint>\n";
  };
  std::string chain = "<link name=\"vb_world\"/><link name=\"vb_x\"/><link name=\"vb_y\"/><link name=\"vb_z\"/>"
                      "<link name=\"vb_yaw\"/><link name=\"vb_pitch\"/>\n";
  chain += joint("vb_px", "prismatic", "vb_world", "vb_x", "1 0 0");
  chain += joint("vb_py", "prismatic", "vb_x", "vb_y", "0 1 0");
  chain += joint("vb_pz", "prismatic", "vb_y", "vb_z", "0 0 1");
  chain += joint("vb_rz", "continuous", "vb_z", "vb_yaw", "0 0 1");
  chain += joint("vb_ry", "continuous", "vb_yaw", "vb_pitch", "0 1 0");
  chain += joint("vb_rx", "continuous", "vb_pitch", urdf_root, "1 0 0");
  const std::size_t end = xml.rfind("</robot>");
  return xml.substr(0, end) + chain + xml.substr(end);
}

/// A cubic joint trajectory q(t) = c0 + c1 t + c2 t² + c3 t³ with its exact derivatives.
struct Cubic {
  Eigen::VectorXd c0, c1, c2, c3;
  Cubic(int n, std::mt19937& rng) {
    c0 = spatial::testing::random_vector(n, rng, 0.4);
    c1 = spatial::testing::random_vector(n, rng, 1.0);
    c2 = spatial::testing::random_vector(n, rng, 1.0);
    c3 = spatial::testing::random_vector(n, rng, 1.0);
  }
  Eigen::VectorXd q(double t) const { return c0 + t * (c1 + t * (c2 + t * c3)); }
  Eigen::VectorXd qd(double t) const { return c1 + t * (2 * c2 + 3 * t * c3); }
  Eigen::VectorXd qdd(double t) const { return 2 * c2 + 6 * t * c3; }
};

Motion<double> link_motion(const uio::LoadedModel& m, const std::vector<Motion<double>>& per_body,
                           const std::string& link) {
  const uio::LinkInfo& L = m.links[static_cast<std::size_t>(m.link_index(link))];
  if (L.body < 0) return Motion<double>::Zero();
  return L.X.apply(per_body[static_cast<std::size_t>(L.body)]);
}

void check_reroot(const std::string& file, const std::string& new_root, bool axis_aligned, unsigned seed) {
  SCOPED_TRACE(file + " rooted at " + new_root + (axis_aligned ? "" : " (axis_aligned = false)"));
  const std::string xml = spatial::testing::read_text(urdf_path(file));
  const std::string r0 = spatial::testing::parse_urdf_or_throw(urdf_path(file))->getRoot()->name;

  uio::LoadOptions ob;
  ob.root = new_root;
  ob.axis_aligned = axis_aligned;
  const uio::LoadedModel B = uio::load_string(xml, ob, file);
  uio::LoadOptions oa;
  oa.root = "vb_world";
  oa.axis_aligned = axis_aligned;
  const uio::LoadedModel A = uio::load_string(with_virtual_base(xml, r0), oa, file + "+virtual base");
  const int nb = B.model.size(), na = A.model.size();
  ASSERT_EQ(na, nb + 6);
  ASSERT_EQ(A.model.joint_name(5), "vb_rx");
  const uio::LinkInfo& r0_in_A = A.links[static_cast<std::size_t>(A.link_index(r0))];
  ASSERT_EQ(r0_in_A.body, 5);
  ASSERT_LT((r0_in_A.X.E - Eigen::Matrix3d::Identity()).norm() + r0_in_A.X.r.norm(), 1e-300);
  std::vector<int> a_of_b(static_cast<std::size_t>(nb));  // A index of each B joint
  for (int i = 0; i < nb; ++i) {
    a_of_b[static_cast<std::size_t>(i)] = A.model.joint_index(B.model.joint_name(i));
    ASSERT_GE(a_of_b[static_cast<std::size_t>(i)], 6);
  }

  // Conserved, root-independent quantities at rest: total mass.
  EXPECT_NEAR(uio::whole_body_mass(A), uio::whole_body_mass(B), 1e-14 * uio::whole_body_mass(B));

  const Model<double> A0 = A.model.with_gravity(Eigen::Vector3d::Zero());
  const Model<double> B0 = B.model.with_gravity(Eigen::Vector3d::Zero());
  Data<double> da(A.model), da0(A0), db(B.model), db0(B0);
  std::mt19937 rng(seed);
  const Cubic traj(nb, rng);
  for (double t : {0.0, 0.35, 0.8}) {
    const Eigen::VectorXd q = traj.q(t), qd = traj.qd(t), qdd = traj.qdd(t);

    // r0's motion in B.
    forward_kinematics(B.model, db, q);
    const Eigen::Isometry3d T = uio::link_pose(B, db, r0);
    rnea(B0, db0, q, qd, qdd);  // no gravity: data.a is the true acceleration
    const Motion<double> v_r0 = link_motion(B, db0.v, r0), a_r0 = link_motion(B, db0.a, r0);

    // Virtual joint positions: T = Trans(p) Rz(α) Ry(β) Rx(γ).
    const Eigen::Matrix3d& R = T.linear();
    const double beta = std::asin(-R(2, 0)), alpha = std::atan2(R(1, 0), R(0, 0)), gamma = std::atan2(R(2, 1), R(2, 2));
    Eigen::VectorXd QA = Eigen::VectorXd::Zero(na), QDA = QA, QDDA = QA;
    QA.head<3>() = T.translation();
    QA[3] = alpha;
    QA[4] = beta;
    QA[5] = gamma;
    for (int i = 0; i < nb; ++i) {
      const int k = a_of_b[static_cast<std::size_t>(i)];
      QA[k] = q[i];
      QDA[k] = qd[i];
      QDDA[k] = qdd[i];
    }
    forward_kinematics(A.model, da, QA);
    ASSERT_LT((uio::link_pose(A, da, r0).matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-14);

    // Virtual joint rates from r0's spatial velocity and acceleration.
    Eigen::Matrix<double, 6, 6> J;
    for (int k = 0; k < 6; ++k) {
      Eigen::VectorXd e = Eigen::VectorXd::Zero(na);
      e[k] = 1;
      forward_velocities(A0, da0, QA, e);
      J.col(k) = da0.v[5].vector();
    }
    const Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> Jlu(J);
    QDA.head<6>() = Jlu.solve(v_r0.vector());
    rnea(A0, da0, QA, QDA, QDDA);  // QDDA's virtual part is still 0: da0.a[5] = J̇ q̇_v
    QDDA.head<6>() = Jlu.solve(a_r0.vector() - da0.a[5].vector());

    // Sanity: in A, r0 now moves as in B and r1 is still.
    rnea(A0, da0, QA, QDA, QDDA);
    EXPECT_LT((link_motion(A, da0.v, r0).vector() - v_r0.vector()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((link_motion(A, da0.a, r0).vector() - a_r0.vector()).cwiseAbs().maxCoeff(), 1e-11);
    EXPECT_LT(link_motion(A, da0.v, new_root).vector().cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(link_motion(A, da0.a, new_root).vector().cwiseAbs().maxCoeff(), 1e-11);

    // Root-independent energies: the same motion has the same kinetic energy (H is consistent), and the
    // potential energies differ by that of the links merged into B's base.
    const double ke_a = kinetic_energy(A.model, da, QA, QDA), ke_b = kinetic_energy(B.model, db, q, qd);
    EXPECT_NEAR(ke_a, ke_b, 1e-12 * std::max(1.0, ke_b));
    const double pe_a = potential_energy(A.model, da, QA), pe_b = potential_energy(B.model, db, q);
    const double pe_base = -B.model.gravity().dot(B.base_inertia.h);
    EXPECT_NEAR(pe_a, pe_b + pe_base, 1e-12 * std::max(1.0, std::abs(pe_a)));

    // B's torques (r1 held still by its base).
    const Eigen::VectorXd tau_b = rnea(B.model, db, q, qd, qdd);
    // B's base reaction on the moving bodies plus the support of the base links' weight, in base coordinates.
    Force<double> reaction = Force<double>::Zero();
    for (int i = 0; i < nb; ++i)
      if (B.model.parent(i) < 0)
        reaction += db.X_up[static_cast<std::size_t>(i)].apply_force_inverse(db.f[static_cast<std::size_t>(i)]);
    const Eigen::Vector3d mg = B.base_inertia.m * B.model.gravity();
    const Force<double> weight(B.base_inertia.h.cross(B.model.gravity()), mg);  // c × m g, m g
    const Force<double> ground = reaction - weight;

    // A's torques with an external wrench F on r1's body, chosen so that the virtual joints are unactuated.
    const int body_r1 = A.links[static_cast<std::size_t>(A.link_index(new_root))].body;
    ASSERT_GE(body_r1, 5);
    std::vector<Force<double>> fext(static_cast<std::size_t>(na), Force<double>::Zero());
    const Eigen::VectorXd tau0 = rnea(A.model, da, QA, QDA, QDDA, fext, ForceFrame::Base);
    Eigen::MatrixXd M(na, 6);
    for (int k = 0; k < 6; ++k) {
      Vector6<double> w = Vector6<double>::Zero();
      w[k] = 1;
      fext[static_cast<std::size_t>(body_r1)] = Force<double>(w);
      M.col(k) = rnea(A.model, da, QA, QDA, QDDA, fext, ForceFrame::Base) - tau0;
    }
    const Vector6<double> F = M.topRows<6>().partialPivLu().solve(-tau0.head<6>());
    const Eigen::VectorXd tau_a = tau0 + M * F;

    const double scale = std::max(1.0, tau_b.cwiseAbs().maxCoeff());
    EXPECT_LT(tau_a.head<6>().cwiseAbs().maxCoeff(), 1e-11 * scale);
    double worst = 0;
    for (int i = 0; i < nb; ++i) worst = std::max(worst, std::abs(tau_a[a_of_b[static_cast<std::size_t>(i)]] - tau_b[i]));
    EXPECT_LT(worst, 1e-11 * scale) << "t = " << t << ", torque scale " << scale;
    const double fscale = std::max(1.0, ground.vector().cwiseAbs().maxCoeff());
    EXPECT_LT((F - ground.vector()).cwiseAbs().maxCoeff(), 1e-11 * fscale) << "F = " << F.transpose()
                                                                          << "\nground = " << ground.vector().transpose();
  }
}

TEST(UrdfReroot, Hoap3AtTheFeetAndElsewhere) {
  unsigned seed = 100;
  for (const char* root : {"R_SOLE", "L_FOOT", "R_KN", "L_HAND", "H_ROLL", "CHEST", "WAIST"})
    for (bool aligned : {true, false}) check_reroot("hoap3.urdf", root, aligned, seed++);
}

TEST(UrdfReroot, TestRobots) {
  unsigned seed = 200;
  for (const char* root : {"a10", "a5", "b2", "c3", "a8"}) check_reroot("test/all_joints.urdf", root, true, seed++);
  check_reroot("test/all_joints.urdf", "a10", false, seed++);
  for (const char* root : {"foot", "r_hand", "l_spacer1", "camera", "trunk"})
    check_reroot("test/branched.urdf", root, true, seed++);
  for (const char* root : {"tcp", "link3"}) check_reroot("test/serial_arm.urdf", root, true, seed++);
}

TEST(UrdfReroot, WholeBodyCentreOfMassIsTheSameFromEveryRoot) {
  // The centre of mass, expressed in one link's frame, does not depend on the root.
  const std::string path = urdf_path("hoap3.urdf");
  const uio::LoadedModel pelvis = uio::load_file(path);
  std::mt19937 rng(9);
  const Eigen::VectorXd q = spatial::testing::random_vector(26, rng, 0.6);
  Data<double> dp(pelvis.model);
  const Eigen::Vector3d c_pelvis = uio::whole_body_com(pelvis, dp, q);  // in base_link
  for (const char* root : {"R_SOLE", "L_HAND", "R_KN", "HEAD"}) {
    uio::LoadOptions o;
    o.root = root;
    const uio::LoadedModel m = uio::load_file(path, o);
    Eigen::VectorXd qm(26);
    for (int i = 0; i < 26; ++i) qm[i] = q[pelvis.model.joint_index(m.model.joint_name(i))];
    Data<double> d(m.model);
    const Eigen::Vector3d c = uio::whole_body_com(m, d, qm);  // in the new root; whole_body_com ran the kinematics
    const Eigen::Vector3d c_in_base_link = uio::link_pose(m, d, "base_link").inverse() * c;
    EXPECT_LT((c_in_base_link - c_pelvis).norm(), 1e-15) << root;
    EXPECT_NEAR(uio::whole_body_mass(m), 8.8024, 1e-14) << root;
  }
}

}  // namespace

// The reference study's experiments (tools/scenes.hpp, `spatial-dyn scene`): the cubic trajectories' boundary
// conditions, the resultant force against the weight and the ZMP against the centre of mass (computed by other
// code), forward dynamics recovering the trajectory's accelerations within a bound derived from cond(H), the motor
// table against the URDF, joint limits, and the command-line tool writing its files.
#include "scenes.hpp"
#include "support/cli_runner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using namespace spatial::scenes;
constexpr double kEps = std::numeric_limits<double>::epsilon();

std::vector<std::string> scene_list() { return scene_names(); }

TEST(Scenes, CubicsMeetTheirViaPointsAndStartAndEndAtRest) {
  for (const std::string& name : scene_list()) {
    SCOPED_TRACE(name);
    const Trajectory& tr = make_scene(name).trajectory;
    ASSERT_GE(tr.via_points(), 2);
    Eigen::VectorXd q, qd, qdd, ql, qdl, qddl;
    for (int k = 0; k < tr.via_points(); ++k) {
      tr.eval(tr.time(k), q, qd, qdd);
      const double scale = tr.position(k).cwiseAbs().maxCoeff() + 1;
      EXPECT_LE((q - tr.position(k)).cwiseAbs().maxCoeff(), 8 * kEps * scale);
      // The velocity is a sum of four terms of size |q|/T: rounding of order eps |q| / T.
      const double T = k + 1 < tr.via_points() ? tr.time(k + 1) - tr.time(k) : tr.time(k) - tr.time(k - 1);
      EXPECT_LE((qd - tr.velocity(k)).cwiseAbs().maxCoeff(), 32 * kEps * scale / T + 32 * kEps * tr.velocity(k).norm());
      if (k > 0) {
        // The end of the previous cubic reaches the same via point: evaluated just before t_k, it differs by at
        // most |q̇| dt + |q̈| dt² / 2.
        const double dt = 1e-7;
        tr.eval(tr.time(k) - dt, ql, qdl, qddl);
        EXPECT_LE((ql - tr.position(k)).cwiseAbs().maxCoeff(),
                  qdl.cwiseAbs().maxCoeff() * dt + qddl.cwiseAbs().maxCoeff() * dt * dt + 64 * kEps * scale);
        // q̇ just before t_k: q̇_k − q̈ dt + q⃛ dt²/2, where a cubic's q⃛ = (12 (p0 − p1) + 6 T (v0 + v1)) / T³ is bounded
        // by 36 (scale + T |v|) / T³ with the previous segment's T; plus rounding of order eps scale / T.
        const double Tp = tr.time(k) - tr.time(k - 1);
        const double v = std::max(tr.velocity(k).cwiseAbs().maxCoeff(), tr.velocity(k - 1).cwiseAbs().maxCoeff());
        const double sc = std::max(scale, tr.position(k - 1).cwiseAbs().maxCoeff() + 1);
        EXPECT_LE((qdl - tr.velocity(k)).cwiseAbs().maxCoeff(),
                  qddl.cwiseAbs().maxCoeff() * dt + 18 * (sc + Tp * v) / (Tp * Tp * Tp) * dt * dt +
                      64 * kEps * (sc / Tp + v));
      }
    }
    EXPECT_EQ(tr.velocity(0).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(tr.velocity(tr.via_points() - 1).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(tr.samples(), static_cast<int>(std::lround(tr.duration() / kPeriod)) + 1);
  }
}

TEST(Scenes, CubicAccelerationIsTheDerivativeOfItsVelocity) {
  const Trajectory& tr = make_scene("torso_strokes").trajectory;
  Eigen::VectorXd q0, qd0, qdd0, qa, qda, qdda, qb, qdb, qddb;
  const double h = 1e-6;
  for (double t = 0.05; t < tr.duration(); t += 0.1) {
    tr.eval(t, q0, qd0, qdd0);
    tr.eval(t - h, qa, qda, qdda);
    tr.eval(t + h, qb, qdb, qddb);
    // Central differences of a cubic are exact up to rounding (eps |q̇| / h) and the third derivative's h² term (0
    // for q̇'s difference of a cubic's q̈ being linear).
    EXPECT_LE(((qb - qa) / (2 * h) - qd0).cwiseAbs().maxCoeff(), 8 * kEps * (q0.cwiseAbs().maxCoeff() + 1) / h);
    EXPECT_LE(((qdb - qda) / (2 * h) - qdd0).cwiseAbs().maxCoeff(), 8 * kEps * (qd0.cwiseAbs().maxCoeff() + 1) / h);
  }
}

TEST(Scenes, EverySampleIsWithinTheJointLimits) {
  for (const std::string& name : scene_list()) {
    SCOPED_TRACE(name);
    const Scene s = make_scene(name);
    const bool torso_model = s.model == ModelKind::Torso;
    Eigen::VectorXd q, qd, qdd;
    for (int k = 0; k < s.trajectory.samples(); ++k) {
      s.trajectory.eval(k * kPeriod, q, qd, qdd);
      for (int i = 0; i < q.size(); ++i) {
        const auto u = static_cast<std::size_t>(i);
        const double lo = torso_model ? torso::lower[u] : stance::lower[u];
        const double hi = torso_model ? torso::upper[u] : stance::upper[u];
        ASSERT_GE(q[i], lo) << "sample " << k << " joint " << i;
        ASSERT_LE(q[i], hi) << "sample " << k << " joint " << i;
      }
    }
  }
}

TEST(Scenes, MotorTableAgreesWithTheUrdfMaximumTorques) {
  for (int i = 0; i < stance::dof; ++i) {
    const MotorTorque m = motor_torque(stance::joint_names[static_cast<std::size_t>(i)]);
    EXPECT_EQ(m.max, stance::effort[static_cast<std::size_t>(i)]) << stance::joint_names[static_cast<std::size_t>(i)];
    EXPECT_LT(m.rated, m.max);
  }
  for (int i = 0; i < torso::dof; ++i)
    EXPECT_EQ(motor_torque(torso::joint_names[static_cast<std::size_t>(i)]).max,
              torso::effort[static_cast<std::size_t>(i)]);
  EXPECT_THROW(motor_torque("CHEST_H_PAN_joint"), std::invalid_argument);
}

/// Static poses: the ground carries the weight, and the ZMP is the centre of mass's projection (whole_body_com adds
/// first moments of every body; ground_wrench adds RNEA's transmitted forces: two different computations).
TEST(Scenes, StaticResultantIsTheWeightAndZmpIsUnderTheCentreOfMass) {
  const auto m = stance::model();
  Data<double, stance::Tree> d(m);
  const double weight = stance::whole_body_mass * 9.81;
  const SupportPolygon sole;
  const Eigen::Matrix<double, stance::dof, 1> zero = Eigen::Matrix<double, stance::dof, 1>::Zero();
  std::vector<Eigen::VectorXd> poses;
  for (const StancePose& p : step_poses()) poses.push_back(solve_pose(p));
  poses.push_back(Eigen::VectorXd::Zero(stance::dof));
  for (std::size_t k = 0; k < poses.size(); ++k) {
    SCOPED_TRACE(k);
    const Eigen::Matrix<double, stance::dof, 1> q = poses[k];
    rnea(m, d, q, zero, zero);
    const Force<double> w = ground_wrench(m, d, stance::base_inertia<double>());
    // n additions of forces of size ≤ weight, each rounding by eps, through n transforms of as many flops.
    const double tol = 8 * stance::dof * kEps * weight;
    EXPECT_NEAR(w.f.z(), weight, tol);
    EXPECT_NEAR(w.f.x(), 0, tol);
    EXPECT_NEAR(w.f.y(), 0, tol);
    const Eigen::Vector3d com = stance::whole_body_com(m, d, q);
    const Eigen::Vector2d p = zmp(w);
    // Moments of size weight × 0.3 m; their rounding divided by the weight.
    EXPECT_NEAR(p.x(), com.x(), 8 * stance::dof * kEps * 0.5);
    EXPECT_NEAR(p.y(), com.y(), 8 * stance::dof * kEps * 0.5);
    if (k + 1 < poses.size()) EXPECT_TRUE(sole.contains(p.x(), p.y())) << p.transpose();  // the step's poses
    else EXPECT_FALSE(sole.contains(p.x(), p.y())) << p.transpose();  // all joints 0: CoM between the feet
  }
}

TEST(Scenes, PendulumCarriesTheSameWeightAndFollowsTheCentreOfMass) {
  const auto pm = pendulum::model();
  Data<double, pendulum::Tree> pd(pm);
  const auto m = stance::model();
  Data<double, stance::Tree> d(m);
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  for (const StancePose& p : step_poses()) {
    const Eigen::VectorXd q = solve_pose(p);
    const Eigen::Vector2d th = pendulum_angles(m, d, q);
    rnea(pm, pd, th, zero, zero);
    const Force<double> w = ground_wrench(pm, pd, pendulum::base_inertia<double>());
    const double weight = pendulum::whole_body_mass * 9.81;
    EXPECT_NEAR(w.f.z(), weight, 32 * kEps * weight);
    // Static: the ZMP is under the pendulum's own centre of mass.
    const Eigen::Vector3d pc = center_of_mass(pm, pd, th);
    EXPECT_NEAR(zmp(w).x(), pc.x(), 64 * kEps);
    // The trunk's point mass lies on the ray from the pendulum's hip towards the whole body's centre of mass, and
    // the hip on the ray from the ankle towards the whole body's hip-pitch axis (sagittal plane).
    Eigen::Matrix<double, stance::dof, 1> qs = q;
    const Eigen::Vector3d com = stance::whole_body_com(m, d, qs);
    const Eigen::Vector3d hip = d.X_base[3].r;
    forward_kinematics(pm, pd, th);
    const auto trunk = body_pose(pd, 1);
    const Eigen::Vector3d mass2 = trunk * (pm.inertia(1).h / pm.inertia(1).m);
    const Eigen::Vector3d p_hip = trunk.translation(), ankle = body_pose(pd, 0).translation();
    auto sagittal_cross = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return (a.x() * b.z() - a.z() * b.x()) / (std::hypot(a.x(), a.z()) * std::hypot(b.x(), b.z()));
    };
    EXPECT_NEAR(sagittal_cross(mass2 - p_hip, com - p_hip), 0, 64 * kEps);
    EXPECT_NEAR(sagittal_cross(p_hip - ankle, hip - ankle), 0, 64 * kEps);
  }
}

/// ‖FD(q, q̇, RNEA(q, q̇, q̈)) − q̈‖₂ ≤ c n ε ‖H⁻¹‖₂ (2 ‖H‖₂ ‖q̈‖₂ + ‖C‖₂): RNEA's rounding of τ and C, and the
/// backward-stable solve, both amplified by ‖H⁻¹‖; c = 4.
template <class T>
void check_forward_dynamics(const Scene& s, const Model<double, T>& m) {
  Data<double, T> d(m);
  using V = typename Data<double, T>::VectorN;
  Eigen::VectorXd q, qd, qdd;
  const int n = m.size();
  for (int k = 0; k < s.trajectory.samples(); k += 7) {
    s.trajectory.eval(k * kPeriod, q, qd, qdd);
    const V qv = q, qdv = qd, qddv = qdd;
    const V tau = rnea(m, d, qv, qdv, qddv);
    const V c = bias_forces(m, d, qv, qdv);
    const Eigen::MatrixXd H = crba(m, d, qv);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
    const double hmax = eig.eigenvalues().maxCoeff(), hinv = 1 / eig.eigenvalues().minCoeff();
    const double bound = 4 * n * kEps * hinv * (2 * hmax * qdd.norm() + c.norm());
    const V a1 = forward_dynamics_crba(m, d, qv, qdv, tau);
    const V a2 = aba(m, d, qv, qdv, tau);
    EXPECT_LE((a1 - qddv).norm(), bound) << s.name << " sample " << k;
    EXPECT_LE((a2 - qddv).norm(), bound) << s.name << " sample " << k;
  }
}

TEST(Scenes, ForwardDynamicsRecoverTheTrajectoryAccelerations) {
  for (const char* name : {"torso_arms", "torso_strokes"})
    check_forward_dynamics<torso::Tree>(make_scene(name), torso::model());
  for (const char* name : {"circles", "step"})
    check_forward_dynamics<stance::Tree>(make_scene(name), stance::model());
}

TEST(Scenes, StepZmpStaysInsideTheSole) {
  const Scene s = make_scene("step");
  const auto m = stance::model();
  Data<double, stance::Tree> d(m);
  const SupportPolygon sole;
  Eigen::VectorXd q, qd, qdd;
  for (int k = 0; k < s.trajectory.samples(); ++k) {
    s.trajectory.eval(k * kPeriod, q, qd, qdd);
    const Eigen::Matrix<double, stance::dof, 1> qv = q, qdv = qd, qddv = qdd;
    rnea(m, d, qv, qdv, qddv);
    const Eigen::Vector2d p = zmp(ground_wrench(m, d, stance::base_inertia<double>()));
    ASSERT_TRUE(sole.contains(p.x(), p.y())) << "sample " << k << ": " << p.transpose();
  }
}

#ifdef SPATIAL_DYN_EXE
TEST(Scenes, CommandLineWritesCsvAndSummary) {
  spatial::testing::ScratchDir dir("scenes");
  const auto r = spatial::testing::run_program(SPATIAL_DYN_EXE, {"scene", "step", "--out", dir.file("out")});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string csv = spatial::testing::slurp(dir.file("out/step.csv"));
  const std::string json = spatial::testing::slurp(dir.file("out/step.json"));
  const Scene s = make_scene("step");
  std::size_t lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_EQ(lines, static_cast<std::size_t>(s.trajectory.samples()) + 1);
  const std::string header = csv.substr(0, csv.find('\n'));
  for (const char* col : {"time", "tau:R_KN_R_AFE_joint", "tau/rated:R_KN_R_AFE_joint", "qdd_aba:WAIST_CHEST_joint",
                          "qdd_crba:L_LFE_L_KN_joint", "F_z", "zmp_x", "zmp_y"})
    EXPECT_NE(header.find(col), std::string::npos) << col;
  for (const char* key : {"\"static_Fz_N\"", "\"sample_ns\"", "\"max_tau_over_rated\"", "\"Fz_start_whole_N\": 83.3"})
    EXPECT_NE(json.find(key), std::string::npos) << key;

  const auto bad = spatial::testing::run_program(SPATIAL_DYN_EXE, {"scene", "dance"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("unknown scene 'dance'"), std::string::npos) << bad.err;
}
#endif

}  // namespace

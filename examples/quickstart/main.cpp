// Quick start (README.md): the HOAP-3 humanoid standing on its right sole, loaded from the installed URDF; inverse
// dynamics, the forward-dynamics round trip, and the same robot as a compile-time model.
#include <spatial/models/hoap3_stance_right.hpp>  // the same robot, every number a constant (spatial::hoap3_models)
#include <spatial/robots.hpp>                     // spatial::urdf_path: <prefix>/share/spatial/urdf/...
#include <spatial/spatial.hpp>                    // algorithms, checks, printing
#include <spatial/urdf.hpp>                       // spatial::urdf_io (spatial::urdf)

#include <cmath>
#include <iostream>

int main() {
  namespace uio = spatial::urdf_io;

  // 1. Load the robot re-rooted at the right sole, head and wrists locked at 0 (the wrists move no mass: with them
  //    the joint-space inertia matrix would be singular). 21 joints remain.
  uio::LoadOptions opt;
  opt.root = "R_SOLE";
  opt.locked = {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
                {"R_EB_R_WR_joint", 0.0},   {"L_EB_L_WR_joint", 0.0}};
  const uio::LoadedModel robot = uio::load_file(spatial::urdf_path("hoap3.urdf"), opt);
  const spatial::Model<double>& model = robot.model;
  std::cout << spatial::describe(robot);  // joints in model order, limits, mass, centre of mass, frames

  // 2. A state, in model order (model.joint_name(i)): the middle of each joint's range, moving.
  const int n = model.size();
  Eigen::VectorXd q(n), qd(n), qdd(n);
  for (int i = 0; i < n; ++i) {
    const uio::JointInfo& j = robot.joints[static_cast<std::size_t>(i)];
    q[i] = std::isfinite(j.lower + j.upper) ? 0.5 * (j.lower + j.upper) : 0.0;
    qd[i] = 0.3 * std::sin(i + 1.0);
    qdd[i] = 0.5 * std::cos(i + 1.0);
  }

  // 3. Inverse dynamics. The result is a reference into `data`, overwritten by the next call on the same data:
  //    copy it (Eigen::VectorXd tau = ...) or use a second Data to keep it.
  spatial::Data<double> data(model);
  const Eigen::VectorXd tau = spatial::rnea(model, data, q, qd, qdd);

  // 4. Forward dynamics gives q̈ back (ABA; spatial::forward_dynamics_crba is the other method).
  const Eigen::VectorXd qdd_aba = spatial::aba(model, data, q, qd, tau);
  const double round_trip = (qdd_aba - qdd).cwiseAbs().maxCoeff();

  // 5. The compile-time model of the same robot: same joints, same order, unrolled code.
  namespace stance = spatial::models::hoap3_stance_right;
  const auto fixed = stance::model();
  spatial::Data<double, stance::Tree> fixed_data(fixed);
  using VecN = Eigen::Matrix<double, stance::dof, 1>;  // a VecN of another size would not compile
  const VecN tau_fixed = spatial::rnea(fixed, fixed_data, VecN(q), VecN(qd), VecN(qdd));
  const double fixed_vs_runtime = (tau_fixed - tau).cwiseAbs().maxCoeff() / tau.cwiseAbs().maxCoeff();

  // 6. Where is the left hand? Frames by name, after forward kinematics.
  spatial::forward_kinematics(model, data, q);
  const Eigen::Vector3d hand = spatial::frame_pose(model, data, model.frame_index("L_HAND")).translation();

  // 7. Bad input: the checked entry points refuse it and say why instead of computing.
  const spatial::InputCheck bad = spatial::rnea_checked(model, data, q.head(n - 1), qd, qdd);

  std::cout << "tau[" << model.joint_name(2) << "] = " << tau[2] << " N m\n"
            << "ABA round trip: max |qdd - aba(rnea(qdd))| = " << round_trip << " rad/s^2\n"
            << "compile-time vs run-time model: max relative difference " << fixed_vs_runtime << "\n"
            << "L_HAND at q: " << hand.transpose() << " m (right-sole frame)\n"
            << "rnea_checked with 20 entries: " << bad << "\n";
  const bool ok = round_trip < 1e-9 && fixed_vs_runtime < 1e-12 && !bad.ok() && n == stance::dof;
  std::cout << (ok ? "quickstart: ok" : "quickstart: FAILED") << "\n";
  return ok ? 0 : 1;
}

#pragma once
// The reference study's experiments (thesis ch. 6; ../shared/hoap3/DATASHEET.md), shared by `spatial-dyn scene`
// (tools/spatial_dyn.cpp), its tests (tests/test_scenes.cpp) and the error study (bench/error_study.cpp).
//
// Trajectories are piecewise cubic polynomials in joint space (cubic Hermite segments between via points: the
// position and the velocity are given at every via point, zero unless a via point lies on a smooth path), sampled
// at 2 ms, as in the study. The study gives the kind of each motion but not its via points or durations; the
// choices below are ours and are printed by the tool (`Scene::notes`).
//
// Scenes:
//   torso_arms     torso model: both arms raised forward overhead and lowered
//   torso_strokes  torso model: arms raised forward, then four diagonal strokes up and down, then lowered
//   circles        whole body on the right foot: both arms draw identical (mirrored) circles
//   step           whole body on the right foot: one forward step of the left leg in single support
//   pendulum       the double inverted pendulum against the whole body during the step: resultant force, ZMP
//
// Resultant force on the robot (`ground_wrench`): what the fixed base (the ground) exerts on the robot, i.e. the
// force RNEA transmits into the base from its root bodies plus what holds the base's own mass (in the stance model
// the stance foot is part of the base) against gravity, in base coordinates (z up at the stance sole), moment about
// the base origin. The ZMP is the point of the sole plane z = 0 about which that moment has no horizontal part.
// Not part of the installed library.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_double_pendulum.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace spatial::scenes {

namespace torso = spatial::models::hoap3_torso;
namespace stance = spatial::models::hoap3_stance_right;
namespace pendulum = spatial::models::hoap3_double_pendulum;

/// The study's sampling period [s].
inline constexpr double kPeriod = 0.002;
/// Shoulder pitch with the arm hanging down [rad] (at 0 the HOAP-3's arms point forward, horizontally).
inline constexpr double kHang = 1.5708;

// ---------------------------------------------------------------------------------------------------------------
// Piecewise cubic trajectories

/// Via points (t_k, q_k, q̇_k), k = 0 … K−1, t strictly increasing; between two via points every joint follows the
/// cubic polynomial with those positions and velocities at both ends (cubic Hermite). The velocities at the first
/// and last via points are zero (the motion starts and ends at rest).
class Trajectory {
 public:
  Trajectory() = default;
  explicit Trajectory(int dof) : dof_(dof) {}

  int dof() const { return dof_; }
  int via_points() const { return static_cast<int>(t_.size()); }
  double time(int k) const { return t_[static_cast<std::size_t>(k)]; }
  const Eigen::VectorXd& position(int k) const { return q_[static_cast<std::size_t>(k)]; }
  const Eigen::VectorXd& velocity(int k) const { return qd_[static_cast<std::size_t>(k)]; }
  double duration() const { return t_.empty() ? 0.0 : t_.back(); }

  /// Adds a via point `dt` seconds after the previous one (the first via point is at t = 0 whatever dt is).
  Trajectory& to(double dt, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    if (q.size() != dof_ || qd.size() != dof_) throw std::invalid_argument("Trajectory: wrong number of joints");
    if (!t_.empty() && !(dt > 0)) throw std::invalid_argument("Trajectory: via points must be strictly later");
    t_.push_back(t_.empty() ? 0.0 : t_.back() + dt);
    q_.push_back(q);
    qd_.push_back(qd);
    return *this;
  }
  Trajectory& to(double dt, const Eigen::VectorXd& q) { return to(dt, q, Eigen::VectorXd::Zero(dof_)); }

  /// Number of 2 ms samples t = 0, h, 2h, … ≤ duration.
  int samples(double h = kPeriod) const { return static_cast<int>(std::floor(duration() / h + 1e-9)) + 1; }

  /// q, q̇, q̈ at time t. Outside [0, duration] the first or last cubic is extended (used for finite differences
  /// at the ends; sampled trajectories stay inside).
  void eval(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd, Eigen::VectorXd& qdd) const {
    std::size_t k = 0;
    while (k + 2 < t_.size() && t >= t_[k + 1]) ++k;
    const double T = t_[k + 1] - t_[k], s = (t - t_[k]) / T;
    const Eigen::VectorXd &p0 = q_[k], &p1 = q_[k + 1];
    const Eigen::VectorXd m0 = T * qd_[k], m1 = T * qd_[k + 1];
    // Hermite basis h00 = 2s³ − 3s² + 1, h10 = s³ − 2s² + s, h01 = −2s³ + 3s², h11 = s³ − s², and derivatives.
    const double s2 = s * s, s3 = s2 * s;
    q = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
    qd = ((6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * p1 + (3 * s2 - 2 * s) * m1) / T;
    qdd = ((12 * s - 6) * p0 + (6 * s - 4) * m0 + (-12 * s + 6) * p1 + (6 * s - 2) * m1) / (T * T);
  }

 private:
  int dof_ = 0;
  std::vector<double> t_;
  std::vector<Eigen::VectorXd> q_, qd_;
};

// ---------------------------------------------------------------------------------------------------------------
// Motor torques (data sheet: rated / maximum, N·m)

struct MotorTorque {
  double rated, max;
};

/// Rated and maximum torque of the motor of a HOAP-3 joint (URDF name): hip yaw, hip pitch, ankle roll and all arm
/// joints 1.5 / 3; hip roll, knee, ankle pitch and waist 2 / 4.5; wrists 0.28 / 0.36. Throws for other joints.
inline MotorTorque motor_torque(std::string_view joint) {
  const auto has = [&](std::string_view s) { return joint.find(s) != std::string_view::npos; };
  if (joint == "WAIST_CHEST_joint") return {2.0, 4.5};
  if (has("_WR_joint")) return {0.28, 0.36};
  if (has("_SFE_joint") || has("_SAA_joint") || has("_SHR_joint") || has("_EB_joint")) return {1.5, 3.0};  // arms
  if (has("_LR_joint")) return {1.5, 3.0};    // WAIST_x_LR: hip yaw
  if (has("_LAA_joint")) return {2.0, 4.5};   // x_LR_x_LAA: hip roll
  if (has("_LFE_joint")) return {1.5, 3.0};   // x_LAA_x_LFE: hip pitch
  if (has("_KN_joint")) return {2.0, 4.5};    // x_LFE_x_KN: knee
  if (has("_AFE_joint")) return {2.0, 4.5};   // x_KN_x_AFE: ankle pitch
  if (has("_AAA_joint")) return {1.5, 3.0};   // x_AFE_x_AAA: ankle roll
  throw std::invalid_argument("motor_torque: no motor data for joint '" + std::string(joint) + "'");
}

// ---------------------------------------------------------------------------------------------------------------
// Resultant force and ZMP

/// The wrench the fixed base exerts on the robot, in base coordinates, moment about the base origin, after `rnea`
/// on (model, data): Σ over root bodies of the force transmitted across their joints (data.f, body coordinates,
/// carried to the base), plus I_base (−a_g), the force that holds the base's own inertia still against gravity.
template <class S, class T>
Force<S> ground_wrench(const Model<S, T>& model, const Data<S, T>& data, const Inertia<S>& base_inertia) {
  Force<S> w = base_inertia * (-model.gravity_motion());
  for (int i = 0; i < model.size(); ++i)
    if (model.parent(i) < 0) {
      const auto k = static_cast<std::size_t>(i);
      w += data.X_up[k].apply_force_inverse(data.f[k]);
    }
  return w;
}

/// Zero-moment point on the plane z = 0 of the base frame: the point P with (n_O − P × f) horizontal part zero.
template <class S>
Eigen::Matrix<S, 2, 1> zmp(const Force<S>& w) {
  return Eigen::Matrix<S, 2, 1>(-w.n.y() / w.f.z(), w.n.x() / w.f.z());
}

/// The support polygon of the stance foot, in the sole frame: a rectangle. The data sheet and the thesis give no
/// sole size; we take 0.10 m × 0.06 m, centred on the sole frame's origin (see the README's scene section).
struct SupportPolygon {
  double x_min = -0.05, x_max = 0.05, y_min = -0.03, y_max = 0.03;
  bool contains(double x, double y) const { return x >= x_min && x <= x_max && y >= y_min && y <= y_max; }
  /// Signed distance to the nearest edge: positive inside.
  double margin(double x, double y) const {
    return std::min(std::min(x - x_min, x_max - x), std::min(y - y_min, y_max - y));
  }
};

// ---------------------------------------------------------------------------------------------------------------
// Poses of the whole-body (right-foot stance) model by inverse kinematics

/// Where the whole-body model stands at a via point of the step: the pelvis (frame base_link) level, at height
/// `pelvis_z`, placed horizontally so that the whole-body centre of mass is over (com_x, com_y); the swing (left)
/// sole level at (foot_x, foot_y, foot_z); the arms hanging (shoulder pitch kHang) plus a swing angle each;
/// everything else at 0.
struct StancePose {
  double pelvis_z, com_x, com_y;
  double foot_x, foot_y, foot_z;
  double right_arm_swing = 0, left_arm_swing = 0;
};

/// Joint angles of a `StancePose` (stance model order), by one multi-task inverse kinematics (ik.hpp) over the
/// twelve leg joints, arms and waist locked: the pelvis frame (base_link) level at height `pelvis_z` (its x and y
/// free: pose task with axes (0, 0, 1, 1, 1, 1)), the swing sole's pose, and the centre of mass's x and y (axes
/// (1, 1, 0)). The whole-body centre of mass includes the base (the stance foot, which does not move), while the
/// library's fixed-base CoM task is over the moving bodies: with M c = M_mov c_mov + h_base, the target c_mov =
/// (M c − h_base) / M_mov.
inline Eigen::VectorXd solve_pose(const StancePose& pose) {
  const auto m = stance::model();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(stance::dof);
  // Initial guess: knees bent forward, so the solver finds the knee-forward branch.
  q[2] = 0.4;
  q[18] = 0.4;
  q[1] = -0.2;
  q[3] = -0.2;
  q[17] = -0.2;
  q[19] = -0.2;
  q[7] = kHang + pose.right_arm_swing;
  q[11] = kHang + pose.left_arm_swing;
  const int pelvis = stance::frame_index("base_link"), sole = stance::frame_index("L_SOLE");
  const Eigen::Matrix3d level = Eigen::Matrix3d::Identity();
  const Inertia<double> base = stance::base_inertia<double>();
  const Eigen::Vector3d com_moving =
      (stance::whole_body_mass * Eigen::Vector3d(pose.com_x, pose.com_y, 0) - base.h) / stance::moving_mass;
  IkTask<double> hips = ik_pose(pelvis, Eigen::Vector3d(0.0, 0.039, pose.pelvis_z), level);
  hips.axes << 0, 0, 1, 1, 1, 1;
  IkTask<double> com = ik_center_of_mass(com_moving);
  com.axes << 1, 1, 0, 0, 0, 0;
  IkOptions<double> opt;
  opt.active = {0, 1, 2, 3, 4, 5, 15, 16, 17, 18, 19, 20};
  opt.tolerance = 1e-14;  // tighter than the default: the scenes want the exact pose
  IkSolver<Model<double, stance::Tree>> ik(
      m, {hips, ik_pose(sole, Eigen::Vector3d(pose.foot_x, pose.foot_y, pose.foot_z), level), com}, opt);
  const IkStatus<double> s = ik.solve(q);
  if (!s.converged)
    throw std::runtime_error(std::string("scenes: the stance pose was not reached (") + ik_reason_name(s.reason) +
                             ")");
  return q;
}

// ---------------------------------------------------------------------------------------------------------------
// The scenes

enum class ModelKind { Torso, Stance };

struct Scene {
  std::string name, title;
  ModelKind model;
  Trajectory trajectory;
  bool resultant = false;  ///< compute the resultant force and the ZMP (whole body)
  bool pendulum = false;   ///< and the double pendulum's resultant on the same motion
  std::vector<std::string> notes;  ///< our choices where the study is vague
};

inline const std::vector<std::string>& scene_names() {
  static const std::vector<std::string> names = {"torso_arms", "torso_strokes", "circles", "step", "pendulum"};
  return names;
}

namespace detail {

/// Torso joint vector (torso::joint_names order) from the right and left arm angles (SFE, SAA, SHR, EB), the left
/// arm mirrored: same shoulder pitch and elbow, roll and yaw negated (the left arm's roll range is [0, π/2]).
inline Eigen::VectorXd torso_q(double sfe, double saa, double shr, double eb) {
  Eigen::VectorXd q(torso::dof);
  q << sfe, saa, shr, eb, sfe, -saa, -shr, eb;
  return q;
}

/// Copies the arm angles of a torso-ordered vector into a stance-ordered one (arms: stance joints 7-10, 11-14).
inline void set_arms(Eigen::VectorXd& q, const Eigen::VectorXd& arms) {
  q.segment<4>(7) = arms.segment<4>(0);
  q.segment<4>(11) = arms.segment<4>(4);
}

}  // namespace detail

/// The step's via points (also the start pose of `circles`).
inline std::vector<StancePose> step_poses() {
  // Pelvis 20 mm lower than with straight legs (the knee's lower limit is 0.0873 rad: the legs are never straight);
  // centre of mass over the sole's centre and 6 mm forward of it at the end; swing foot lifted 25 mm, put down
  // 50 mm forward; arms swing ±0.15 rad in opposition to the legs.
  const double z = 0.285;
  // The left sole starts where it is with every joint at 0: 88 mm to the left of the right one.
  return {{z, 0.000, 0.0, 0.000, 0.088, 0.000, 0.00, 0.00},
          {z, 0.002, 0.0, -0.010, 0.088, 0.025, -0.08, 0.08},
          {z, 0.004, 0.0, 0.040, 0.088, 0.025, -0.15, 0.15},
          {z, 0.006, 0.0, 0.050, 0.088, 0.000, -0.15, 0.15}};
}

inline Scene make_scene(const std::string& name) {
  using V = Eigen::VectorXd;
  Scene s;
  s.name = name;
  if (name == "torso_arms") {
    s.title = "Torso: both arms raised and lowered";
    s.model = ModelKind::Torso;
    s.trajectory = Trajectory(torso::dof);
    s.trajectory.to(0, detail::torso_q(kHang, 0, 0, 0))
        .to(1.2, detail::torso_q(-1.3, -0.15, 0, -0.3))
        .to(0.4, detail::torso_q(-1.3, -0.15, 0, -0.3))
        .to(1.2, detail::torso_q(kHang, 0, 0, 0));
    s.notes = {"via points: arms hanging (shoulder pitch 1.5708 rad, the rest 0) -> raised forward to overhead "
               "(shoulder pitch -1.3 rad), roll 0.15 rad outward, elbow 0.3 rad, in 1.2 s -> held 0.4 s -> lowered "
               "in 1.2 s; zero velocity at every via point"};
  } else if (name == "torso_strokes") {
    s.title = "Torso: arms raised, then four transverse strokes up and down";
    s.model = ModelKind::Torso;
    s.trajectory = Trajectory(torso::dof);
    Trajectory& t = s.trajectory;
    t.to(0, detail::torso_q(kHang, 0, 0, 0)).to(0.8, detail::torso_q(0, -0.3, 0, -0.2));
    for (int k = 0; k < 4; ++k)
      t.to(0.3, detail::torso_q(-0.55, -0.6, 0.3, -0.5)).to(0.3, detail::torso_q(0.55, -0.05, -0.3, -0.1));
    t.to(0.3, detail::torso_q(0, -0.3, 0, -0.2)).to(0.8, detail::torso_q(kHang, 0, 0, 0));
    s.notes = {"via points: arms raised forward from hanging to horizontal (shoulder pitch 1.5708 -> 0 rad) in 0.8 s, "
               "then four strokes along a diagonal (pitch -0.55 <-> 0.55 rad, roll 0.6 <-> 0.05 rad outward, yaw and "
               "elbow with it) of 0.3 s per half stroke, back to horizontal and down; zero velocity at every via "
               "point (hence the larger accelerations)"};
  } else if (name == "circles") {
    s.title = "Whole body, right foot stance: identical circles with both arms";
    s.model = ModelKind::Stance;
    s.trajectory = Trajectory(stance::dof);
    const V q0 = solve_pose(step_poses().front());
    // Circle in (shoulder pitch, shoulder roll) about (0.9, −0.45) rad, radius 0.3 rad, two turns of 2 s each,
    // 12 via points per turn with the circle's tangent velocities (a smooth circle); left arm mirrored.
    const double c_pitch = 0.9, c_roll = -0.45, r = 0.3, turn = 2.0, two_pi = 6.283185307179586;
    const int per_turn = 12, turns = 2;
    auto on_circle = [&](double phi, double speed) {
      V q = q0, qd = V::Zero(stance::dof);
      detail::set_arms(q, detail::torso_q(c_pitch + r * std::cos(phi), c_roll + r * std::sin(phi), 0, -0.3));
      detail::set_arms(qd, detail::torso_q(-r * std::sin(phi) * speed, r * std::cos(phi) * speed, 0, 0));
      return std::make_pair(q, qd);
    };
    s.trajectory.to(0, q0);
    s.trajectory.to(0.8, on_circle(0, 0).first);
    const double w = two_pi / turn;
    for (int k = 1; k <= per_turn * turns; ++k) {
      const bool last = k == per_turn * turns;
      const auto [q, qd] = on_circle(two_pi * k / per_turn, last ? 0.0 : w);
      s.trajectory.to(turn / per_turn, q, qd);
    }
    s.trajectory.to(0.8, q0);
    s.notes = {"stance pose: the step's first via point (centre of mass over the right sole, pelvis level, 285 mm "
               "high)",
               "arms: from hanging to the circle in 0.8 s; two turns of 2 s in (shoulder pitch, shoulder roll) "
               "about (0.9, -0.45) rad, radius 0.3 rad, elbow 0.3 rad; left arm mirrored; 12 via points per turn "
               "with the circle's tangent velocities; back to hanging in 0.8 s"};
  } else if (name == "step" || name == "pendulum") {
    s.title = name == "step" ? "Whole body: one forward step in single support, right foot stance"
                             : "Double inverted pendulum against the whole body during the step";
    s.model = ModelKind::Stance;
    s.resultant = true;
    s.pendulum = name == "pendulum";
    s.trajectory = Trajectory(stance::dof);
    const auto poses = step_poses();
    const double dt[] = {0, 0.4, 0.4, 0.4};
    for (std::size_t k = 0; k < poses.size(); ++k) s.trajectory.to(dt[k], solve_pose(poses[k]));
    s.notes = {"single support from the moment the left foot leaves the ground to the moment it lands: 3 segments "
               "of 0.4 s (lift 25 mm, swing 50 mm forward, put down), zero velocity at the via points",
               "via points solved by inverse kinematics: pelvis level at 285 mm, centre of mass over the sole centre "
               "(moving 6 mm forward), left sole level, arms swinging +-0.15 rad in shoulder pitch",
               "support polygon: the right sole, taken as 0.10 m x 0.06 m centred on the sole frame (not in the "
               "data sheet)"};
    if (s.pendulum)
      s.notes.push_back("pendulum angles: link 1 along the whole body's ankle-pitch-axis -> hip-pitch-axis line, "
                        "link 2 towards the whole-body centre of mass (sagittal plane); rates by central differences "
                        "(h = 1e-4 s) on the cubic trajectory");
  } else {
    throw std::invalid_argument("unknown scene '" + name + "'");
  }
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// The double pendulum on the whole body's motion

/// Pendulum angles (ankle_pitch, hip_pitch) that put its hip on the line from its ankle to the whole body's
/// hip-pitch axis and its trunk towards the whole-body centre of mass, in the sagittal (x, z) plane of the sole.
inline Eigen::Vector2d pendulum_angles(const Model<double, stance::Tree>& m, Data<double, stance::Tree>& d,
                                       const Eigen::VectorXd& q) {
  const Eigen::Matrix<double, stance::dof, 1> qs = q;
  const Eigen::Vector3d com = stance::whole_body_com(m, d, qs);  // runs forward_kinematics
  const Eigen::Vector3d hip = d.X_base[3].r;                     // body 3's origin: on the hip pitch axis
  static const auto pm = pendulum::model();
  const Eigen::Vector3d ankle = pm.tree_transform(0).r;                    // the pendulum's ankle in the sole frame
  const Eigen::Vector3d l1 = pm.tree_transform(1).r;                       // link 1 at q = 0
  const Eigen::Vector3d c2 = pm.inertia(1).h / pm.inertia(1).m;    // trunk mass at q = 0, in link 2
  const double th1 = std::atan2(hip.x() - ankle.x(), hip.z() - ankle.z()) - std::atan2(l1.x(), l1.z());
  const Eigen::Vector3d p_hip = ankle + Eigen::Vector3d(l1.norm() * std::sin(th1), 0, l1.norm() * std::cos(th1));
  const double abs2 = std::atan2(com.x() - p_hip.x(), com.z() - p_hip.z()) - std::atan2(c2.x(), c2.z());
  return Eigen::Vector2d(th1, abs2 - th1);
}

}  // namespace spatial::scenes

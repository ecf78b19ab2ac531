// The open-loop whole-body walking pipeline (include/spatial/walking/whole_body.hpp) on the floating HOAP-3: the sole
// frames' geometry, the data sheet's motor torques, and a short walk (1 step, 1 s standing before and 0.5 s after, 5 ms
// ticks: 541 ticks, three passes) checked tick by tick with independent code paths (forward kinematics, centre of mass, manifold
// differences of consecutive ticks, frame accelerations, the contact wrenches' CoP). One run is shared by the tests.
//
// Tolerances: the IK stops at ‖r‖ ≤ 1e-11 (m, rad), so poses are checked at 1e-10; velocities and accelerations come
// from exact derivatives of the targets, so the stance sole's velocity and acceleration are zero to round-off of
// ~1e3 · eps times the largest entries (v ~ 1, v̇ ~ 10: 1e-10, 1e-9); central differences of q and v over 2 ms have
// truncation errors ~dt² · (third derivative) and rounding ~1e-11 / dt: bounds measured and set with a 3–5× margin.

#include <spatial/models/hoap3_floating.hpp>
#include <spatial/walking/whole_body.hpp>

#include "support/walking_hoap3.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fb = spatial::models::hoap3_floating;
using namespace spatial::walking;
// the compile-time tree, or its run-time twin in the sanitizer build
using spatial::testing::walking_hoap3::FM;
using spatial::testing::walking_hoap3::hoap3_frames;
using spatial::testing::walking_hoap3::make_model;
using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;

GaitParameters<double> short_gait() {
  GaitParameters<double> g;  // the HOAP-3 defaults of docs/walking.md (50 mm, 1.0 s, r = 0.2, 20 mm), one step
  g.steps = 1;
  // one second of standing before the first step: the preview controllers see the first step coming from t = 0 (with
  // less, the first stage starts by tracking late and the second stage cannot anticipate the error of the first ticks)
  g.initial_double_support = 1.0;
  g.final_double_support = 0.5;
  return g;
}

struct ShortWalk {
  FM model = make_model();
  FootstepPlan<double> plan{short_gait()};
  WholeBodyOptions<double> options;
  WholeBodyRun<FM> run;
  ShortWalk() {
    options = hoap3_whole_body_options<double>(fb::joint_names);
    // 5 ms ticks (the reference study's other period, Kajita 2003's example) to keep the sanitizer build's run short;
    // the pipeline does not depend on it
    options.preview.dt = 0.005;
    options.second_stage_iterations = 2;
    run = run_whole_body(model, hoap3_frames(), spatial::ik_limits(fb::lower), spatial::ik_limits(fb::upper), plan,
                         options);
  }
};

const ShortWalk& walk() {
  static const auto w = std::make_unique<ShortWalk>();
  return *w;
}

// ---------------------------------------------------------------------------------------------------------- setup

TEST(WholeBodySetup, SoleFrameIsTheCentreOfTheDataSheetSole) {
  // The data sheet's sole: x ∈ [−40, 68] mm from the point under the ankle-roll axis, 73 mm wide and centred 5 mm
  // outboard, 40 mm below the axis. The URDF's sole frames are that centre: the ankle is 14 mm behind, 5 mm inboard
  // and 40 mm above their origin, and their axes are the pelvis's at q = 0 (x forward, z up).
  const FM model = make_model();
  spatial::FloatingData<double, FM::tree_type> data(model);
  const auto q = spatial::neutral(model);
  spatial::forward_kinematics(model, data, q);
  for (const char* name : {"L_SOLE", "R_SOLE"}) {
    const int f = fb::frame_index(name);
    const int body = fb::frame_bodies[static_cast<std::size_t>(f)];
    const auto P = spatial::frame_pose(model, data, f);
    const V3 ankle = data.tree.X_base[static_cast<std::size_t>(body)].r;  // root = world at neutral
    const V3 in_sole = P.linear().transpose() * (ankle - P.translation());
    const double outboard = name[0] == 'L' ? 1.0 : -1.0;  // +y for the left foot
    EXPECT_NEAR((in_sole - V3(-0.014, -outboard * 0.005, 0.040)).norm(), 0.0, 1e-12) << name;
    EXPECT_NEAR((P.linear() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12) << name;
    // the sole centres are the plan's feet: 88 mm apart (docs/walking.md's step width)
    EXPECT_NEAR(std::abs(P.translation().y()), 0.044, 1e-12) << name;
  }
  const Sole<double> sole;  // the defaults used for the contacts: ±54 × ±36.5 mm about the sole frame
  EXPECT_DOUBLE_EQ(sole.front + sole.back, 0.108);
  EXPECT_DOUBLE_EQ(sole.left + sole.right, 0.073);
}

TEST(WholeBodySetup, Hoap3MotorTorquesFromTheDataSheet) {
  const auto o = hoap3_whole_body_options<double>(fb::joint_names);
  ASSERT_EQ(o.max_torque.size(), fb::dof);
  for (int j = 0; j < fb::dof; ++j) {
    // the URDF's effort limits are the data sheet's maximum torques
    EXPECT_DOUBLE_EQ(o.max_torque[j], fb::effort[static_cast<std::size_t>(j)]) << fb::joint_names[static_cast<std::size_t>(j)];
    // rated: 1.5 N m for the 3 N m motors, 2 N m for the 4.5 N m ones
    EXPECT_DOUBLE_EQ(o.rated_torque[j], o.max_torque[j] == 3.0 ? 1.5 : 2.0);
  }
  EXPECT_DOUBLE_EQ(o.rated_torque[fb::joint_index("WAIST_CHEST_joint")], 2.0);
  EXPECT_DOUBLE_EQ(o.rated_torque[fb::joint_index("R_LFE_R_KN_joint")], 2.0);
  EXPECT_DOUBLE_EQ(o.rated_torque[fb::joint_index("WAIST_L_LR_joint")], 1.5);
  const std::array<std::string_view, 1> bad = {{"NECK_joint"}};
  EXPECT_THROW(hoap3_whole_body_options<double>(bad), std::invalid_argument);
}

TEST(WholeBodySetup, BadFramesAndVectorsAreRejected) {
  const FM model = make_model();
  const auto lo = spatial::ik_limits(fb::lower), hi = spatial::ik_limits(fb::upper);
  auto o = hoap3_whole_body_options<double>(fb::joint_names);
  WholeBodyFrames f = hoap3_frames();
  f.left_sole = 99;
  EXPECT_THROW(WholeBodyGenerator<FM>(model, f, lo, hi, o), std::invalid_argument);
  // two frames on the same leg: 6 active joints, not the square 18
  f = hoap3_frames();
  f.left_sole = fb::frame_index("R_FOOT");
  EXPECT_THROW(WholeBodyGenerator<FM>(model, f, lo, hi, o), std::invalid_argument);
  o.posture.resize(3);
  EXPECT_THROW(WholeBodyGenerator<FM>(model, hoap3_frames(), lo, hi, o), std::invalid_argument);
}

// --------------------------------------------------------------------------------------------------- the short walk

TEST(WholeBodyWalk, IkConvergesAtEveryTickAndTheFeetFollowThePlan) {
  const ShortWalk& w = walk();
  EXPECT_TRUE(w.run.start.converged);
  spatial::FloatingData<double, FM::tree_type> data(w.model);
  const WholeBodyFrames fr = hoap3_frames();
  const double zc = w.options.preview.com_height;
  double foot = 0.0, com = 0.0, pelvis = 0.0, limits = 0.0;
  for (const auto& s : w.run.samples) {
    ASSERT_TRUE(s.ik.converged) << "t = " << s.t;
    ASSERT_LE(s.ik.residual, 1e-10) << "t = " << s.t;
    spatial::forward_kinematics(w.model, data, s.q);
    for (Foot f : {Foot::left, Foot::right}) {
      const FootState<double> target = w.plan.foot(f, s.t);
      const auto P = spatial::frame_pose(w.model, data, f == Foot::left ? fr.left_sole : fr.right_sole);
      const Eigen::Matrix3d R = Eigen::AngleAxisd(target.yaw, V3::UnitZ()).toRotationMatrix();
      foot = std::max({foot, (P.translation() - target.position).norm(), (P.linear() - R).norm()});
    }
    const V3 c = spatial::center_of_mass(w.model, data, s.q);
    com = std::max(com, (c - V3(s.com.x(), s.com.y(), zc)).norm());
    const double yaw = 0.5 * (w.plan.foot(Foot::left, s.t).yaw + w.plan.foot(Foot::right, s.t).yaw);
    pelvis = std::max(pelvis, (spatial::root_quaternion(s.q).toRotationMatrix() -
                               Eigen::AngleAxisd(yaw, V3::UnitZ()).toRotationMatrix()).norm());
    for (int j = 0; j < fb::dof; ++j)
      limits = std::max({limits, fb::lower[static_cast<std::size_t>(j)] - s.q[7 + j], s.q[7 + j] - fb::upper[static_cast<std::size_t>(j)]});
  }
  std::printf("  [whole body] %zu ticks: feet %.1e, CoM %.1e, pelvis %.1e from their targets; IK %.2f iterations "
              "per tick (max %d)\n",
              w.run.samples.size(), foot, com, pelvis, w.run.summary.ik_iterations_mean, w.run.summary.ik_iterations_max);
  EXPECT_LE(foot, 1e-10);
  EXPECT_LE(com, 1e-10);
  EXPECT_LE(pelvis, 1e-10);
  EXPECT_LE(limits, 0.0);
  EXPECT_LE(w.run.summary.ik_iterations_max, 5);  // the warm start is a second-order prediction
  // the standing pose has its knees bent (data sheet: ≈ 46°) and the CoM at z_c
  const auto& q0 = w.run.samples.front().q;
  EXPECT_GT(q0[7 + fb::joint_index("R_LFE_R_KN_joint")], 0.6);
  EXPECT_LT(q0[7 + fb::joint_index("R_LFE_R_KN_joint")], 1.0);
}

TEST(WholeBodyWalk, VelocitiesAndAccelerationsAreTheDerivativesOfTheConfiguration) {
  // v_k against (q_{k+1} ⊖ q_{k−1}) / 2dt on the manifold, v̇_k against (v_{k+1} − v_{k−1}) / 2dt (body-frame root
  // velocities: their time derivative is the root's spatial acceleration in root coordinates, floating.hpp's v̇).
  const ShortWalk& w = walk();
  const double dt = w.options.preview.dt;
  const auto& s = w.run.samples;
  double ev = 0.0, ea = 0.0, vmax = 0.0, amax = 0.0;
  for (std::size_t k = 1; k + 1 < s.size(); ++k) {
    const Eigen::VectorXd dq = spatial::difference(w.model, s[k - 1].q, s[k + 1].q) / (2 * dt);
    ev = std::max(ev, (dq - s[k].v).cwiseAbs().maxCoeff());
    ea = std::max(ea, ((s[k + 1].v - s[k - 1].v) / (2 * dt) - s[k].a).cwiseAbs().maxCoeff());
    vmax = std::max(vmax, s[k].v.cwiseAbs().maxCoeff());
    amax = std::max(amax, s[k].a.cwiseAbs().maxCoeff());
  }
  std::printf("  [whole body] |v| ≤ %.3f, |v̇| ≤ %.2f; central differences differ by %.1e and %.1e\n", vmax, amax, ev, ea);
  EXPECT_GT(vmax, 0.1);  // the walk moves
  // measured at dt = 5 ms: 1.0e-3 and 2.9e-2 of the largest entries (the swing knee at lift-off, |v̇| ≈ 19 rad/s²;
  // at 2 ms: 1.9e-4 and 7.7e-3, the dt² of central differences); a v or v̇ in the wrong frame would be off by O(1)
  EXPECT_LE(ev, 3e-3 * vmax);
  EXPECT_LE(ea, 0.1 * amax);
}

TEST(WholeBodyWalk, StanceSolesDoNotMoveAndSwingSolesFollowTheirTrajectories) {
  const ShortWalk& w = walk();
  spatial::FloatingData<double, FM::tree_type> data(w.model);
  const WholeBodyFrames fr = hoap3_frames();
  const auto LWA = spatial::ReferenceFrame::LocalWorldAligned;
  double stance_v = 0.0, stance_a = 0.0, swing_a = 0.0;
  int swing_ticks = 0;
  for (const auto& s : w.run.samples) {
    spatial::forward_kinematics(w.model, data, s.q, s.v, s.a);
    for (Foot f : {Foot::left, Foot::right}) {
      const int frame = f == Foot::left ? fr.left_sole : fr.right_sole;
      const spatial::Motion<double> vel = spatial::frame_velocity(w.model, data, frame, LWA);
      const V3 acc = spatial::frame_classical_acceleration(w.model, data, frame, LWA);
      const V3 wdot = spatial::frame_acceleration(w.model, data, frame, LWA).w;
      if (w.plan.in_contact(f, s.t)) {
        stance_v = std::max({stance_v, vel.v.norm(), vel.w.norm()});
        stance_a = std::max({stance_a, acc.norm(), wdot.norm()});
      } else {
        const FootState<double> target = w.plan.foot(f, s.t);
        swing_a = std::max({swing_a, (vel.v - target.velocity).norm(), (acc - target.acceleration).norm(),
                            (wdot - V3(0, 0, target.yaw_acceleration)).norm()});
        ++swing_ticks;
      }
    }
  }
  std::printf("  [whole body] stance soles: |v| ≤ %.1e, |a| ≤ %.1e; swing soles off their trajectory by %.1e\n",
              stance_v, stance_a, swing_a);
  EXPECT_GT(swing_ticks, 100);
  EXPECT_LE(stance_v, 1e-10);
  EXPECT_LE(stance_a, 1e-9);
  EXPECT_LE(swing_a, 1e-9);
}

TEST(WholeBodyWalk, ContactInverseDynamicsFindsAPhysicalSplitWhoseCopIsTheMultibodyZmp) {
  const ShortWalk& w = walk();
  const Sole<double> sole = w.options.sole;
  int ok = 0;
  double residual = 0.0, cop = 0.0, min_fz = 1e9, foot_cop = 1e9, weight = 0.0;
  for (const auto& s : w.run.samples) {
    if (!s.ok) continue;
    ++ok;
    residual = std::max(residual, s.root_residual);
    cop = std::max(cop, (s.cop - s.zmp_multibody).norm());
    double fz = 0.0;
    for (int f = 0; f < 2; ++f) {
      const auto& l = s.wrench[static_cast<std::size_t>(f)];
      if (!s.contact[static_cast<std::size_t>(f)]) {
        EXPECT_EQ(l.norm(), 0.0);
        continue;
      }
      min_fz = std::min(min_fz, l[2]);
      fz += l[2];
      if (l[2] > 1e-6) {  // each sole's own CoP (sole axes): x = −n_y / f_z, y = n_x / f_z
        const double x = -l[4] / l[2], y = l[3] / l[2];
        foot_cop = std::min({foot_cop, sole.front - x, x + sole.back, sole.left - y, y + sole.right});
      }
    }
    weight = std::max(weight, std::abs(fz / (w.model.total_mass() * 9.81) - 1.0));
  }
  std::printf("  [whole body] split ok at %d / %zu ticks; root residual %.1e; |CoP − ZMP| %.1e; min f_z %.2f N; "
              "sole CoPs ≥ %.1f mm inside; vertical force within %.1f %% of the weight\n",
              ok, w.run.samples.size(), residual, cop, min_fz, 1e3 * foot_cop, 100 * weight);
  EXPECT_EQ(ok, static_cast<int>(w.run.samples.size()));
  EXPECT_LE(residual, 1e-9);
  EXPECT_LE(cop, 1e-9);
  EXPECT_GE(min_fz, 0.0);
  EXPECT_GE(foot_cop, -1e-9);
  EXPECT_LE(weight, 0.2);
  // independently: the multibody ZMP of the stored state by zmp.hpp
  spatial::FloatingData<double, FM::tree_type> data(w.model);
  const auto& s = w.run.samples[w.run.samples.size() / 2];
  const V3 p = spatial::multibody_zmp(w.model, data, s.q, s.v, s.a, 0.0);
  EXPECT_NEAR((p.head<2>() - s.zmp_multibody).norm(), 0.0, 1e-12);
}

TEST(WholeBodyWalk, SecondStageReducesTheMultibodyZmpError) {
  const ShortWalk& w = walk();
  const auto& p = w.run.summary.passes;
  ASSERT_EQ(p.size(), 3u);
  for (std::size_t i = 0; i < p.size(); ++i)
    std::printf("  [whole body] pass %zu: |p_mb − p_ref| max %.3f mm, RMS %.3f mm; |p_mb − p_ct| max %.3f mm, RMS "
                "%.3f mm; min margin %.1f mm\n",
                i, 1e3 * p[i].zmp_error_max, 1e3 * p[i].zmp_error_rms, 1e3 * p[i].zmp_error_ct_max,
                1e3 * p[i].zmp_error_ct_rms, 1e3 * p[i].min_margin);
  // the first stage leaves millimetres between the multibody and the cart-table ZMP
  EXPECT_GT(p[0].zmp_error_ct_max, 1e-3);
  // each correction shrinks it (to the second controller's tracking error of the previous one)
  EXPECT_LT(p[1].zmp_error_ct_max, 0.6 * p[0].zmp_error_ct_max);
  EXPECT_LT(p[2].zmp_error_ct_max, 0.6 * p[1].zmp_error_ct_max);
  EXPECT_LT(p[2].zmp_error_ct_rms, 0.1 * p[0].zmp_error_ct_rms);
  // against the reference: what is left is the cart-table's own tracking error
  EXPECT_LT(p[2].zmp_error_max, 0.5 * p[0].zmp_error_max);
  EXPECT_LT(p[2].zmp_error_rms, 0.2 * p[0].zmp_error_rms);
  EXPECT_LE(p[2].zmp_error_max, w.run.summary.cart_table_error_max + 0.5e-3);
  // the corrected multibody ZMP lies where the cart-table ZMP lies: well inside the support polygon
  EXPECT_GT(w.run.summary.multibody_min_margin, 0.030);
  EXPECT_GT(p[2].min_margin, p[0].min_margin);
  // the stored samples are the last pass's
  const auto& last = w.run.zmp_multibody.back();
  for (std::size_t k = 0; k < w.run.samples.size(); k += 97)
    EXPECT_EQ(last.row(static_cast<Eigen::Index>(k)).transpose(), w.run.samples[k].zmp_multibody);
}

TEST(WholeBodyWalk, TorquesAgainstTheMotors) {
  const ShortWalk& w = walk();
  const auto& sum = w.run.summary;
  ASSERT_EQ(sum.max_ratio.size(), fb::dof);
  for (int j = 0; j < fb::dof; ++j)
    std::printf("  [whole body] %-20s max |τ| %.3f N m: %.2f of rated, %.2f of maximum\n",
                std::string(fb::joint_names[static_cast<std::size_t>(j)]).c_str(), sum.torque_max[j],
                sum.rated_ratio[j], sum.max_ratio[j]);
  // every motor within its maximum torque on this gentle walk; the stance hip roll and knee work hardest
  EXPECT_LT(sum.max_ratio.maxCoeff(), 1.0);
  EXPECT_GT(sum.torque_max[fb::joint_index("R_LFE_R_KN_joint")], 1.0);
  EXPECT_GT(sum.torque_max[fb::joint_index("L_LR_L_LAA_joint")], 1.0);
  // torques from the run equal RNEA − Jᵀλ recomputed: spot check one single-support tick through the round trip
  // (constrained forward dynamics with these torques gives back v̇)
  spatial::FloatingData<double, FM::tree_type> data(w.model);
  for (const auto& s : w.run.samples) {
    if (s.contact[0] && s.contact[1]) continue;
    const int frame = s.contact[0] ? fb::frame_index("L_SOLE") : fb::frame_index("R_SOLE");
    spatial::ContactData<FM> cd(w.model, {spatial::contact_6d<double>(frame)});
    Eigen::VectorXd tau = s.tau;
    tau.head<6>().setZero();
    spatial::constrained_forward_dynamics(w.model, data, cd, s.q, s.v, tau);
    EXPECT_NEAR((cd.qdd - s.a).cwiseAbs().maxCoeff(), 0.0, 1e-8 * (1.0 + s.a.cwiseAbs().maxCoeff()));
    EXPECT_NEAR((cd.lambda - s.wrench[s.contact[0] ? 0 : 1]).norm(), 0.0, 1e-8);
    break;
  }
}

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(WholeBodyWalk, RunTimeTreeGivesTheSameTicks) {
  const ShortWalk& w = walk();
  const auto rt = w.model.to_runtime();
  using RM = std::decay_t<decltype(rt)>;
  auto options = w.options;
  options.preview.dt = 0.002;
  GaitParameters<double> g = short_gait();
  g.initial_double_support = 0.0;
  const FootstepPlan<double> plan(g);
  WholeBodyGenerator<RM> gen(rt, hoap3_frames(), spatial::ik_limits(fb::lower), spatial::ik_limits(fb::upper),
                             options);
  WholeBodyGenerator<FM> ref(w.model, hoap3_frames(), spatial::ik_limits(fb::lower), spatial::ik_limits(fb::upper),
                             options);
  PreviewController<double> ctl(options.preview);
  const auto zref = sample_zmp_reference(plan, options.preview.dt);
  const PreviewTrajectory<double> pt = run_preview(ctl, zref);
  gen.start(plan, zref.row(0).transpose());
  ref.start(plan, zref.row(0).transpose());
  for (int k = 0; k < 120; ++k) {  // through the first double support into single support
    Eigen::Matrix<double, 3, 2> c;
    c << pt.com.row(k), pt.com_velocity.row(k), pt.com_acceleration.row(k);
    const auto& a = gen.tick(plan, k * options.preview.dt, c);
    const auto& b = ref.tick(plan, k * options.preview.dt, c);
    ASSERT_NEAR((a.q - b.q).cwiseAbs().maxCoeff(), 0.0, 1e-12) << k;
    ASSERT_NEAR((a.tau - b.tau).cwiseAbs().maxCoeff(), 0.0, 1e-9) << k;
  }
}
#endif

}  // namespace

// The walking pattern generator (include/spatial/walking/): footstep plan, swing trajectories, reference ZMP,
// support polygons, and ZMP preview control on the cart-table model (Kajita et al., ICRA 2003).
//
// HOAP-3 numbers (/work/shared/hoap3/DATASHEET.md; docs/walking.md gives the reasoning): dt = 2 ms (the reference
// study's trajectory period and the tick), z_c = 0.30 m (the whole-body CoM is 0.317 m above the soles with
// straight legs; bending the knees to ~46° lowers the hips by 2 · 0.105 · (1 − cos 23°) ≈ 17 mm), feet 88 mm apart
// (hips 2 × 39 mm apart, sole centres 5 mm outboard of the ankles), soles 108 × 73 mm.
//
// Tolerances: exact formulas are compared to a few ulps of their magnitudes; finite differences of the returned
// trajectories use central differences with h = 1e-6 s on O(1)–O(1e3) derivatives (truncation ~h² · f''' and
// rounding ~eps · f / h give ~1e-6 relative, checked at 1e-5 · scale).

#include <spatial/walking/footsteps.hpp>
#include <spatial/walking/preview.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace {

using namespace spatial::walking;
using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;
using Ref2 = Eigen::Matrix<double, Eigen::Dynamic, 2>;

constexpr double kEps = 1e-12;

GaitParameters<double> hoap3_gait() {
  GaitParameters<double> g;  // the defaults are the HOAP-3 numbers; spelled out here for the reader
  g.steps = 8;
  g.step_length = 0.05;
  g.step_width = 0.088;
  g.period = 1.0;
  g.double_support_ratio = 0.2;
  g.swing_height = 0.02;
  g.first_swing = Foot::right;
  g.initial_double_support = 1.0;
  g.final_double_support = 1.5;
  return g;
}

PreviewParameters<double> hoap3_preview() {
  PreviewParameters<double> p;
  p.dt = 0.002;
  p.com_height = 0.30;
  p.gravity = 9.81;
  p.q_error = 1.0;
  p.q_state = 0.0;
  p.r_input = 1e-6;
  p.preview_time = 1.6;
  return p;
}

// ------------------------------------------------------------------------------------------------ cart-table model

TEST(WalkingCartTable, ZmpOfConstantAccelerationIsExact) {
  PreviewController<double> ctl(hoap3_preview());
  const double zg = 0.30 / 9.81;
  PreviewController<double>::State x;
  x << 0.12, -0.03,  // rows c, ċ, c̈; columns x, y
      0.4, 1.5,       //
      -0.5, -2.25;
  // with zero jerk the acceleration stays constant and the model integrates the parabola exactly
  for (int k = 0; k <= 500; ++k) {
    const double t = 0.002 * k;
    const V2 c(0.12 + 0.4 * t - 0.25 * t * t, -0.03 + 1.5 * t - 1.125 * t * t);
    const V2 a(-0.5, -2.25);
    const V2 expected = c - zg * a;
    ASSERT_NEAR((ctl.zmp(x) - expected).norm(), 0.0, 1e-14) << "t = " << t;
    EXPECT_EQ(x(2, 0), -0.5);
    EXPECT_EQ(x(2, 1), -2.25);
    x = (ctl.A() * x).eval();
  }
  // one sample with jerk u from the Taylor series of a cubic
  const double dt = 0.002, u = 7.0;
  V3 s(0.1, 0.2, 0.3);
  const V3 n = ctl.A() * s + ctl.B() * u;
  EXPECT_NEAR(n(0), 0.1 + 0.2 * dt + 0.3 * dt * dt / 2 + u * dt * dt * dt / 6, kEps);
  EXPECT_NEAR(n(1), 0.2 + 0.3 * dt + u * dt * dt / 2, kEps);
  EXPECT_NEAR(n(2), 0.3 + u * dt, kEps);
}

TEST(WalkingPreview, CoMAtRestOverConstantReferenceStaysThere) {
  PreviewController<double> ctl(hoap3_preview());
  PreviewController<double>::State x = PreviewController<double>::State::Zero();
  x(0, 0) = 0.137;
  x(0, 1) = -0.021;
  ctl.reset(x);
  Ref2 ref(ctl.horizon() + 1, 2);
  ref.col(0).setConstant(0.137);
  ref.col(1).setConstant(-0.021);
  PreviewController<double>::State y = x;
  for (int k = 0; k < 3000; ++k) y = ctl.step(y, ref);
  EXPECT_EQ(y, x);
  EXPECT_EQ(ctl.jerk().norm(), 0.0);
}

// ----------------------------------------------------------------------------------------------- Riccati, gains

double dare_residual(const PreviewController<double>& ctl) {
  const auto& P = ctl.riccati();
  const auto& A = ctl.augmented_A();
  const auto& B = ctl.augmented_B();
  const double m = ctl.parameters().r_input + B.dot(P * B);
  const Eigen::RowVector4d bpa = B.transpose() * P * A;
  const Eigen::Matrix4d rhs = A.transpose() * P * A - bpa.transpose() * bpa / m + ctl.augmented_Q();
  return (P - rhs).norm() / P.norm();
}

double spectral_radius(const Eigen::Matrix4d& M) { return M.eigenvalues().cwiseAbs().maxCoeff(); }

TEST(WalkingPreview, RiccatiSolvesTheDareAndTheLoopIsStable) {
  for (const double dt : {0.002, 0.005, 0.001}) {
    for (const double zc : {0.30, 0.814}) {  // the HOAP-3 and Kajita 2003's HRP-2 CoM height
      PreviewParameters<double> p = hoap3_preview();
      p.dt = dt;
      p.com_height = zc;
      PreviewController<double> ctl(p);
      const double res = dare_residual(ctl);
      const double rho = spectral_radius(ctl.closed_loop());
      std::printf("[walking] DARE dt = %.3f s, z_c = %.3f m: %d iterations, relative residual %.2e, spectral "
                  "radius of A_c %.6f, G_i = %.6g, G_x = [%.6g %.6g %.6g], N_L = %d\n",
                  dt, zc, ctl.riccati_iterations(), res, rho, ctl.integral_gain(), ctl.state_gain()(0),
                  ctl.state_gain()(1), ctl.state_gain()(2), ctl.horizon());
      EXPECT_LT(res, 1e-14);  // doubling + Newton refinement: ~1e-16 here
      EXPECT_LT(rho, 1.0);
      // P symmetric positive semi-definite
      EXPECT_LT((ctl.riccati() - ctl.riccati().transpose()).norm(), 1e-14 * ctl.riccati().norm());
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(ctl.riccati());
      EXPECT_GT(es.eigenvalues().minCoeff(), -1e-12 * ctl.riccati().norm());
      // G_p(1) = −G_i, preview gains decaying to nothing over the horizon
      EXPECT_NEAR(ctl.preview_gains()(0), -ctl.integral_gain(), 1e-12 * std::abs(ctl.integral_gain()));
      EXPECT_EQ(ctl.horizon(), static_cast<int>(std::lround(1.6 / dt)));
      const auto& gp = ctl.preview_gains();
      EXPECT_LT(std::abs(gp(gp.size() - 1)), 1e-2 * gp.cwiseAbs().maxCoeff());
    }
  }
}

TEST(WalkingPreview, RiccatiForOtherWeights) {
  for (const double r : {1e-9, 1e-3, 1.0}) {
    for (const double qx : {0.0, 1e-2}) {
      PreviewParameters<double> p = hoap3_preview();
      p.r_input = r;
      p.q_state = qx;
      PreviewController<double> ctl(p);
      EXPECT_LT(dare_residual(ctl), 1e-13) << "R = " << r << ", q_x = " << qx;
      EXPECT_LT(spectral_radius(ctl.closed_loop()), 1.0);
    }
  }
}

TEST(WalkingPreview, ClosedLoopMatrixMatchesItsDefinition) {
  PreviewController<double> ctl(hoap3_preview());
  Eigen::RowVector4d K;
  K << ctl.integral_gain(), ctl.state_gain();
  EXPECT_LT((ctl.closed_loop() - (ctl.augmented_A() - ctl.augmented_B() * K)).norm(), 1e-12);
  // the augmented matrices from the cart-table model
  const double dt = 0.002, zg = 0.30 / 9.81;
  EXPECT_NEAR(ctl.augmented_A()(0, 1), 1.0, kEps);
  EXPECT_NEAR(ctl.augmented_A()(0, 2), dt, kEps);
  EXPECT_NEAR(ctl.augmented_A()(0, 3), dt * dt / 2 - zg, kEps);
  EXPECT_NEAR(ctl.augmented_B()(0), dt * dt * dt / 6 - zg * dt, kEps);
}

TEST(WalkingPreview, StepResponseAnticipatesAndSettles) {
  PreviewController<double> ctl(hoap3_preview());
  const int n = 3000;  // 6 s, step of 5 cm at t = 2 s on x, of −3 cm at t = 3 s on y
  Ref2 ref = Ref2::Zero(n, 2);
  for (int k = 1000; k < n; ++k) ref(k, 0) = 0.05;
  for (int k = 1500; k < n; ++k) ref(k, 1) = -0.03;
  const PreviewTrajectory<double> tr = run_preview(ctl, ref);
  // the CoM moves before the step (preview), the cart-table ZMP first moves the other way
  EXPECT_GT(tr.com(900, 0), 1e-3);
  EXPECT_LT(tr.zmp.col(0).head(1000).minCoeff(), -1e-3);
  EXPECT_LT(tr.com(1400, 1), -1e-3);
  // and it settles on the new reference, at rest
  EXPECT_NEAR(tr.com(n - 1, 0), 0.05, 1e-4);
  EXPECT_NEAR(tr.com(n - 1, 1), -0.03, 1e-4);
  EXPECT_NEAR(tr.zmp(n - 1, 0), 0.05, 1e-4);
  EXPECT_LT(tr.com_velocity.row(n - 1).norm(), 1e-3);
}

TEST(WalkingPreview, ShortWindowHoldsTheLastReference) {
  // run_preview's shrinking windows at the end of the plan = stepping on the reference padded with its last row
  PreviewController<double> ctl(hoap3_preview());
  const FootstepPlan<double> plan(hoap3_gait());
  const Ref2 ref = sample_zmp_reference(plan, 0.002);
  const PreviewTrajectory<double> tr = run_preview(ctl, ref);
  const Eigen::Index n = ref.rows(), nl = ctl.horizon();
  Ref2 padded(n + nl, 2);
  padded.topRows(n) = ref;
  for (Eigen::Index k = n; k < n + nl; ++k) padded.row(k) = ref.row(n - 1);
  PreviewController<double>::State x = PreviewController<double>::State::Zero();
  x.row(0) = ref.row(0);
  ctl.reset(x);
  double diff = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    diff = std::max(diff, (x.row(0) - tr.com.row(k)).norm());
    x = ctl.step(x, padded.middleRows(k, nl + 1));
  }
  EXPECT_EQ(diff, 0.0);
}

// ---------------------------------------------------------------------------------------- tracking on walks

struct Tracking {
  double max_error = 0;       // max |p − p_ref| (m)
  double min_margin = 1e9;    // min signed distance of the cart-table ZMP to the support polygon's boundary (m)
  double min_ref_margin = 1e9;
  double final_offset = 0;    // |final CoM − middle of the final feet| (m)
};

Tracking track(const GaitParameters<double>& g, const PreviewParameters<double>& pp, const char* name) {
  const FootstepPlan<double> plan(g);
  PreviewController<double> ctl(pp);
  const Ref2 ref = sample_zmp_reference(plan, pp.dt);
  const PreviewTrajectory<double> tr = run_preview(ctl, ref);
  Tracking r;
  for (Eigen::Index k = 0; k < ref.rows(); ++k) {
    const double t = pp.dt * static_cast<double>(k);
    r.max_error = std::max(r.max_error, (tr.zmp.row(k) - ref.row(k)).norm());
    r.min_margin = std::min(r.min_margin, plan.margin(t, tr.zmp.row(k).transpose()));
    r.min_ref_margin = std::min(r.min_ref_margin, plan.margin(t, ref.row(k).transpose()));
  }
  const auto& f = plan.final_feet();
  const V2 mid = 0.5 * (f[0].position + f[1].position).head<2>();
  r.final_offset = (tr.com.bottomRows(1).transpose() - mid).norm();
  std::printf("[walking] %s: %d steps, length %.3f m, width %.3f m, turn %.3f rad, period %.2f s, double support "
              "%.0f %%, z_c %.2f m, dt %.3f s: max |ZMP - ref| %.2f mm, min ZMP margin %.2f mm (reference %.2f mm), "
              "final CoM %.2f mm from the feet's middle\n",
              name, g.steps, g.step_length, g.step_width, g.turn, g.period, 100 * g.double_support_ratio,
              pp.com_height, pp.dt, 1e3 * r.max_error, 1e3 * r.min_margin, 1e3 * r.min_ref_margin,
              1e3 * r.final_offset);
  return r;
}

TEST(WalkingPreview, Hoap3StraightWalkTracksInsideTheSupportPolygon) {
  const Tracking r = track(hoap3_gait(), hoap3_preview(), "HOAP-3 straight");
  EXPECT_LT(r.max_error, 5e-3);
  EXPECT_GT(r.min_margin, 0.025);  // the sole is 73 mm wide: 36.5 mm around the stance foot centre
  EXPECT_LT(r.final_offset, 1e-3);
}

TEST(WalkingPreview, Hoap3TurningWalkTracksInsideTheSupportPolygon) {
  GaitParameters<double> g = hoap3_gait();
  g.turn = 0.15;  // turning left: the left foot leads
  g.first_swing = Foot::left;
  const Tracking r = track(g, hoap3_preview(), "HOAP-3 turning");
  EXPECT_LT(r.max_error, 5e-3);
  EXPECT_GT(r.min_margin, 0.025);
  EXPECT_LT(r.final_offset, 1e-3);
}

TEST(WalkingPreview, Hoap3PublicWalkAndAFastWalk) {
  // the public HOAP-3 walk of the data sheet: 87 mm steps, 1.28 s period, short double support
  GaitParameters<double> g = hoap3_gait();
  g.step_length = 0.087;
  g.period = 1.28;
  g.double_support_ratio = 0.05;
  g.swing_height = 0.021;
  const Tracking a = track(g, hoap3_preview(), "HOAP-3 public-walk numbers");
  EXPECT_LT(a.max_error, 1e-2);
  EXPECT_GT(a.min_margin, 0.015);
  // a stress case: shorter, faster steps
  g = hoap3_gait();
  g.step_length = 0.04;
  g.period = 0.6;
  g.double_support_ratio = 0.2;
  const Tracking b = track(g, hoap3_preview(), "HOAP-3 fast");
  EXPECT_LT(b.max_error, 1e-2);
  EXPECT_GT(b.min_margin, 0.015);
}

// ---------------------------------------------------------------------------------------------- footsteps

TEST(WalkingFootsteps, StraightPlanMatchesTheParameters) {
  const GaitParameters<double> g = hoap3_gait();
  const FootstepPlan<double> plan(g);
  const auto& init = plan.initial_feet();
  EXPECT_EQ(init[0].position, V3(0, 0.044, 0));
  EXPECT_EQ(init[1].position, V3(0, -0.044, 0));
  ASSERT_EQ(plan.footsteps().size(), 8u);
  Foot swing = Foot::right;
  for (int k = 1; k <= 8; ++k, swing = other(swing)) {
    const Footstep<double>& f = plan.footsteps()[static_cast<std::size_t>(k - 1)];
    EXPECT_EQ(f.foot, swing);
    const double x = 0.05 * std::min(k, 7);
    EXPECT_NEAR(f.position.x(), x, kEps) << "step " << k;
    EXPECT_NEAR(f.position.y(), swing == Foot::left ? 0.044 : -0.044, kEps);
    EXPECT_EQ(f.position.z(), 0.0);
    EXPECT_EQ(f.yaw, 0.0);
  }
  const auto& fin = plan.final_feet();
  EXPECT_NEAR(fin[0].position.x(), fin[1].position.x(), kEps);
  EXPECT_NEAR(fin[0].position.y() - fin[1].position.y(), 0.088, kEps);
  EXPECT_NEAR(fin[0].position.x(), 0.35, kEps);

  // the timeline: standing, (double, single) × 8, double, standing; contiguous; durations from the parameters
  const auto& ph = plan.phases();
  ASSERT_EQ(ph.size(), 2u + 2u * 8u + 1u);
  EXPECT_EQ(ph.front().kind, PhaseKind::standing);
  EXPECT_EQ(ph.back().kind, PhaseKind::standing);
  EXPECT_EQ(ph[ph.size() - 2].kind, PhaseKind::double_support);
  for (std::size_t i = 1; i < ph.size(); ++i) EXPECT_EQ(ph[i].start, ph[i - 1].end);
  for (int k = 1; k <= 8; ++k) {
    const Phase<double>& ds = ph[static_cast<std::size_t>(2 * k - 1)];
    const Phase<double>& ss = ph[static_cast<std::size_t>(2 * k)];
    EXPECT_EQ(ds.kind, PhaseKind::double_support);
    EXPECT_EQ(ss.kind, PhaseKind::single_support);
    EXPECT_EQ(ss.step, k);
    EXPECT_NEAR(ds.end - ds.start, 0.2, kEps);
    EXPECT_NEAR(ss.end - ss.start, 0.8, kEps);
    EXPECT_EQ(ss.swing, plan.footsteps()[static_cast<std::size_t>(k - 1)].foot);
    EXPECT_EQ(ss.stance, other(ss.swing));
  }
  EXPECT_NEAR(plan.duration(), 1.0 + 8 * 1.0 + 0.2 + 1.5, kEps);
}

TEST(WalkingFootsteps, TurningPlanTurnsByTheAngleEachStep) {
  GaitParameters<double> g = hoap3_gait();
  g.turn = 0.2;
  g.first_swing = Foot::left;
  const FootstepPlan<double> plan(g);
  // recover the path frames from the landings: C = foot − R(ψ) (0, ±w/2)
  auto path = [&](const Footstep<double>& f) {
    const double side = f.foot == Foot::left ? 0.044 : -0.044;
    return V2(f.position.x() + std::sin(f.yaw) * side, f.position.y() - std::cos(f.yaw) * side);
  };
  V2 prev(0, 0);
  double prev_yaw = 0;
  const auto& st = plan.footsteps();
  for (std::size_t k = 0; k + 1 < st.size(); ++k) {
    const V2 c = path(st[k]);
    EXPECT_NEAR((c - prev).norm(), 0.05, kEps) << "step " << k + 1;
    EXPECT_NEAR(st[k].yaw - prev_yaw, 0.2, kEps);
    // the path moves along the mean heading
    EXPECT_NEAR(std::atan2(c.y() - prev.y(), c.x() - prev.x()), prev_yaw + 0.1, 1e-12);
    prev = c;
    prev_yaw = st[k].yaw;
  }
  EXPECT_NEAR(st.back().yaw, 7 * 0.2, kEps);  // the closing step does not turn
  // final feet side by side: the right foot at (0, −w) in the left foot's frame, same yaw
  const auto& fin = plan.final_feet();
  const V2 d = (fin[1].position - fin[0].position).head<2>();
  const double c = std::cos(fin[0].yaw), s = std::sin(fin[0].yaw);
  EXPECT_NEAR(c * d.x() + s * d.y(), 0.0, kEps);
  EXPECT_NEAR(-s * d.x() + c * d.y(), -0.088, kEps);
  EXPECT_NEAR(fin[0].yaw, fin[1].yaw, kEps);
  // at every instant the right foot is to the right of the left foot
  for (double t = 0; t <= plan.duration(); t += 0.01) {
    const FootState<double> l = plan.foot(Foot::left, t), r = plan.foot(Foot::right, t);
    const V2 rl = (r.position - l.position).head<2>();
    EXPECT_LT(-std::sin(l.yaw) * rl.x() + std::cos(l.yaw) * rl.y(), -0.05) << "t = " << t;
  }
}

TEST(WalkingFootsteps, ZeroAndOneStep) {
  GaitParameters<double> g = hoap3_gait();
  g.steps = 0;
  const FootstepPlan<double> none(g);
  EXPECT_TRUE(none.footsteps().empty());
  EXPECT_NEAR(none.duration(), 2.5, kEps);
  EXPECT_EQ(none.zmp_reference(1.2), V2(0, 0));
  g.steps = 1;
  const FootstepPlan<double> one(g);
  ASSERT_EQ(one.footsteps().size(), 1u);
  EXPECT_EQ(one.footsteps()[0].position, one.initial_feet()[1].position);  // lifted and put back
  EXPECT_NEAR(one.foot(Foot::right, 1.2 + 0.4).position.z(), 0.02, kEps);
}

TEST(WalkingFootsteps, BadParametersAreRejectedByName) {
  const auto expect_throw = [](const std::function<void(GaitParameters<double>&)>& edit, const std::string& name) {
    GaitParameters<double> g;
    edit(g);
    try {
      const FootstepPlan<double> plan(g);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  expect_throw([](auto& g) { g.steps = -1; }, "steps");
  expect_throw([](auto& g) { g.period = -1; }, "period");
  expect_throw([](auto& g) { g.period = 0; }, "period");
  expect_throw([](auto& g) { g.double_support_ratio = 1; }, "double_support_ratio");
  expect_throw([](auto& g) { g.double_support_ratio = -0.1; }, "double_support_ratio");
  expect_throw([](auto& g) { g.step_width = 0; }, "step_width");
  expect_throw([](auto& g) { g.step_length = NAN; }, "step_length");
  expect_throw([](auto& g) { g.turn = 4; }, "turn");
  expect_throw([](auto& g) { g.swing_height = -0.01; }, "swing_height");
  expect_throw([](auto& g) { g.initial_double_support = -1; }, "initial_double_support");
  expect_throw([](auto& g) { g.final_double_support = INFINITY; }, "final_double_support");
  expect_throw([](auto& g) { g.left_sole.front = -0.01; }, "left_sole");
  expect_throw([](auto& g) { g.right_sole.left = g.right_sole.right = 0; }, "right_sole");

  const auto expect_throw_p = [](const std::function<void(PreviewParameters<double>&)>& edit, const std::string& name) {
    PreviewParameters<double> p;
    edit(p);
    try {
      const PreviewController<double> ctl(p);
      ADD_FAILURE() << name << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  expect_throw_p([](auto& p) { p.dt = 0; }, "dt");
  expect_throw_p([](auto& p) { p.com_height = -0.3; }, "com_height");
  expect_throw_p([](auto& p) { p.gravity = 0; }, "gravity");
  expect_throw_p([](auto& p) { p.q_error = 0; }, "q_error");
  expect_throw_p([](auto& p) { p.q_state = -1; }, "q_state");
  expect_throw_p([](auto& p) { p.r_input = 0; }, "r_input");
  expect_throw_p([](auto& p) { p.preview_time = 0; }, "preview_time");
}

// ------------------------------------------------------------------------------------------ swing trajectories

TEST(WalkingSwing, ZeroVelocityAndAccelerationAtLiftOffAndTouchdown) {
  GaitParameters<double> g = hoap3_gait();
  g.turn = 0.2;
  g.first_swing = Foot::left;
  g.ground_height = 0.013;
  const FootstepPlan<double> plan(g);
  int swings = 0;
  for (const Phase<double>& ph : plan.phases()) {
    if (ph.kind != PhaseKind::single_support) continue;
    ++swings;
    const Footstep<double>& from = ph.feet[static_cast<std::size_t>(index(ph.swing))];
    const FootState<double> a = plan.foot(ph.swing, ph.start + 1e-15);
    const FootState<double> b = plan.foot(ph.swing, ph.end - 1e-12);
    const FootState<double> mid = plan.foot(ph.swing, 0.5 * (ph.start + ph.end));
    // at the ends: on the footprints, at rest (to round-off: 1e-12 s from the end the terms are O(1e-12))
    EXPECT_LT((a.position - from.position).norm(), 1e-14);
    EXPECT_LT((b.position - ph.swing_to.position).norm(), 1e-12);
    EXPECT_NEAR(b.yaw, ph.swing_to.yaw, 1e-12);
    for (const FootState<double>* s : {&a, &b}) {
      EXPECT_LT(s->velocity.norm(), 1e-10);
      EXPECT_LT(s->acceleration.norm(), 1e-9);
      EXPECT_LT(std::abs(s->yaw_rate), 1e-10);
      EXPECT_LT(std::abs(s->yaw_acceleration), 1e-9);
    }
    // exactly zero at the phase's own start
    const FootState<double> s0 = plan.foot(ph.swing, ph.start);
    EXPECT_EQ(s0.velocity.norm() + s0.acceleration.norm() + std::abs(s0.yaw_rate) + std::abs(s0.yaw_acceleration), 0.0);
    EXPECT_EQ(s0.position, from.position);
    // the swing height at mid-swing, and never above it
    EXPECT_NEAR(mid.position.z(), 0.013 + 0.02, kEps);
    EXPECT_NEAR(mid.velocity.z(), 0.0, kEps);
    for (int i = 0; i <= 100; ++i)
      EXPECT_LE(plan.foot(ph.swing, ph.start + (ph.end - ph.start) * i / 100.0).position.z(), 0.033 + kEps);
    EXPECT_FALSE(mid.in_contact);
    // the stance foot does not move
    const FootState<double> s1 = plan.foot(ph.stance, ph.start + 0.1), s2 = plan.foot(ph.stance, ph.end - 0.1);
    EXPECT_EQ(s1.position, s2.position);
    EXPECT_EQ(s1.velocity.norm() + s1.acceleration.norm() + std::abs(s1.yaw_rate), 0.0);
    EXPECT_TRUE(s1.in_contact);
  }
  EXPECT_EQ(swings, 8);
}

TEST(WalkingSwing, DerivativesMatchFiniteDifferencesAndAreContinuous) {
  GaitParameters<double> g = hoap3_gait();
  g.turn = -0.25;
  const FootstepPlan<double> plan(g);
  const double h = 1e-6;
  double worst_v = 0, worst_a = 0, worst_jump = 0;
  for (Foot f : {Foot::left, Foot::right}) {
    for (double t = 0.0005; t < plan.duration(); t += 0.0137) {
      const FootState<double> m = plan.foot(f, t - h), c = plan.foot(f, t), p = plan.foot(f, t + h);
      const V3 v_fd = (p.position - m.position) / (2 * h);
      const V3 a_fd = (p.velocity - m.velocity) / (2 * h);
      worst_v = std::max({worst_v, (v_fd - c.velocity).norm(), std::abs((p.yaw - m.yaw) / (2 * h) - c.yaw_rate)});
      worst_a = std::max({worst_a, (a_fd - c.acceleration).norm(),
                          std::abs((p.yaw_rate - m.yaw_rate) / (2 * h) - c.yaw_acceleration)});
    }
    // continuity across every phase boundary (position, velocity, acceleration)
    for (const Phase<double>& ph : plan.phases()) {
      const FootState<double> l = plan.foot(f, ph.end - 1e-9), r = plan.foot(f, ph.end + 1e-9);
      worst_jump = std::max({worst_jump, (l.position - r.position).norm(), (l.velocity - r.velocity).norm(),
                             (l.acceleration - r.acceleration).norm(), std::abs(l.yaw - r.yaw)});
    }
  }
  std::printf("[walking] swing finite differences: velocity %.2e m/s, acceleration %.2e m/s^2; largest jump at a "
              "phase boundary %.2e\n",
              worst_v, worst_a, worst_jump);
  EXPECT_LT(worst_v, 1e-7);
  EXPECT_LT(worst_a, 1e-5);
  EXPECT_LT(worst_jump, 1e-6);
}

// ------------------------------------------------------------------------------------------------- reference ZMP

TEST(WalkingZmpReference, InTheStanceSoleDuringSingleSupport) {
  for (const double offset : {0.0, 0.01}) {
    GaitParameters<double> g = hoap3_gait();
    g.turn = 0.2;
    g.first_swing = Foot::left;
    g.zmp_forward_offset = offset;
    const FootstepPlan<double> plan(g);
    for (const Phase<double>& ph : plan.phases()) {
      const double mid_t = 0.5 * (ph.start + ph.end);
      const V2 z = plan.zmp_reference(mid_t);
      if (ph.kind == PhaseKind::single_support) {
        const Footstep<double>& st = ph.feet[static_cast<std::size_t>(index(ph.stance))];
        const V2 expect = st.position.head<2>() + offset * V2(std::cos(st.yaw), std::sin(st.yaw));
        EXPECT_LT((z - expect).norm(), kEps);
        // inside the stance sole alone: 36.5 mm to its side edges, 54 − offset mm to its toe
        EXPECT_NEAR(plan.margin(mid_t, z), std::min(0.0365, 0.054 - offset), 1e-12);
        EXPECT_EQ(plan.zmp_reference(ph.start + 1e-9), plan.zmp_reference(ph.end - 1e-9));
      } else if (ph.kind == PhaseKind::double_support) {
        EXPECT_LT((z - 0.5 * (ph.zmp_start + ph.zmp_end)).norm(), kEps);  // linear: halfway at half time
        EXPECT_LT((plan.zmp_reference(ph.start) - ph.zmp_start).norm(), kEps);
        EXPECT_LT((plan.zmp_reference(ph.end - 1e-12) - ph.zmp_end).norm(), 1e-12);
        EXPECT_GT(plan.margin(mid_t, z), 0.03);
      } else {
        const V2 mid = 0.5 * (ph.feet[0].position + ph.feet[1].position).head<2>();
        EXPECT_LT((z - mid).norm(), kEps);
      }
    }
  }
}

TEST(WalkingZmpReference, SmoothTransferHasZeroRateAtItsEnds) {
  GaitParameters<double> g = hoap3_gait();
  g.smooth_zmp_transfer = true;
  const FootstepPlan<double> plan(g);
  const Phase<double>& ds = plan.phases()[3];
  ASSERT_EQ(ds.kind, PhaseKind::double_support);
  const double h = 1e-5;
  const V2 rate0 = (plan.zmp_reference(ds.start + h) - plan.zmp_reference(ds.start)) / h;
  const V2 rate1 = (plan.zmp_reference(ds.end - 1e-9) - plan.zmp_reference(ds.end - 1e-9 - h)) / h;
  const double tm = 0.5 * (ds.start + ds.end);
  const V2 rate_mid = (plan.zmp_reference(tm + h) - plan.zmp_reference(tm)) / h;
  EXPECT_LT(rate0.norm(), 1e-6);
  EXPECT_LT(rate1.norm(), 1e-6);
  EXPECT_NEAR(rate_mid.norm(), 1.875 * (ds.zmp_end - ds.zmp_start).norm() / (ds.end - ds.start), 1e-5);
  EXPECT_LT((plan.zmp_reference(0.5 * (ds.start + ds.end)) - 0.5 * (ds.zmp_start + ds.zmp_end)).norm(), kEps);
}

// ------------------------------------------------------------------------------------- hull and support polygon

TEST(WalkingPolygon, HullOfASquareWithInteriorCollinearAndRepeatedPoints) {
  std::array<V2, 8> pts{V2(1, 1), V2(0, 0), V2(0.5, 0.5), V2(1, 0), V2(0, 1), V2(0.5, 0), V2(1, 1), V2(0.2, 0.7)};
  const ConvexPolygon<double, 8> h = convex_hull<double, 8>(pts, 8);
  ASSERT_EQ(h.size, 4);
  EXPECT_EQ(h.vertices[0], V2(0, 0));  // counter-clockwise from the lowest x, then y
  EXPECT_EQ(h.vertices[1], V2(1, 0));
  EXPECT_EQ(h.vertices[2], V2(1, 1));
  EXPECT_EQ(h.vertices[3], V2(0, 1));
  EXPECT_NEAR(signed_distance(h, V2(0.5, 0.5)), 0.5, kEps);
  EXPECT_NEAR(signed_distance(h, V2(0.9, 0.3)), 0.1, kEps);
  EXPECT_NEAR(signed_distance(h, V2(1.0, 0.3)), 0.0, kEps);
  EXPECT_NEAR(signed_distance(h, V2(1.5, 0.3)), -0.5, kEps);
  EXPECT_NEAR(signed_distance(h, V2(2, 2)), -std::sqrt(2.0), kEps);
  EXPECT_NEAR(signed_distance(h, V2(-0.3, -0.4)), -0.5, kEps);
}

TEST(WalkingPolygon, DegenerateHulls) {
  std::array<V2, 8> pts{};
  pts[0] = V2(1, 2);
  EXPECT_EQ((convex_hull<double, 8>(pts, 0).size), 0);
  ConvexPolygon<double, 8> p = convex_hull<double, 8>(pts, 1);
  ASSERT_EQ(p.size, 1);
  EXPECT_NEAR(signed_distance(p, V2(4, 6)), -5.0, kEps);
  pts = {V2(0, 0), V2(2, 0), V2(1, 0), V2(2, 0)};
  p = convex_hull<double, 8>(pts, 4);
  ASSERT_EQ(p.size, 2);
  EXPECT_NEAR(signed_distance(p, V2(1, 0.5)), -0.5, kEps);
  EXPECT_NEAR(signed_distance(p, V2(3, 0)), -1.0, kEps);
  EXPECT_TRUE(std::isinf(signed_distance(ConvexPolygon<double, 8>{}, V2(0, 0))));
}

TEST(WalkingPolygon, TwoFeetAndOneFoot) {
  const FootstepPlan<double> plan(hoap3_gait());
  // standing: two 108 × 73 mm soles 88 mm apart form one rectangle 108 × 161 mm (8 corners, 4 on the hull)
  const SupportPolygon<double> both = plan.support_polygon(0.5);
  EXPECT_EQ(both.corner_count, 8);
  ASSERT_EQ(both.hull.size, 4);
  EXPECT_NEAR(plan.margin(0.5, V2(0, 0)), 0.054, kEps);
  EXPECT_NEAR(plan.margin(0.5, V2(0.0, 0.07)), 0.044 + 0.0365 - 0.07, kEps);
  EXPECT_NEAR(plan.margin(0.5, V2(0.0, 0.1)), -(0.1 - 0.0805), kEps);
  EXPECT_NEAR(plan.margin(0.5, V2(0.06, 0.0)), -0.006, kEps);
  // first single support (right foot swings): only the left sole
  const Phase<double>& ss = plan.phases()[2];
  ASSERT_EQ(ss.kind, PhaseKind::single_support);
  const double t = 0.5 * (ss.start + ss.end);
  const SupportPolygon<double> one = plan.support_polygon(t);
  EXPECT_EQ(one.corner_count, 4);
  EXPECT_EQ(one.hull.size, 4);
  EXPECT_NEAR(plan.margin(t, V2(0, 0.044)), 0.0365, kEps);
  EXPECT_LT(plan.margin(t, V2(0, 0)), 0.0);  // the middle of the feet is outside one foot
  // a later double support, feet staggered: the hull is a hexagon
  const Phase<double>& ds = plan.phases()[5];
  ASSERT_EQ(ds.kind, PhaseKind::double_support);
  EXPECT_EQ(plan.support_polygon(0.5 * (ds.start + ds.end)).hull.size, 6);
  // a rotated sole: a point on the foot's axis at 50 mm ahead is 4 mm from the toe
  GaitParameters<double> g = hoap3_gait();
  g.turn = 0.5;
  g.first_swing = Foot::left;
  const FootstepPlan<double> turning(g);
  const Phase<double>& ss2 = turning.phases()[4];  // step 2: the right foot swings, the left (yaw 0.5) stands
  ASSERT_EQ(ss2.kind, PhaseKind::single_support);
  const Footstep<double>& st = ss2.feet[static_cast<std::size_t>(index(ss2.stance))];
  EXPECT_NEAR(st.yaw, 0.5, kEps);
  const V2 p = st.position.head<2>() + 0.05 * V2(std::cos(0.5), std::sin(0.5));
  EXPECT_NEAR(turning.margin(0.5 * (ss2.start + ss2.end), p), 0.004, kEps);
}

TEST(WalkingPolygon, FloatScalarInstantiates) {
  GaitParameters<float> g;
  const FootstepPlan<float> plan(g);
  EXPECT_NEAR(plan.margin(0.5f, Eigen::Vector2f(0, 0)), 0.054f, 1e-6f);
  EXPECT_EQ(plan.footsteps().size(), 8u);
}

}  // namespace

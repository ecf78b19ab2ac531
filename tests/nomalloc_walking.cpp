// The walking generator's per-tick call (walking/preview.hpp: PreviewController::step), the plan's queries
// (walking/footsteps.hpp: foot, zmp_reference, margin), the simulator's step (walking/simulation.hpp: with and
// without contacts, with an impact) and the whole-body tick (walking/whole_body.hpp: IK, differential IK, contact
// inverse dynamics, multibody ZMP) never allocate once built. Guarded by Eigen's run-time check
// and by the counting global operator new of nomalloc_algorithms.cpp (same executable).

#include <spatial/spatial.hpp>
#include <spatial/walking.hpp>
#include <spatial/models/hoap3_floating.hpp>

#include "support/no_allocation.hpp"

#include <gtest/gtest.h>

namespace {

using namespace spatial::walking;
using spatial::testing::NoAllocationRegion;

volatile double g_sink = 0.0;

TEST(NoMallocWalking, PreviewStepAndPlanQueries) {
  GaitParameters<double> g;
  g.steps = 4;
  const FootstepPlan<double> plan(g);
  PreviewController<double> pc{PreviewParameters<double>{}};
  const Eigen::Matrix<double, Eigen::Dynamic, 2> ref = sample_zmp_reference(plan, 0.002);
  PreviewController<double>::State x = PreviewController<double>::State::Zero();
  const int n = static_cast<int>(ref.rows()), window = pc.horizon() + 1;
  NoAllocationRegion guard;
  for (int k = 0; k + window <= n; k += 7) {
    x = pc.step(x, ref.middleRows(k, window));
    const double t = 0.002 * k;
    g_sink = g_sink + x.sum() + plan.foot(Foot::left, t).position.sum() + plan.zmp_reference(t).sum() +
             plan.margin(t, plan.zmp_reference(t));
  }
  EXPECT_EQ(guard.new_calls(), 0);
}

TEST(NoMallocWalking, SimulatorSteps) {
  const auto model = spatial::models::hoap3_floating::floating_model<double>().to_runtime();
  std::vector<spatial::RigidContact<double>> feet{spatial::contact_6d(model.frame_index("L_SOLE")),
                                                  spatial::contact_6d(model.frame_index("R_SOLE"))};
  ContactSimulator<spatial::FloatingModel<double>> sim(model, feet);
  const Eigen::VectorXd q = spatial::neutral(model), zero = Eigen::VectorXd::Zero(model.nv());
  sim.reset(q, zero, 1u);
  NoAllocationRegion guard;
  sim.step(zero, 1u);
  sim.step(zero, 3u);  // the right foot joins: an impact
  sim.step(zero, 2u);
  sim.step(zero, 0u);  // flying
  sim.reset(q, zero, 3u);
  g_sink = g_sink + sim.q().sum() + sim.v().sum();
  EXPECT_EQ(guard.new_calls(), 0);
}

TEST(NoMallocWalking, WholeBodyTicks) {
  namespace fb = spatial::models::hoap3_floating;
  const auto model = fb::floating_model<double>().to_runtime();
  auto options = hoap3_whole_body_options<double>(fb::joint_names);
  options.preview.dt = 0.005;
  GaitParameters<double> g;
  g.steps = 1;
  const FootstepPlan<double> plan(g);
  PreviewController<double> ctl(options.preview);
  const auto zref = sample_zmp_reference(plan, options.preview.dt);
  const PreviewTrajectory<double> pt = run_preview(ctl, zref);
  WholeBodyGenerator<spatial::FloatingModel<double>> gen(
      model, {fb::frame_index("L_SOLE"), fb::frame_index("R_SOLE"), fb::frame_index("base_link")},
      spatial::ik_limits(fb::lower), spatial::ik_limits(fb::upper), options);
  gen.start(plan, zref.row(0).transpose());
  Eigen::Matrix<double, 3, 2> c;
  NoAllocationRegion guard;
  for (int k = 0; k < static_cast<int>(pt.com.rows()); k += 10) {  // standing, double and single support
    c << pt.com.row(k), pt.com_velocity.row(k), pt.com_acceleration.row(k);
    g_sink = g_sink + gen.tick(plan, k * options.preview.dt, c).tau.sum();
  }
  EXPECT_EQ(guard.new_calls(), 0);
}

}  // namespace

// The walking generator's per-tick call (walking/preview.hpp: PreviewController::step) and the plan's queries
// (walking/footsteps.hpp: foot, zmp_reference, margin) never allocate once built. Guarded by Eigen's run-time check
// and by the counting global operator new of nomalloc_algorithms.cpp (same executable).

#include <spatial/walking.hpp>

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

}  // namespace

// The per-tick work of the open-loop whole-body walking pipeline (include/spatial/walking/whole_body.hpp) on the
// compile-time floating HOAP-3 (floating27), to be read as a fraction of the 2 ms control period:
//
//   spatial/WalkTick/floating27/double/static   one 2 ms tick: the first-stage preview step (N_L = 800 preview gains,
//                                               both axes), then WholeBodyGenerator::tick — the position IK warm-started
//                                               from the previous tick, v and v̇ by differential IK, the contact
//                                               inverse dynamics (the stance sole or both soles) and the multibody ZMP
//                                               and CoP.
//
// The ticks walk through the plan in order (the warm start needs consecutive ticks: a random state would time a cold
// IK solve instead); at the end of the plan the generator and the controller are reset outside the timed region. The
// plan is docs/walking.md's 8-step HOAP-3 walk (50 mm, 1.0 s, r = 0.2) with the data sheet's options.

#include "bench_common.hpp"
#include "bench_floating.hpp"

#include <spatial/walking/whole_body.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>

namespace {

using namespace spatial;
using namespace spatial::bench;
namespace fb = models::hoap3_floating;

template <class TreeT>
struct WalkFixture {
  using FM = FloatingModel<double, TreeT>;
  const FM& model;
  walking::FootstepPlan<double> plan;
  walking::WholeBodyOptions<double> options;
  walking::PreviewController<double> ctl;
  walking::WholeBodyGenerator<FM> gen;
  Eigen::Matrix<double, Eigen::Dynamic, 2> ref;
  walking::PreviewController<double>::State x;
  Eigen::Index k = 0;
  double ik_iterations = 0.0;
  long ticks = 0;

  explicit WalkFixture(const FM& m)
      : model(m), plan(walking::GaitParameters<double>{}), options(walking::hoap3_whole_body_options<double>(fb::joint_names)),
        ctl(options.preview),
        gen(model, {fb::frame_index("L_SOLE"), fb::frame_index("R_SOLE"), fb::frame_index("base_link")},
            ik_limits(fb::lower), ik_limits(fb::upper), options),
        ref(walking::sample_zmp_reference(plan, options.preview.dt)) {
    restart();
  }

  void restart() {
    x.setZero();
    x.row(0) = ref.row(0);
    ctl.reset(x);
    gen.start(plan, ref.row(0).transpose());
    k = 0;
  }

  /// One tick: the first-stage preview step, then the whole-body tick at the new CoM state.
  void tick() {
    const Eigen::Index window = std::min<Eigen::Index>(ctl.horizon() + 1, ref.rows() - k);
    x = ctl.step(x, ref.middleRows(k, window));
    ++k;
    const auto& st = gen.tick(plan, static_cast<double>(k) * options.preview.dt, x);
    benchmark::DoNotOptimize(st.tau.data());
    ik_iterations += st.ik.iterations;
    ++ticks;
  }
};

template <class TreeT>
void register_walk(const std::string& tree, const FloatingModel<double, TreeT>& model) {
  using Fx = WalkFixture<TreeT>;
  auto fx = std::make_shared<Fx>(model);
  benchmark::RegisterBenchmark(bench_name("spatial", "WalkTick", "floating27", "double", tree).c_str(),
                               [fx](benchmark::State& st) {
                                 Fx& f = *fx;
                                 f.ik_iterations = 0.0;
                                 f.ticks = 0;
                                 for (auto _ : st) {
                                   if (f.k + 1 >= f.ref.rows()) {
                                     st.PauseTiming();
                                     f.restart();
                                     st.ResumeTiming();
                                   }
                                   f.tick();
                                 }
                                 st.counters["ik_iterations_per_tick"] = f.ticks ? f.ik_iterations / double(f.ticks) : 0.0;
                                 st.counters["period_fraction"] = benchmark::Counter(
                                     double(st.iterations()) * 0.002,
                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
                               });
}

const bool registered = [] {
  add_build_context();
  register_walk("static", floating27());
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

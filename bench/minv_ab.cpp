// Wall-clock of inverse_inertia (stance21 compile-time and run-time tree, hoap3_floating) for an old/new comparison
// of minv.hpp (docs/performance.md, 2026-12-03): build it twice, once against the previous headers and once against
// the current ones, and run the two binaries in alternating rounds. Standalone, not in the build:
//   git worktree add /tmp/old <commit>
//   for v in old new; do I=$([ $v = old ] && echo /tmp/old/include || echo include)
//     g++ -std=c++17 -O3 -march=native -DNDEBUG -I$I -Ibuild/src/models/include -isystem /usr/include/eigen3 \
//       bench/minv_ab.cpp -o /tmp/bm_$v -lbenchmark -pthread; done
//   for r in 1 2 3; do for v in old new; do /tmp/bm_$v --benchmark_repetitions=5 \
//     --benchmark_report_aggregates_only=true | grep median; done; done
#include <benchmark/benchmark.h>
#include <spatial/spatial.hpp>
#include <spatial/minv.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_floating.hpp>
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;
static void ct(benchmark::State& st) {
  auto m = M::model(); Data<double, M::Tree> d(m); MinvData<double, M::Tree> md(m);
  Eigen::Matrix<double, 21, 1> q = Eigen::Matrix<double, 21, 1>::Random();
  for (auto _ : st) { q[0] += 1e-9; benchmark::DoNotOptimize(inverse_inertia(m, d, md, q).data()); }
}
static void rt(benchmark::State& st) {
  auto m = M::model().to_runtime(); Data<double> d(m); MinvData<double> md(m);
  Eigen::VectorXd q = Eigen::VectorXd::Random(21);
  for (auto _ : st) { q[0] += 1e-9; benchmark::DoNotOptimize(inverse_inertia(m, d, md, q).data()); }
}
static void fl(benchmark::State& st) {
  auto m = F::floating_model(); FloatingData<double, F::Tree> d(m); FloatingMinvData<double, F::Tree> md(m);
  Eigen::Matrix<double, 28, 1> q = Eigen::Matrix<double, 28, 1>::Random(); q.segment<4>(3).normalize();
  for (auto _ : st) { q[7] += 1e-9; benchmark::DoNotOptimize(inverse_inertia(m, d, md, q).data()); }
}
BENCHMARK(ct); BENCHMARK(rt); BENCHMARK(fl);
BENCHMARK_MAIN();

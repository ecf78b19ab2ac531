// Wall-clock of rnea_derivatives and aba_derivatives (stance21 compile-time tree, hoap3_floating) for an old/new
// comparison of derivatives.hpp (docs/performance.md, 2026-12-04): build it twice, once against the previous headers
// and once against the current ones, and run the two binaries in alternating rounds. Standalone, not in the build:
//   git worktree add /tmp/old <commit>
//   for c in g++ clang++; do for v in old new; do I=$([ $v = old ] && echo /tmp/old/include || echo include)
//     $c -std=c++17 -O3 -march=native -DNDEBUG -I$I -Ibuild/src/models/include -isystem /usr/include/eigen3 \
//       bench/derivatives_ab.cpp -o /tmp/da_${c}_$v -lbenchmark -pthread; done; done
//   for r in 1 2 3; do for c in g++ clang++; do for v in old new; do /tmp/da_${c}_$v --benchmark_repetitions=5 \
//     --benchmark_report_aggregates_only=true | grep median | sed "s/^/$c $v /"; done; done; done
#include <benchmark/benchmark.h>
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;
using V21 = Eigen::Matrix<double, 21, 1>;
using V27 = Eigen::Matrix<double, 27, 1>;
static void rnea_d_stance21(benchmark::State& st) {
  auto m = M::model(); Data<double, M::Tree> d(m); DerivativeData<double, M::Tree> dd(m);
  V21 q = V21::Random(), v = V21::Random(), a = V21::Random();
  for (auto _ : st) { q[0] += 1e-9; rnea_derivatives(m, d, dd, q, v, a); benchmark::DoNotOptimize(dd.dtau_dq.data()); }
}
static void aba_d_stance21(benchmark::State& st) {
  auto m = M::model(); Data<double, M::Tree> d(m); DerivativeData<double, M::Tree> dd(m);
  V21 q = V21::Random(), v = V21::Random(), t = V21::Random();
  for (auto _ : st) { q[0] += 1e-9; aba_derivatives(m, d, dd, q, v, t); benchmark::DoNotOptimize(dd.dqdd_dq.data()); }
}
static void rnea_d_floating27(benchmark::State& st) {
  auto m = F::floating_model(); FloatingData<double, F::Tree> d(m); FloatingDerivativeData<double, F::Tree> dd(m);
  Eigen::Matrix<double, 28, 1> q = Eigen::Matrix<double, 28, 1>::Random(); q.segment<4>(3).normalize();
  V27 v = V27::Random(), a = V27::Random();
  for (auto _ : st) { q[10] += 1e-9; rnea_derivatives(m, d, dd, q, v, a); benchmark::DoNotOptimize(dd.dtau_dq.data()); }
}
static void aba_d_floating27(benchmark::State& st) {
  auto m = F::floating_model(); FloatingData<double, F::Tree> d(m); FloatingDerivativeData<double, F::Tree> dd(m);
  Eigen::Matrix<double, 28, 1> q = Eigen::Matrix<double, 28, 1>::Random(); q.segment<4>(3).normalize();
  V27 v = V27::Random(), t = V27::Random();
  for (auto _ : st) { q[10] += 1e-9; aba_derivatives(m, d, dd, q, v, t); benchmark::DoNotOptimize(dd.dqdd_dq.data()); }
}
BENCHMARK(rnea_d_stance21);
BENCHMARK(aba_d_stance21);
BENCHMARK(rnea_d_floating27);
BENCHMARK(aba_d_floating27);
BENCHMARK_MAIN();

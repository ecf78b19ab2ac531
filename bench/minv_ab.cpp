// inverse_inertia (stance21 compile-time and run-time tree, hoap3_floating), old against new headers in one process
// for scripts/ab.sh (docs/performance.md used it from 2026-12-03, then as two binaries run in turn):
//   bash scripts/ab.sh [--cxx clang++] <old revision> bench/minv_ab.cpp
// Standalone, not in the CMake build.
#include <benchmark/benchmark.h>
#include "ab.hpp"
#include <spatial/spatial.hpp>
#include <spatial/minv.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_floating.hpp>

namespace {
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;
void ct(benchmark::State& st) {
  auto m = M::model(); Data<double, M::Tree> d(m); MinvData<double, M::Tree> md(m);
  Eigen::Matrix<double, 21, 1> q = Eigen::Matrix<double, 21, 1>::Random();
  for (auto _ : st) { q[0] += 1e-9; benchmark::DoNotOptimize(inverse_inertia(m, d, md, q).data()); }
}
void rt(benchmark::State& st) {
  auto m = M::model().to_runtime(); Data<double> d(m); MinvData<double> md(m);
  Eigen::VectorXd q = Eigen::VectorXd::Random(21);
  for (auto _ : st) { q[0] += 1e-9; benchmark::DoNotOptimize(inverse_inertia(m, d, md, q).data()); }
}
void fl(benchmark::State& st) {
  auto m = F::floating_model(); FloatingData<double, F::Tree> d(m); FloatingMinvData<double, F::Tree> md(m);
  Eigen::Matrix<double, 28, 1> q = Eigen::Matrix<double, 28, 1>::Random(); q.segment<4>(3).normalize();
  for (auto _ : st) { q[7] += 1e-9; benchmark::DoNotOptimize(inverse_inertia(m, d, md, q).data()); }
}
}  // namespace

BENCHMARK(ct)->Name(AB_TAG "Minv/stance21/static");
BENCHMARK(rt)->Name(AB_TAG "Minv/stance21/runtime");
BENCHMARK(fl)->Name(AB_TAG "Minv/floating27/static");

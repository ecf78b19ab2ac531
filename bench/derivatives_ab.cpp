// rnea_derivatives and aba_derivatives (stance21 compile-time tree, hoap3_floating), old against new headers in one
// process for scripts/ab.sh (docs/performance.md used it from 2026-12-04, then as two binaries run in turn):
//   bash scripts/ab.sh [--cxx clang++] <old revision> bench/derivatives_ab.cpp
// Standalone, not in the CMake build.
#include <benchmark/benchmark.h>
#include "ab.hpp"
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

namespace {
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;
using V21 = Eigen::Matrix<double, 21, 1>;
using V27 = Eigen::Matrix<double, 27, 1>;
void rnea_d_stance21(benchmark::State& st) {
  auto m = M::model(); Data<double, M::Tree> d(m); DerivativeData<double, M::Tree> dd(m);
  V21 q = V21::Random(), v = V21::Random(), a = V21::Random();
  for (auto _ : st) { q[0] += 1e-9; rnea_derivatives(m, d, dd, q, v, a); benchmark::DoNotOptimize(dd.dtau_dq.data()); }
}
void aba_d_stance21(benchmark::State& st) {
  auto m = M::model(); Data<double, M::Tree> d(m); DerivativeData<double, M::Tree> dd(m);
  V21 q = V21::Random(), v = V21::Random(), t = V21::Random();
  for (auto _ : st) { q[0] += 1e-9; aba_derivatives(m, d, dd, q, v, t); benchmark::DoNotOptimize(dd.dqdd_dq.data()); }
}
void rnea_d_floating27(benchmark::State& st) {
  auto m = F::floating_model(); FloatingData<double, F::Tree> d(m); FloatingDerivativeData<double, F::Tree> dd(m);
  Eigen::Matrix<double, 28, 1> q = Eigen::Matrix<double, 28, 1>::Random(); q.segment<4>(3).normalize();
  V27 v = V27::Random(), a = V27::Random();
  for (auto _ : st) { q[10] += 1e-9; rnea_derivatives(m, d, dd, q, v, a); benchmark::DoNotOptimize(dd.dtau_dq.data()); }
}
void aba_d_floating27(benchmark::State& st) {
  auto m = F::floating_model(); FloatingData<double, F::Tree> d(m); FloatingDerivativeData<double, F::Tree> dd(m);
  Eigen::Matrix<double, 28, 1> q = Eigen::Matrix<double, 28, 1>::Random(); q.segment<4>(3).normalize();
  V27 v = V27::Random(), t = V27::Random();
  for (auto _ : st) { q[10] += 1e-9; aba_derivatives(m, d, dd, q, v, t); benchmark::DoNotOptimize(dd.dqdd_dq.data()); }
}
}  // namespace

BENCHMARK(rnea_d_stance21)->Name(AB_TAG "RNEA_derivatives/stance21/static");
BENCHMARK(aba_d_stance21)->Name(AB_TAG "ABA_derivatives/stance21/static");
BENCHMARK(rnea_d_floating27)->Name(AB_TAG "RNEA_derivatives/floating27/static");
BENCHMARK(aba_d_floating27)->Name(AB_TAG "ABA_derivatives/floating27/static");

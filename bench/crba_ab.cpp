// CRBA on stance21 (compile-time and run-time tree) and on floating27 (the floating CRBA and the centroidal momentum
// matrix, which share crba_impl's passes), for scripts/ab.sh: old against new headers in one process, interleaved.
//   bash scripts/ab.sh HEAD bench/crba_ab.cpp                 # g++
//   bash scripts/ab.sh --cxx clang++ HEAD bench/crba_ab.cpp
// Standalone (not in the CMake build). Each benchmark cycles through 64 random states.
#include <benchmark/benchmark.h>
#include "ab.hpp"
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <random>
#include <vector>

namespace {
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;

template <class Q>
std::vector<Q> random_states(int n) {
  std::vector<Q> pool(static_cast<std::size_t>(n));
  for (auto& q : pool) q = Q::Random(21);
  return pool;
}

void crba_stance21_ct(benchmark::State& st) {
  const auto m = M::model();
  Data<double, M::Tree> d(m);
  const auto pool = random_states<Eigen::Matrix<double, 21, 1>>(64);
  std::size_t k = 0;
  for (auto _ : st) benchmark::DoNotOptimize(crba(m, d, pool[k++ & 63]).data());
}
void crba_stance21_rt(benchmark::State& st) {
  const auto m = M::model().to_runtime();
  Data<double> d(m);
  const auto pool = random_states<Eigen::VectorXd>(64);
  std::size_t k = 0;
  for (auto _ : st) benchmark::DoNotOptimize(crba(m, d, pool[k++ & 63]).data());
}
std::vector<Eigen::Matrix<double, 28, 1>> floating_states(const FloatingModel<double, F::Tree>& m) {
  std::mt19937 rng(7);
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(21, -1), hi = Eigen::VectorXd::Constant(21, 1);
  std::vector<Eigen::Matrix<double, 28, 1>> pool;
  for (int k = 0; k < 64; ++k) pool.push_back(random_configuration(m, lo, hi, rng));
  return pool;
}
void crba_floating27(benchmark::State& st) {
  const auto m = F::floating_model<double>();
  FloatingData<double, F::Tree> d(m);
  const auto pool = floating_states(m);
  std::size_t k = 0;
  for (auto _ : st) benchmark::DoNotOptimize(crba(m, d, pool[k++ & 63]).data());
}
void centroidal_floating27(benchmark::State& st) {
  const auto m = F::floating_model<double>();
  FloatingData<double, F::Tree> d(m);
  const auto pool = floating_states(m);
  Eigen::MatrixXd Ag(6, m.nv());
  std::size_t k = 0;
  for (auto _ : st) {
    centroidal_momentum_matrix(m, d, pool[k++ & 63], Ag);
    benchmark::DoNotOptimize(Ag.data());
    benchmark::ClobberMemory();
  }
}
}  // namespace

BENCHMARK(crba_stance21_ct)->Name(AB_TAG "CRBA/stance21/static");
BENCHMARK(crba_stance21_rt)->Name(AB_TAG "CRBA/stance21/runtime");
BENCHMARK(crba_floating27)->Name(AB_TAG "CRBA/floating27/static");
BENCHMARK(centroidal_floating27)->Name(AB_TAG "CentroidalMatrix/floating27/static");

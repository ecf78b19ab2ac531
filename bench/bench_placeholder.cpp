// Temporary: only here to validate the build infrastructure. Deleted when the library lands.
#include <spatial/spatial.hpp>

#include <benchmark/benchmark.h>

static void BM_Placeholder_Matrix3dTimesVector3d(benchmark::State& state) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Random();
  Eigen::Vector3d v = Eigen::Vector3d::Random();
  for (auto _ : state) {
    benchmark::DoNotOptimize(m);
    benchmark::DoNotOptimize(v);
    Eigen::Vector3d r = m * v;
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_Placeholder_Matrix3dTimesVector3d);
BENCHMARK_MAIN();

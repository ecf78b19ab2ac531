// Run time of every algorithm on every bench model (bench_models.hpp): RNEA, gravity torques, bias forces, CRBA,
// forward dynamics by CRBA + tree LTDL and by CRBA + dense Cholesky, ABA and forward kinematics; compile-time trees
// in double and float, run-time trees in double. Each iteration takes the next state from a pre-generated pool
// (random within the model's input range), so nothing is cached between calls.
#include "bench_common.hpp"

namespace {
using namespace spatial;
using namespace spatial::bench;

const bool registered = [] {
  add_build_context();
  for_each_bench_model([](const auto& entry) {
    register_algorithms<double>(entry.name, "static", entry.model, entry.range);
    register_algorithms<float>(entry.name, "static", entry.model.template cast<float>(), entry.range);
    register_algorithms<double>(entry.name, "runtime", to_runtime(entry.model), entry.range);
  });
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

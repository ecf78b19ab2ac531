// Run time of every algorithm on every bench model (bench_models.hpp): RNEA, gravity torques, bias forces, CRBA,
// forward dynamics by CRBA + tree LTDL and by CRBA + dense Cholesky, ABA and forward kinematics, and in double the
// derivatives of RNEA and ABA (bench_derivatives.hpp); compile-time trees
// in double and float, run-time trees in double. Each iteration takes the next state from a pre-generated pool
// (random within the model's input range), so nothing is cached between calls.
#include "bench_common.hpp"
#include "bench_derivatives.hpp"

namespace {
using namespace spatial;
using namespace spatial::bench;

const bool registered = [] {
  add_build_context();
  for_each_bench_model([](const auto& entry) {
    register_algorithms<double>(entry.name, "static", entry.model, entry.range);
    register_algorithms<float>(entry.name, "static", entry.model.template cast<float>(), entry.range);
    register_algorithms<double>(entry.name, "runtime", entry.model.to_runtime(), entry.range);
    const auto derivatives = [&](const std::string& tree, const auto& model) {
      using M = std::decay_t<decltype(model)>;
      using T = typename M::tree_type;
      const auto pool = InputPool<double>(entry.range).template cast<double, M::NB>();
      register_derivatives<M, Data<double, T>, DerivativeData<double, T>>(model, pool, [&](const char* algorithm) {
        return bench_name("spatial", algorithm, entry.name, "double", tree);
      });
    };
    derivatives("static", entry.model);
    derivatives("runtime", entry.model.to_runtime());
  });
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

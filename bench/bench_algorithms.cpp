// Run time of every algorithm on every bench model (bench_models.hpp): RNEA, gravity torques, bias forces, CRBA,
// forward dynamics by CRBA + tree LTDL and by CRBA + dense Cholesky, ABA and forward kinematics, and in double the
// derivatives of RNEA and ABA and H⁻¹ (bench_derivatives.hpp; on stance21 also in float and by central differences);
// compile-time trees
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
    // On the target model (stance21) also float and central differences: the derivatives' points of the
    // run-time-against-error chart (the error study measures their accuracy).
    const bool variants = entry.name == "stance21";
    const auto derivatives = [&](const std::string& tree, const auto& model) {
      using M = std::decay_t<decltype(model)>;
      using S = typename M::Scalar;
      using T = typename M::tree_type;
      const auto pool = InputPool<double>(entry.range).template cast<S, M::NB>();
      register_derivatives<M, Data<S, T>, DerivativeData<S, T>>(
          model, pool, [&](const char* algorithm) { return bench_name("spatial", algorithm, entry.name,
                                                                      scalar_name<S>(), tree); },
          variants && tree == "static");
    };
    derivatives("static", entry.model);
    derivatives("runtime", entry.model.to_runtime());
    if (variants) derivatives("static", entry.model.template cast<float>());
  });
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

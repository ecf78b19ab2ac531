// Run time of every algorithm on every bench model (bench_models.hpp): RNEA, gravity torques, bias forces, CRBA,
// forward dynamics by CRBA + tree LTDL and by CRBA + dense Cholesky, ABA and forward kinematics, and in double the
// derivatives of RNEA and ABA and H⁻¹ (bench_derivatives.hpp; on stance21 also in float and by central differences);
// compile-time trees
// in double and float, run-time trees in double. Each iteration takes the next state from a pre-generated pool
// (random within the model's input range), so nothing is cached between calls.
#include "bench_common.hpp"
#include "bench_derivatives.hpp"
#include "support/autodiff.hpp"

namespace {
using namespace spatial;
using namespace spatial::bench;

/// RNEA_derivatives_ad: ∂τ/∂q and ∂τ/∂q̇ by forward-mode automatic differentiation (tests/support/autodiff.hpp's
/// dual number, one derivative per pass: 2n RNEA passes in duals), on the run-time twin in duals built once.
void register_ad(const std::string& model_name, const Model<double>& model, const InputPool<double>& pool) {
  using spatial::testing::Dual;
  using VD = Eigen::Matrix<Dual, Eigen::Dynamic, 1>;
  struct Fx {
    Model<Dual> m;
    Data<Dual> data;
    InputPool<double> pool;
    Eigen::MatrixXd dq, dv;
    VD q, v, a;
    Fx(const Model<double>& model, const InputPool<double>& p)
        : m(model.cast<Dual>()), data(m), pool(p), dq(model.size(), model.size()), dv(dq), q(model.size()),
          v(model.size()), a(model.size()) {}
  };
  auto fx = std::make_shared<Fx>(model, pool);
  register_one(bench_name("spatial", "RNEA_derivatives_ad", model_name, "double", "runtime"), fx, [](Fx& f, int k) {
    const auto s = static_cast<std::size_t>(k);
    const int n = f.m.size();
    for (int i = 0; i < n; ++i) {
      f.q[i] = Dual(f.pool.q[s][i]);
      f.v[i] = Dual(f.pool.qd[s][i]);
      f.a[i] = Dual(f.pool.u[s][i]);
    }
    for (int c = 0; c < n; ++c) {
      f.q[c].der = 1.0;
      const auto& t1 = rnea(f.m, f.data, f.q, f.v, f.a);
      for (int i = 0; i < n; ++i) f.dq(i, c) = t1[i].der;
      f.q[c].der = 0.0;
      f.v[c].der = 1.0;
      const auto& t2 = rnea(f.m, f.data, f.q, f.v, f.a);
      for (int i = 0; i < n; ++i) f.dv(i, c) = t2[i].der;
      f.v[c].der = 0.0;
    }
    benchmark::DoNotOptimize(f.dq.data());
    benchmark::ClobberMemory();
  });
}

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
    if (variants) {
      derivatives("static", entry.model.template cast<float>());
      register_ad(entry.name, entry.model.to_runtime(), InputPool<double>(entry.range));
    }
  });
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

// Run time of the floating-base algorithms on floating27 (the HOAP-3 free-flying at the pelvis, nv = 27;
// bench_floating.hpp): RNEA, CRBA, ABA and forward dynamics by CRBA + LTDL, compile-time and run-time trees, double.
// Names "spatial/<algorithm>/floating27/double/<static|runtime>"; bench_pinocchio times Pinocchio's free-flyer
// model of the same robot on the same states.
#include "bench_common.hpp"
#include "bench_floating.hpp"

namespace {
using namespace spatial;
using namespace spatial::bench;

template <class S, class TreeT>
struct FloatingFixture {
  FloatingModel<S, TreeT> model;
  FloatingData<S, TreeT> data;
  FloatingPool<S, FloatingModel<S, TreeT>::NQ, FloatingModel<S, TreeT>::NV> pool;
  explicit FloatingFixture(const FloatingModel<S, TreeT>& m)
      : model(m), data(model),
        pool(floating_pool().template cast<S, FloatingModel<S, TreeT>::NQ, FloatingModel<S, TreeT>::NV>()) {}
};

template <class S, class TreeT>
void register_floating(const std::string& tree, const FloatingModel<S, TreeT>& model) {
  using Fx = FloatingFixture<S, TreeT>;
  auto fx = std::make_shared<Fx>(model);
  const auto name = [&](const char* algorithm) {
    return bench_name("spatial", algorithm, "floating27", scalar_name<S>(), tree);
  };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  register_one(name("RNEA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(rnea(f.model, f.data, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("CRBA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(crba(f.model, f.data, at(f.pool.q, k)).data());
  });
  register_one(name("ABA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(aba(f.model, f.data, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
  register_one(name("FD_CRBA_LTDL"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(
        forward_dynamics_crba(f.model, f.data, at(f.pool.q, k), at(f.pool.v, k), at(f.pool.u, k)).data());
  });
}

const bool registered = [] {
  add_build_context();
  register_floating<double>("static", floating27());
  register_floating<double>("runtime", floating_to_runtime(floating27()));
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

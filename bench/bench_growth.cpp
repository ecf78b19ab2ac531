// Cost growth: RNEA, CRBA, ABA and the tree factorisation (LTDL: `ltdl` + `ltdl_solve`) on chains and balanced
// binary trees of 2, 4, …, 256 bodies (revolute joints cycling about x, y, z; random geometry and inertias), in
// double. Every size runs as a run-time tree; sizes up to SPATIAL_GROWTH_MAX_STATIC (CMake option, default 16)
// also as compile-time trees generated from index sequences. Fully unrolled trees cost a lot to compile: with
// GCC 12 at -O3, this file takes ~32 s of CPU with the compile-time trees of 2…16 bodies, ~137 s with the 32-body
// ones too (measured 2026-12-02), and 64 bodies several minutes and 4 GB, too much for the report's time budget. tools/report.py fits time ∝ n^k on a
// log–log scale for each algorithm, shape and tree kind.
//
// Names: "spatial/<algorithm>/<chain|binary><n>/double/<static|runtime>".
#include "bench_common.hpp"

#ifndef SPATIAL_GROWTH_MAX_STATIC
#define SPATIAL_GROWTH_MAX_STATIC 16
#endif

namespace {
using namespace spatial;
using namespace spatial::bench;

template <class TreeT>
void register_growth(const std::string& model_name, const Model<double, TreeT>& model) {
  using Fx = Fixture<double, TreeT>;
  const std::string tree = Model<double, TreeT>::is_static ? "static" : "runtime";
  auto fx = std::make_shared<Fx>(model, unit_range(model.size()));
  const auto name = [&](const char* algorithm) { return bench_name("spatial", algorithm, model_name, "double", tree); };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  register_one(name("RNEA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(rnea(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)).data());
  });
  register_one(name("CRBA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(crba(f.model, f.data, at(f.pool.q, k)).data());
  });
  register_one(name("ABA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(aba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)).data());
  });
  // The factorisation and solve of H x = b. H is computed once (by CRBA at the first pool state); every call
  // factorises it from scratch (ltdl reads only data.H) and solves for a fresh right-hand side.
  crba(fx->model, fx->data, fx->pool.q[0]);
  register_one(name("LTDL"), fx, [at](Fx& f, int k) {
    f.x = at(f.pool.u, k);
    ltdl(f.model, f.data);
    ltdl_solve(f.model, f.data, f.x);
    benchmark::DoNotOptimize(f.x.data());
  });
}

template <int N>
void register_size() {
  constexpr unsigned seed = 4000u + unsigned(N);
  if constexpr (N <= SPATIAL_GROWTH_MAX_STATIC) {
    register_growth("chain" + std::to_string(N), random_model<ChainTree<N>>(seed));
    register_growth("binary" + std::to_string(N), random_model<BinaryTree<N>>(seed + 1));
  }
  register_growth("chain" + std::to_string(N), random_runtime_model<ChainTree<N>>(seed));
  register_growth("binary" + std::to_string(N), random_runtime_model<BinaryTree<N>>(seed + 1));
}

template <int... N>
void register_sizes(std::integer_sequence<int, N...>) {
  (register_size<N>(), ...);
}

const bool registered = [] {
  add_build_context();
  benchmark::AddCustomContext("spatial_growth_max_static", std::to_string(SPATIAL_GROWTH_MAX_STATIC));
  register_sizes(std::integer_sequence<int, 2, 4, 8, 16, 32, 64, 128, 256>{});
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

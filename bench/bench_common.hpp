#pragma once
/// \file bench_common.hpp
/// Registration of spatial's own benchmarks: one fixture (model, data, input pool) per model, scalar and tree kind,
/// and one benchmark per algorithm, named "spatial/<algorithm>/<model>/<scalar>/<tree>" (see bench_name).

#include "bench_models.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace spatial::bench {

/// Compiler and flags, recorded in every benchmark JSON's context for the report.
inline void add_build_context() {
#if defined(__clang__)
  benchmark::AddCustomContext("spatial_compiler", std::string("clang ") + __clang_version__);
#elif defined(__GNUC__)
  benchmark::AddCustomContext("spatial_compiler", std::string("gcc ") + __VERSION__);
#endif
#ifdef SPATIAL_BENCH_FLAGS
  benchmark::AddCustomContext("spatial_flags", SPATIAL_BENCH_FLAGS);
#endif
  benchmark::AddCustomContext("spatial_eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                                   std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                                   std::to_string(EIGEN_MINOR_VERSION));
}

template <class S, class TreeT>
struct Fixture {
  using VectorN = typename Data<S, TreeT>::VectorN;
  Model<S, TreeT> model;
  Data<S, TreeT> data;
  InputPool<S, Model<S, TreeT>::NB> pool;
  VectorN x;  ///< scratch right-hand side
  Eigen::LLT<typename Data<S, TreeT>::MatrixN> llt;  ///< dense Cholesky, allocated once

  Fixture(const Model<S, TreeT>& m, const InputRange& range)
      : model(m), data(model), pool(InputPool<double>(range).template cast<S, Model<S, TreeT>::NB>()),
        x(VectorN::Zero(m.size())), llt(m.size()) {}
};

/// Registers one benchmark whose loop body is `body(fixture, k)` with k the index of a fresh pool state.
template <class Fx, class Body>
void register_one(const std::string& name, const std::shared_ptr<Fx>& fx, Body body) {
  benchmark::RegisterBenchmark(name.c_str(), [fx, body](benchmark::State& st) {
    Fx& f = *fx;
    for (auto _ : st) body(f, f.pool.take());
  });
}

/// Registers every algorithm on one model, scalar and tree kind.
template <class S, class TreeT>
void register_algorithms(const std::string& model_name, const std::string& tree, const Model<S, TreeT>& model,
                         const InputRange& range) {
  using Fx = Fixture<S, TreeT>;
  auto fx = std::make_shared<Fx>(model, range);
  const auto name = [&](const char* algorithm) {
    return bench_name("spatial", algorithm, model_name, scalar_name<S>(), tree);
  };
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  register_one(name("RNEA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(rnea(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)).data());
  });
  register_one(name("GravityTorques"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(gravity_torques(f.model, f.data, at(f.pool.q, k)).data());
  });
  register_one(name("BiasForces"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(bias_forces(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k)).data());
  });
  register_one(name("CRBA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(crba(f.model, f.data, at(f.pool.q, k)).data());
  });
  register_one(name("FD_CRBA_LTDL"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(
        forward_dynamics_crba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)).data());
  });
  register_one(name("FD_CRBA_DenseLLT"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(
        forward_dynamics_dense(f.model, f.data, f.llt, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)).data());
  });
  register_one(name("ABA"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(aba(f.model, f.data, at(f.pool.q, k), at(f.pool.qd, k), at(f.pool.u, k)).data());
  });
  // The tree factorisation alone (ltdl + ltdl_solve) on the H in data (computed here by CRBA at the first pool
  // state; the other benchmarks of this fixture overwrite it with H at other states, always a valid H): every call
  // factorises it from scratch (ltdl reads only data.H) and solves for a fresh right-hand side.
  crba(fx->model, fx->data, fx->pool.q[0]);
  register_one(name("LTDL"), fx, [at](Fx& f, int k) {
    f.x = at(f.pool.u, k);
    ltdl(f.model, f.data);
    ltdl_solve(f.model, f.data, f.x);
    benchmark::DoNotOptimize(f.x.data());
  });
  register_one(name("FK"), fx, [at](Fx& f, int k) {
    forward_kinematics(f.model, f.data, at(f.pool.q, k));
    benchmark::DoNotOptimize(f.data.X_base[static_cast<std::size_t>(f.model.size() - 1)].r.data());
    benchmark::ClobberMemory();
  });
}

}  // namespace spatial::bench

#pragma once
/// \file pinocchio_bench.hpp
/// What the three translation units of bench_pinocchio share: Pinocchio's side of the fixtures (the peer model, its
/// data and the bench states in Pinocchio's joint order) and the registration of a timed call.
///   bench_pinocchio.cpp              the fixed-base algorithms on every bench model, and main
///   bench_pinocchio_derivatives.cpp  the derivatives of RNEA and ABA and H⁻¹, on every bench model and floating27
///   bench_pinocchio_floating.cpp     floating27: dynamics, Jacobians, centre of mass, centroidal, contacts
///   bench_pinocchio_batch.cpp        Pinocchio's batch API (rneaInParallel's OpenMP loop) on stance21 and torso8,
///                                    beside bench_batch (issue 15); only where CMake found OpenMP
///                                    (SPATIAL_PINOCCHIO_BATCH)
/// In one file they took ~10 CPU minutes with GCC 12 at -O3 (most of it instantiating templates, ours and
/// Pinocchio's) and ended every build alone on one core; in three, they build side by side. Each part checks its
/// results against spatial's before any timing and aborts on a mismatch (peers/peer_check.hpp).
/// In bench_pinocchio.cpp and bench_pinocchio_derivatives.cpp, spatial's side of those checks runs on the run-time
/// twin of each model (`to_runtime()`: the same joints, transforms, inertias and states over a run-time tree), not on
/// the compile-time trees that bench_algorithms times: their unrolled instantiation of every checked algorithm for
/// three models cost 13 % and a third of those parts' compile time (GCC 12, 2026-12-02: 144 → 125 and 252 → 166
/// CPU-s), and the tests hold the two trees to the same results (test_static_trees; test_floating's
/// CompileTimeTreeMatchesRunTimeTree; test_derivatives' RuntimeTwin…; test_contact's …CompileTimeAndRunTimeTrees;
/// simd_kinematics). bench_pinocchio_floating.cpp checks the compile-time floating27 it times: there the twin saved
/// nothing measurable (248 → 245 CPU-s; Pinocchio's contact and frame-derivative code dominates).
///
/// Pinocchio is used header-only (PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION is not defined, nothing is linked from
/// libpinocchio), compiled with the same compiler and flags as spatial's benchmarks, and against the Eigen that
/// Pinocchio's wheel was built with (cmeel-eigen): this binary never sees Debian's Eigen.
#include "bench_floating.hpp"
#include "bench_models.hpp"
#include "peers/peer_check.hpp"
#include "peers/pinocchio_peer.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace spatial::bench {

/// A Pinocchio model of a bench model, its data, and the bench states (bench_models.hpp's InputPool) converted to
/// Pinocchio's joint order; `take()` cycles through them as bench_algorithms does.
template <class S>
struct PinFixture {
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  peers::PinocchioPeer<S> peer;
  pinocchio::DataTpl<S> data;
  std::vector<Vector> q, v, u;  // in Pinocchio's joint order
  Vector x;
  int next = 0;
  explicit PinFixture(peers::PinocchioPeer<S> p) : peer(std::move(p)), data(peer.model) {}
  const pinocchio::ModelTpl<S>& model() const { return peer.model; }
  int take() {
    next = next + 1 == static_cast<int>(q.size()) ? 0 : next + 1;
    return next;
  }
};

template <class S, class TreeT>
std::shared_ptr<PinFixture<S>> make_pin_fixture(const BenchModel<TreeT>& entry, const InputPool<double>& pool) {
  auto fx = std::make_shared<PinFixture<S>>(peers::make_pinocchio_peer(entry.model.template cast<S>()));
  for (int k = 0; k < pool.size(); ++k) {
    const auto s = static_cast<std::size_t>(k);
    fx->q.push_back(fx->peer.to_pinocchio(pool.q[s]));
    fx->v.push_back(fx->peer.to_pinocchio(pool.qd[s]));
    fx->u.push_back(fx->peer.to_pinocchio(pool.u[s]));
  }
  fx->x = PinFixture<S>::Vector::Zero(entry.model.size());
  return fx;
}

/// Pinocchio's free-flyer model of floating27 (bench_floating.hpp) and bench_floating's states in Pinocchio's order.
struct FloatingPinStates {
  peers::FloatingPinocchioPeer<double> peer;
  pinocchio::DataTpl<double> data;
  std::vector<Eigen::VectorXd> q, v, u;  // in Pinocchio's order
  int next = 0;
  const pinocchio::Model& model() const { return peer.tree.model; }
  explicit FloatingPinStates(peers::FloatingPinocchioPeer<double> p) : peer(std::move(p)), data(peer.tree.model) {
    const auto& pool = floating_pool();
    for (int k = 0; k < pool.size(); ++k) {
      const auto s = static_cast<std::size_t>(k);
      q.push_back(peer.to_pinocchio(pool.q[s], 7));
      v.push_back(peer.to_pinocchio(pool.v[s], 6));
      u.push_back(peer.to_pinocchio(pool.u[s], 6));
    }
  }
  int take() {
    next = next + 1 == static_cast<int>(q.size()) ? 0 : next + 1;
    return next;
  }
};

/// Registers "pinocchio/<algorithm>/<model>/<scalar>/-", timing body(fixture, next state index).
template <class Fx, class Body>
void register_pinocchio_call(const std::shared_ptr<Fx>& fx, const std::string& model, const char* scalar,
                             const char* algorithm, Body body) {
  const std::string name = bench_name("pinocchio", algorithm, model, scalar, "-");
  benchmark::RegisterBenchmark(name.c_str(), [fx, body](benchmark::State& st) {
    Fx& f = *fx;
    for (auto _ : st) body(f, static_cast<std::size_t>(f.take()));
  });
}

/// bench_pinocchio.cpp's instantiations of Pinocchio's single-state rnea, aba and crba (on VectorXd, as its
/// benchmarks call them), for bench_pinocchio_batch.cpp's loops: one instantiation of each in the binary.
const Eigen::VectorXd& pinocchio_rnea(const pinocchio::Model& m, pinocchio::Data& d, const Eigen::VectorXd& q,
                                      const Eigen::VectorXd& v, const Eigen::VectorXd& a);
const Eigen::VectorXd& pinocchio_aba(const pinocchio::Model& m, pinocchio::Data& d, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& v, const Eigen::VectorXd& tau);
const Eigen::MatrixXd& pinocchio_crba(const pinocchio::Model& m, pinocchio::Data& d, const Eigen::VectorXd& q);

/// bench_pinocchio_batch.cpp: registers Pinocchio's batched RNEA, ABA and CRBA on `m` over the states q, v, u
/// (Pinocchio's joint order, one column per state, ≥ 10000 columns) after checking them against the single-state calls.
void register_pinocchio_batch(const std::string& model, const pinocchio::Model& m, Eigen::MatrixXd q,
                              Eigen::MatrixXd v, Eigen::MatrixXd u);

}  // namespace spatial::bench

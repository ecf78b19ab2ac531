// Orocos KDL 1.5 on every bench model, from the same model (peers/kdl_peer.hpp) and the same input pool as
// bench_algorithms: TreeIdSolver_RNE (inverse dynamics, every model) and, where the model is a chain,
// ChainDynParam::JntToMass (joint-space inertia) and ChainFdSolver_RNE (forward dynamics: inertia matrix, bias
// forces by RNEA and a dense LDLᵀ solve). Before any timing, KDL's results are compared with spatial's on the first
// 32 pool states (τ and H: ≤ 1e-12 relative, q̈: ≤ 1e-10) and the program aborts on a mismatch.
//
// This binary is built WITHOUT -march=native: Debian's liborocos-kdl is compiled for generic x86-64 and passes
// Eigen objects (JntArray, JntSpaceInertiaMatrix) across its API; both sides must agree on Eigen's alignment and
// allocation. KDL's own code is the same either way. spatial's code here only serves the check.
#include "bench_models.hpp"
#include "peers/kdl_peer.hpp"
#include "peers/peer_check.hpp"

#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

namespace {
using namespace spatial;
using namespace spatial::bench;
using namespace spatial::peers;

struct KdlFixture {
  std::unique_ptr<KdlPeer> peer;
  std::vector<KDL::JntArray> q, qd, u;
  KDL::JntArray out;
  KDL::JntSpaceInertiaMatrix H;
  KDL::WrenchMap no_wrench_map;
  KDL::Wrenches no_wrenches;
  int next = 0;
  int take() {
    next = next + 1 == static_cast<int>(q.size()) ? 0 : next + 1;
    return next;
  }
};

template <class TreeT>
void register_kdl(const BenchModel<TreeT>& entry) {
  const Model<double, TreeT>& model = entry.model;
  const int n = model.size();
  auto fx = std::make_shared<KdlFixture>();
  fx->peer = make_kdl_peer(model);
  const InputPool<double> pool(entry.range);
  for (int k = 0; k < pool.size(); ++k) {
    fx->q.push_back(to_jnt_array(pool.q[static_cast<std::size_t>(k)]));
    fx->qd.push_back(to_jnt_array(pool.qd[static_cast<std::size_t>(k)]));
    fx->u.push_back(to_jnt_array(pool.u[static_cast<std::size_t>(k)]));
  }
  fx->out = KDL::JntArray(static_cast<unsigned>(n));
  fx->H = KDL::JntSpaceInertiaMatrix(static_cast<unsigned>(n));
  fx->no_wrenches.assign(static_cast<std::size_t>(n), KDL::Wrench::Zero());

  // The check, before any timing.
  Data<double, TreeT> data(model);
  PeerCheck tau_check{"KDL TreeIdSolver_RNE tau on " + entry.name, 1e-12};
  PeerCheck mass_check{"KDL ChainDynParam::JntToMass H on " + entry.name, 1e-12};
  PeerCheck fd_check{"KDL ChainFdSolver_RNE qdd on " + entry.name, 1e-10};
  for (int k = 0; k < 32 && k < pool.size(); ++k) {
    const auto s = static_cast<std::size_t>(k);
    if (fx->peer->tree_id->CartToJnt(fx->q[s], fx->qd[s], fx->u[s], fx->no_wrench_map, fx->out) < 0) {
      std::fprintf(stderr, "KDL TreeIdSolver_RNE failed on %s\n", entry.name.c_str());
      std::abort();
    }
    tau_check.compare(fx->out.data, rnea(model, data, pool.q[s], pool.qd[s], pool.u[s]));
    if (fx->peer->has_chain) {
      fx->peer->chain_dyn->JntToMass(fx->q[s], fx->H);
      mass_check.compare(fx->H.data, crba(model, data, pool.q[s]));
      if (fx->peer->chain_fd->CartToJnt(fx->q[s], fx->qd[s], fx->u[s], fx->no_wrenches, fx->out) < 0) {
        std::fprintf(stderr, "KDL ChainFdSolver_RNE failed on %s\n", entry.name.c_str());
        std::abort();
      }
      fd_check.compare(fx->out.data, aba(model, data, pool.q[s], pool.qd[s], pool.u[s]));
    }
  }
  tau_check.report();
  if (fx->peer->has_chain) {
    mass_check.report();
    fd_check.report();
  }

  const auto name = [&](const char* algorithm) { return bench_name("kdl", algorithm, entry.name, "double", "-"); };
  benchmark::RegisterBenchmark(name("RNEA").c_str(), [fx](benchmark::State& st) {
    KdlFixture& f = *fx;
    for (auto _ : st) {
      const auto k = static_cast<std::size_t>(f.take());
      f.peer->tree_id->CartToJnt(f.q[k], f.qd[k], f.u[k], f.no_wrench_map, f.out);
      benchmark::DoNotOptimize(f.out.data.data());
    }
  });
  if (fx->peer->has_chain) {
    benchmark::RegisterBenchmark(name("CRBA").c_str(), [fx](benchmark::State& st) {
      KdlFixture& f = *fx;
      for (auto _ : st) {
        const auto k = static_cast<std::size_t>(f.take());
        f.peer->chain_dyn->JntToMass(f.q[k], f.H);
        benchmark::DoNotOptimize(f.H.data.data());
      }
    });
    benchmark::RegisterBenchmark(name("FD_CRBA_LTDL").c_str(), [fx](benchmark::State& st) {
      KdlFixture& f = *fx;
      for (auto _ : st) {
        const auto k = static_cast<std::size_t>(f.take());
        f.peer->chain_fd->CartToJnt(f.q[k], f.qd[k], f.u[k], f.no_wrenches, f.out);
        benchmark::DoNotOptimize(f.out.data.data());
      }
    });
  }
}

const bool registered = [] {
  benchmark::AddCustomContext("kdl_version", KDL_VERSION_STRING);
#ifdef SPATIAL_BENCH_FLAGS
  benchmark::AddCustomContext("spatial_flags", SPATIAL_BENCH_FLAGS);
#endif
  for_each_bench_model([](const auto& entry) { register_kdl(entry); });
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

// Part of bench_pinocchio (pinocchio_bench.hpp): Pinocchio's batch API beside bench_batch (issue 15), on the states
// and models bench_pinocchio.cpp passes (stance21 and torso8, double), B = 1024 and 10000 states per call, on 1 thread
// and on all hardware threads. Compiled with OpenMP only (CMake: OpenMP found; GCC's libgomp here; clang needs
// libomp-dev), and then bench_pinocchio.cpp calls register_pinocchio_batch.
//
// Pinocchio 4.1's batch API (pinocchio/algorithm/parallel/: rneaInParallel, abaInParallel; no crba) is an OpenMP
// `parallel for schedule(static)` over the columns, thread t calling the single-state rnea / aba with the t-th model
// and data of a ModelPool on the column blocks. Instantiating it costs ~120 CPU-s of GCC 12 at -O3 (rnea, aba and
// ModelPool's geometry headers on column-block arguments, measured 2026-12), more than this whole binary's other
// batch parts, so by default this file runs that same loop over the single-state calls that bench_pinocchio.cpp
// instantiates already (pinocchio_rnea, pinocchio_aba, pinocchio_crba: one copy of the state's columns into the
// thread's vectors per call, ~60 doubles against a call of 0.3–1 µs). With -DSPATIAL_PINOCCHIO_PARALLEL_API=ON
// (CMake option) it calls rneaInParallel and abaInParallel themselves. CRBA, which Pinocchio has no batch call for,
// is that loop either way (H's upper triangle, as Pinocchio computes it, copied out per state).
// Names: "pinocchio/<algorithm>_batch/<model>/double/-/batch:<B>/threads:<T>"; wall time per call (UseRealTime),
// process CPU time (MeasureProcessCPUTime: OpenMP's workers spin a while after each loop, which shows there).
//
// Before any timing, the batched results are compared with the single-state calls on the first 256 states (the same
// code on the same numbers: they must be identical; bench_pinocchio.cpp checks the single-state calls against
// spatial's) and the program aborts on a mismatch.
#include "pinocchio_bench.hpp"

#ifdef SPATIAL_PINOCCHIO_PARALLEL_API
#include <pinocchio/algorithm/parallel/aba.hpp>
#include <pinocchio/algorithm/parallel/rnea.hpp>
#endif

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace spatial::bench {
namespace {

constexpr int kSizes[] = {1024, 10000};
constexpr int kChecked = 256;

/// One model and data per thread (Pinocchio's ModelPool, without its geometry), and each thread's state vectors.
struct Pool {
  std::vector<pinocchio::Model> models;
  std::vector<pinocchio::Data> datas;
  std::vector<Eigen::VectorXd> q, v, u;
#ifdef SPATIAL_PINOCCHIO_PARALLEL_API
  pinocchio::ModelPool pin;
#endif
  Pool(const pinocchio::Model& m, int threads)
      : models(static_cast<std::size_t>(threads), m), datas(static_cast<std::size_t>(threads), pinocchio::Data(m)),
        q(static_cast<std::size_t>(threads), Eigen::VectorXd(m.nq)), v(q), u(q)
#ifdef SPATIAL_PINOCCHIO_PARALLEL_API
        , pin(m, static_cast<std::size_t>(threads))
#endif
  {
  }
};

struct States {
  Eigen::MatrixXd q, v, u;
};

enum class Call { RNEA, ABA, CRBA };

/// rneaInParallel's loop (or the call itself) over the first B states; `out` is nv × B (RNEA, ABA) or nv × nv·B.
void run(Call call, int threads, Pool& p, const States& x, int B, Eigen::MatrixXd& out) {
#ifdef SPATIAL_PINOCCHIO_PARALLEL_API
  const auto t = static_cast<std::size_t>(threads);
  if (call == Call::RNEA) {
    pinocchio::rneaInParallel(t, p.pin, x.q.leftCols(B), x.v.leftCols(B), x.u.leftCols(B), out);
    return;
  }
  if (call == Call::ABA) {
    pinocchio::abaInParallel(t, p.pin, x.q.leftCols(B), x.v.leftCols(B), x.u.leftCols(B), out);
    return;
  }
#endif
  const Eigen::Index n = x.q.rows();
  omp_set_num_threads(threads);  // as Pinocchio's setDefaultOpenMPSettings
  omp_set_dynamic(0);
  int i = 0;
#pragma omp parallel for schedule(static)
  for (i = 0; i < B; ++i) {
    const auto t = static_cast<std::size_t>(omp_get_thread_num());
    const pinocchio::Model& m = p.models[t];
    pinocchio::Data& d = p.datas[t];
    p.q[t] = x.q.col(i);
    switch (call) {
      case Call::RNEA:
        p.v[t] = x.v.col(i);
        p.u[t] = x.u.col(i);
        out.col(i) = pinocchio_rnea(m, d, p.q[t], p.v[t], p.u[t]);
        break;
      case Call::ABA:
        p.v[t] = x.v.col(i);
        p.u[t] = x.u.col(i);
        out.col(i) = pinocchio_aba(m, d, p.q[t], p.v[t], p.u[t]);
        break;
      case Call::CRBA:
        out.middleCols(i * n, n) = pinocchio_crba(m, d, p.q[t]);
        break;
    }
  }
}

}  // namespace

void register_pinocchio_batch(const std::string& model, const pinocchio::Model& m, Eigen::MatrixXd q,
                              Eigen::MatrixXd v, Eigen::MatrixXd u) {
  const auto x = std::make_shared<const States>(States{std::move(q), std::move(v), std::move(u)});
  const Eigen::Index n = m.nv;
  const int all = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const std::vector<int> thread_counts = all > 1 ? std::vector<int>{1, all} : std::vector<int>{1};
  const char* const api =
#ifdef SPATIAL_PINOCCHIO_PARALLEL_API
      "rneaInParallel, abaInParallel";
#else
      "OpenMP loop over rnea, aba (as rneaInParallel)";
#endif
  static const bool context_added = (benchmark::AddCustomContext("pinocchio_batch_api", api), true);
  (void)context_added;
  peers::PeerCheck c_tau{"Pinocchio batch rnea on " + model, 0.0}, c_qdd{"Pinocchio batch aba on " + model, 0.0},
      c_H{"Pinocchio batch crba on " + model, 0.0};
  pinocchio::Data data(m);
  for (const int threads : thread_counts) {
    auto pool = std::make_shared<Pool>(m, threads);
    Eigen::MatrixXd T(n, kChecked), A(n, kChecked), H(n, n * kChecked);
    run(Call::RNEA, threads, *pool, *x, kChecked, T);
    run(Call::ABA, threads, *pool, *x, kChecked, A);
    run(Call::CRBA, threads, *pool, *x, kChecked, H);
    for (int k = 0; k < kChecked; ++k) {
      const Eigen::VectorXd qk = x->q.col(k), vk = x->v.col(k), uk = x->u.col(k);
      c_tau.compare(T.col(k), pinocchio_rnea(m, data, qk, vk, uk));
      c_qdd.compare(A.col(k), pinocchio_aba(m, data, qk, vk, uk));
      const Eigen::MatrixXd Hk = pinocchio_crba(m, data, qk);
      c_H.compare(H.middleCols(k * n, n).triangularView<Eigen::Upper>().toDenseMatrix(),
                  Hk.triangularView<Eigen::Upper>().toDenseMatrix());
    }
    for (const int B : kSizes) {
      for (const auto& [call, algorithm, cols] :
           {std::tuple{Call::RNEA, "RNEA", Eigen::Index(1)}, std::tuple{Call::CRBA, "CRBA", n},
            std::tuple{Call::ABA, "ABA", Eigen::Index(1)}}) {
        const std::string name = bench_name("pinocchio", std::string(algorithm) + "_batch", model, "double", "-") +
                                 "/batch:" + std::to_string(B) + "/threads:" + std::to_string(threads);
        benchmark::RegisterBenchmark(name.c_str(), [pool, x, B, threads, n, call = call, cols = cols](
                                                       benchmark::State& st) {
          Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, cols * B);
          for (auto _ : st) {
            run(call, threads, *pool, *x, B, out);
            benchmark::DoNotOptimize(out.data());
            benchmark::ClobberMemory();
          }
          st.SetItemsProcessed(st.iterations() * B);
          st.counters["batch"] = B;
          st.counters["threads"] = threads;
        })->UseRealTime()->MeasureProcessCPUTime();
      }
    }
  }
  for (const peers::PeerCheck* c : {&c_tau, &c_qdd, &c_H}) c->report();
}

}  // namespace spatial::bench

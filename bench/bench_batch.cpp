// Batched algorithms (include/spatial/batch.hpp, issue 15): spatial::Batch over B states per call, each SIMD lane
// one state, on stance21 and torso8, compile-time trees and their run-time twins (`to_runtime()`), double and float,
// on one thread and on all hardware threads (Batch's own worker pool).
//
// Names: "spatial/<algorithm>_batch/<model>/<scalar>/<tree>/batch:<B>/threads:<T>", algorithm spelled as the
// single-state records of bench_algorithms (RNEA, GravityTorques, BiasForces, CRBA, FD_CRBA_LTDL, ABA; FK = one
// frame's placement (Batch::frame_placement: a walk over the frame's chain since 2026-12-07, no longer the whole
// forward kinematics, so the report sets no single-state figure beside it), ComputeFrameJacobian = one frame's
// Jacobian in one walk (Batch::frame_jacobian), as bench_floating's). One iteration = one call over B states; tools/report.py
// divides by B (ns per state). Wall time is the iteration time (UseRealTime: with several threads the main thread's
// CPU time would count half the work) and the CPU time is the whole process's (MeasureProcessCPUTime).
// B: 1024 (inputs and τ or q̈ fit in L2; CRBA's H for 1024 states of stance21 is 3.6 MB in double, so CRBA also at
// B = 128: 0.45 MB) and 10000 (CRBA's H is 35 MB: memory-bound). RNEA, CRBA and ABA on every model, tree, scalar
// and thread count, B = 10000 on the compile-time trees only; the other algorithms on the compile-time trees, one
// thread, B = 1024 (what they cost next to RNEA; no target asks for them).
//
// Before any timing, every batched result is compared with the single-state call on the same state (run-time twin of
// the model, same scalar) for B = 256 and B = 3 × lanes + 1 (a tail group), on every Batch object that is timed, and
// the program aborts on a mismatch: ≤ 1e-12 relative in double, ≤ 1e-4 in float, 1e-3 for q̈ of CRBA + LTDL in
// float, which carries H's conditioning (‖·‖∞ of each state's result, peers/peer_check.hpp; one line per algorithm,
// model and scalar with the largest difference). They are not bit-identical: batch.hpp says why.
//
// The floating base (FloatingBatch) on floating27, the compile-time tree, double and float, B = 1024: RNEA, CRBA and
// ABA on every thread count, GravityTorques, FD_CRBA_LTDL, FK and ComputeFrameJacobian (L_SOLE, placed in the world,
// its Jacobian LOCAL_WORLD_ALIGNED) on one thread; the states are bench_floating's 256
// (bench_floating.hpp: root anywhere in a 1 m box, any orientation), repeated; checked as above against the
// single-state calls on the run-time twin before timing.
#include "bench_common.hpp"
#include "bench_floating.hpp"
#include "peers/peer_check.hpp"

#include <spatial/batch.hpp>

#include <algorithm>
#include <memory>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace {
using namespace spatial;
using namespace spatial::bench;

constexpr int kSizes[] = {1024, 10000};
constexpr int kMaxB = 10000;
constexpr int kSmallB = 128;  // CRBA only (its output, one nv × nv matrix per state, leaves the cache at B = 1024)
constexpr int kChecked = 256;  // states compared with the single-state calls

/// The thread counts timed: 1 and all hardware threads (2 here).
std::vector<int> thread_counts() {
  const int all = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return all > 1 ? std::vector<int>{1, all} : std::vector<int>{1};
}

/// The fixed frame of FK_batch and ComputeFrameJacobian_batch: the end of the longest branch.
const char* frame_of(const std::string& model) { return model == "torso8" ? "L_HAND" : "L_SOLE"; }

/// kMaxB random states (bench_models.hpp's InputPool with its seed: the first 256 are bench_algorithms' pool), one
/// column per state, and the single-state results of the first kChecked on the run-time twin.
template <class S>
struct States {
  using MatrixX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  MatrixX q, v, u;
  // references, one column (or one block of columns) per checked state
  MatrixX tau, grav, bias, H, fd, qdd, T, J;

  States(const Model<S>& runtime, const InputRange& range, int frame) {
    const InputPool<double> pool(range, kMaxB);
    const int n = runtime.size();
    q.resize(n, kMaxB);
    v.resize(n, kMaxB);
    u.resize(n, kMaxB);
    for (int k = 0; k < kMaxB; ++k) {
      const auto s = static_cast<std::size_t>(k);
      q.col(k) = pool.q[s].template cast<S>();
      v.col(k) = pool.qd[s].template cast<S>();
      u.col(k) = pool.u[s].template cast<S>();
    }
    Data<S> data(runtime);
    tau.resize(n, kChecked);
    grav.resize(n, kChecked);
    bias.resize(n, kChecked);
    fd.resize(n, kChecked);
    qdd.resize(n, kChecked);
    H.resize(n, n * kChecked);
    T.resize(3, 4 * kChecked);
    J.resize(6, n * kChecked);
    Eigen::Matrix<S, 6, Eigen::Dynamic> Jk(6, n);
    for (int k = 0; k < kChecked; ++k) {
      tau.col(k) = rnea(runtime, data, q.col(k), v.col(k), u.col(k));
      grav.col(k) = gravity_torques(runtime, data, q.col(k));
      bias.col(k) = bias_forces(runtime, data, q.col(k), v.col(k));
      fd.col(k) = forward_dynamics_crba(runtime, data, q.col(k), v.col(k), u.col(k));
      qdd.col(k) = aba(runtime, data, q.col(k), v.col(k), u.col(k));
      H.middleCols(k * n, n) = crba(runtime, data, q.col(k));
      forward_kinematics(runtime, data, q.col(k));
      T.middleCols(4 * k, 4) = frame_pose(runtime, data, frame).matrix().topRows(3);
      compute_frame_jacobian(runtime, data, q.col(k), frame, ReferenceFrame::LocalWorldAligned, Jk);
      J.middleCols(k * n, n) = Jk;
    }
  }
};

/// The comparisons of one model and scalar with the single-state calls, over both trees and every thread count.
struct Checks {
  peers::PeerCheck tau, grav, bias, H, fd, qdd, T, J;
  /// `fd_tol` for q̈ of CRBA + LTDL, which carries the conditioning of H (in float, the batched and the single-state
  /// calls compute their sines and cosines differently, each within a float spacing or two: see batch.hpp).
  Checks(const std::string& on, double tol, double fd_tol)
      : tau{"RNEA_batch tau" + on, tol}, grav{"GravityTorques_batch" + on, tol}, bias{"BiasForces_batch" + on, tol},
        H{"CRBA_batch H" + on, tol}, fd{"FD_CRBA_LTDL_batch qdd" + on, fd_tol}, qdd{"ABA_batch qdd" + on, tol},
        T{"FK_batch frame placement" + on, tol}, J{"ComputeFrameJacobian_batch" + on, tol} {}
  void report() const {
    for (const peers::PeerCheck* c : {&tau, &grav, &bias, &H, &fd, &qdd, &T, &J}) c->report();
  }
};

/// Compares the batched results on the first B states (B = kChecked and 3 × lanes + 1) with the references.
template <class S, class TreeT>
void check(Batch<S, TreeT>& batch, const States<S>& x, int frame, Checks& c) {
  using MatrixX = typename States<S>::MatrixX;
  const int n = batch.nv();
  for (const int B : {kChecked, 3 * Batch<S, TreeT>::lanes + 1}) {
    MatrixX tau(n, B), grav(n, B), bias(n, B), fd(n, B), qdd(n, B), H(n, n * B), T(3, 4 * B), J(6, n * B);
    batch.rnea(x.q.leftCols(B), x.v.leftCols(B), x.u.leftCols(B), tau);
    batch.gravity(x.q.leftCols(B), grav);
    batch.bias(x.q.leftCols(B), x.v.leftCols(B), bias);
    batch.forward_dynamics_crba(x.q.leftCols(B), x.v.leftCols(B), x.u.leftCols(B), fd);
    batch.aba(x.q.leftCols(B), x.v.leftCols(B), x.u.leftCols(B), qdd);
    batch.crba(x.q.leftCols(B), H);
    batch.frame_placement(x.q.leftCols(B), frame, T);
    batch.frame_jacobian(x.q.leftCols(B), frame, ReferenceFrame::LocalWorldAligned, J);
    for (int k = 0; k < B; ++k) {
      c.tau.compare(tau.col(k), x.tau.col(k));
      c.grav.compare(grav.col(k), x.grav.col(k));
      c.bias.compare(bias.col(k), x.bias.col(k));
      c.fd.compare(fd.col(k), x.fd.col(k));
      c.qdd.compare(qdd.col(k), x.qdd.col(k));
      c.H.compare(H.middleCols(k * n, n), x.H.middleCols(k * n, n));
      c.T.compare(T.middleCols(4 * k, 4), x.T.middleCols(4 * k, 4));
      c.J.compare(J.middleCols(k * n, n), x.J.middleCols(k * n, n));
    }
  }
}

/// Registers one batched call: `call(batch, states, B, outputs)` timed, outputs (rows × cols_per_state·B) allocated
/// and touched before the timed loop.
template <class BatchT, class X, class Call>
void register_batch(const std::string& name, const std::shared_ptr<BatchT>& batch, const std::shared_ptr<const X>& x,
                    int B, int rows, int cols_per_state, Call call) {
  using S = typename BatchT::Scalar;
  benchmark::RegisterBenchmark(name.c_str(), [batch, x, B, rows, cols_per_state, call](benchmark::State& st) {
    Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> out =
        Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>::Zero(rows, Eigen::Index(cols_per_state) * B);
    for (auto _ : st) {
      call(*batch, *x, B, out);
      benchmark::DoNotOptimize(out.data());
      benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(st.iterations() * B);
    st.counters["batch"] = B;
    st.counters["threads"] = batch->threads();
  })->UseRealTime()->MeasureProcessCPUTime();
}

template <class S, class TreeT>
void register_model(const std::string& model_name, const std::string& tree, const Model<S, TreeT>& model,
                    const std::shared_ptr<const States<S>>& x, int frame, Checks& checks) {
  using M = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using B_ = Batch<S, TreeT>;
  const int n = model.size();
  for (const int threads : thread_counts()) {
    auto batch = std::make_shared<B_>(model, threads);
    check(*batch, *x, frame, checks);
    for (const int B : kSizes) {
      // B = 10000 (memory-bound CRBA) on the compile-time trees only: the run-time trees' figures at B = 1024 say
      // what they cost next to them
      if (tree != "static" && B != kSizes[0]) continue;
      const auto name = [&](const char* algorithm, int b) {
        return bench_name("spatial", std::string(algorithm) + "_batch", model_name, scalar_name<S>(), tree) +
               "/batch:" + std::to_string(b) + "/threads:" + std::to_string(threads);
      };
      register_batch(name("RNEA", B), batch, x, B, n, 1, [](B_& b, const States<S>& s, int m, M& out) {
        b.rnea(s.q.leftCols(m), s.v.leftCols(m), s.u.leftCols(m), out);
      });
      register_batch(name("CRBA", B), batch, x, B, n, n, [](B_& b, const States<S>& s, int m, M& out) {
        b.crba(s.q.leftCols(m), out);
      });
      register_batch(name("ABA", B), batch, x, B, n, 1, [](B_& b, const States<S>& s, int m, M& out) {
        b.aba(s.q.leftCols(m), s.v.leftCols(m), s.u.leftCols(m), out);
      });
      if (tree != "static" || threads != 1 || B != kSizes[0]) continue;
      // CRBA at B = kSmallB too: H of 128 states of stance21 is 0.45 MB (L2), against 3.6 MB at B = 1024
      register_batch(name("CRBA", kSmallB), batch, x, kSmallB, n, n, [](B_& b, const States<S>& s, int m, M& out) {
        b.crba(s.q.leftCols(m), out);
      });
      register_batch(name("GravityTorques", B), batch, x, B, n, 1, [](B_& b, const States<S>& s, int m, M& out) {
        b.gravity(s.q.leftCols(m), out);
      });
      register_batch(name("BiasForces", B), batch, x, B, n, 1, [](B_& b, const States<S>& s, int m, M& out) {
        b.bias(s.q.leftCols(m), s.v.leftCols(m), out);
      });
      register_batch(name("FD_CRBA_LTDL", B), batch, x, B, n, 1, [](B_& b, const States<S>& s, int m, M& out) {
        b.forward_dynamics_crba(s.q.leftCols(m), s.v.leftCols(m), s.u.leftCols(m), out);
      });
      register_batch(name("FK", B), batch, x, B, 3, 4, [frame](B_& b, const States<S>& s, int m, M& out) {
        b.frame_placement(s.q.leftCols(m), frame, out);
      });
      register_batch(name("ComputeFrameJacobian", B), batch, x, B, 6, n,
                     [frame](B_& b, const States<S>& s, int m, M& out) {
                       b.frame_jacobian(s.q.leftCols(m), frame, ReferenceFrame::LocalWorldAligned, out);
                     });
    }
  }
}

/// Both trees of one model in scalar S.
template <class S, class TreeT>
void register_scalar(const BenchModel<TreeT>& entry) {
  const Model<S, TreeT> model = entry.model.template cast<S>();
  const Model<S> runtime = model.to_runtime();
  const int frame = runtime.frame_index(frame_of(entry.name));
  const auto x = std::make_shared<const States<S>>(runtime, entry.range, frame);
  Checks checks(std::string(" (") + scalar_name<S>() + ", both trees, all thread counts) on " + entry.name,
                std::is_same_v<S, double> ? 1e-12 : 1e-4, std::is_same_v<S, double> ? 1e-12 : 1e-3);
  register_model(entry.name, "static", model, x, frame, checks);
  register_model(entry.name, "runtime", runtime, x, frame, checks);
  checks.report();
}

/// floating27's batched algorithms in scalar S (see the file comment).
template <class S>
void register_floating() {
  using M = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using FB = FloatingBatch<S, Floating27Tree>;
  struct FloatingStates {
    M q, v, u;
  };
  const FloatingModel<S, Floating27Tree> model = floating27().template cast<S>();
  const FloatingModel<S> runtime = model.to_runtime();
  const FloatingPool<double>& pool = floating_pool();
  const int nq = model.nq(), nv = model.nv(), B = kSizes[0];
  auto x = std::make_shared<FloatingStates>();
  x->q.resize(nq, B), x->v.resize(nv, B), x->u.resize(nv, B);
  for (int k = 0; k < B; ++k) {
    const auto s = static_cast<std::size_t>(k % pool.size());
    x->q.col(k) = pool.q[s].template cast<S>();
    x->v.col(k) = pool.v[s].template cast<S>();
    x->u.col(k) = pool.u[s].template cast<S>();
  }
  const bool dbl = std::is_same_v<S, double>;
  const std::string on = std::string(" (") + scalar_name<S>() + ", all thread counts) on floating27";
  peers::PeerCheck tau{"RNEA_batch tau" + on, dbl ? 1e-12 : 1e-4}, grav{"GravityTorques_batch" + on, dbl ? 1e-12 : 1e-4},
      H{"CRBA_batch H" + on, dbl ? 1e-12 : 1e-4}, fd{"FD_CRBA_LTDL_batch qdd" + on, dbl ? 1e-12 : 1e-3},
      qdd{"ABA_batch qdd" + on, dbl ? 1e-12 : 1e-4}, T{"FK_batch frame placement" + on, dbl ? 1e-12 : 1e-4},
      J{"ComputeFrameJacobian_batch" + on, dbl ? 1e-12 : 1e-4};
  FloatingData<S> data(runtime);
  const int frame = runtime.frame_index(frame_of("floating27"));
  for (const int threads : thread_counts()) {
    auto batch = std::make_shared<FB>(model, threads);
    for (const int b : {kChecked, 3 * FB::lanes + 1}) {
      M t(nv, b), g(nv, b), h(nv, nv * b), f(nv, b), a(nv, b), p(3, 4 * b), j(6, nv * b), jk(6, nv);
      batch->rnea(x->q.leftCols(b), x->v.leftCols(b), x->u.leftCols(b), t);
      batch->gravity(x->q.leftCols(b), g);
      batch->crba(x->q.leftCols(b), h);
      batch->forward_dynamics_crba(x->q.leftCols(b), x->v.leftCols(b), x->u.leftCols(b), f);
      batch->aba(x->q.leftCols(b), x->v.leftCols(b), x->u.leftCols(b), a);
      batch->frame_placement(x->q.leftCols(b), frame, p);
      batch->frame_jacobian(x->q.leftCols(b), frame, ReferenceFrame::LocalWorldAligned, j);
      for (int k = 0; k < b; ++k) {
        tau.compare(t.col(k), rnea(runtime, data, x->q.col(k), x->v.col(k), x->u.col(k)));
        grav.compare(g.col(k), gravity_torques(runtime, data, x->q.col(k)));
        H.compare(h.middleCols(k * nv, nv), crba(runtime, data, x->q.col(k)));
        fd.compare(f.col(k), forward_dynamics_crba(runtime, data, x->q.col(k), x->v.col(k), x->u.col(k)));
        qdd.compare(a.col(k), aba(runtime, data, x->q.col(k), x->v.col(k), x->u.col(k)));
        forward_kinematics(runtime, data, x->q.col(k));
        T.compare(p.middleCols(4 * k, 4), M(frame_pose(runtime, data, frame).matrix().topRows(3)));
        compute_frame_jacobian(runtime, data, x->q.col(k), frame, ReferenceFrame::LocalWorldAligned, jk);
        J.compare(j.middleCols(k * nv, nv), jk);
      }
    }
    const auto name = [&](const char* algorithm) {
      return bench_name("spatial", std::string(algorithm) + "_batch", "floating27", scalar_name<S>(), "static") +
             "/batch:" + std::to_string(B) + "/threads:" + std::to_string(threads);
    };
    using X = FloatingStates;
    register_batch(name("RNEA"), batch, std::shared_ptr<const X>(x), B, nv, 1, [](FB& b, const X& s, int m, M& out) {
      b.rnea(s.q.leftCols(m), s.v.leftCols(m), s.u.leftCols(m), out);
    });
    register_batch(name("CRBA"), batch, std::shared_ptr<const X>(x), B, nv, nv, [](FB& b, const X& s, int m, M& out) {
      b.crba(s.q.leftCols(m), out);
    });
    register_batch(name("ABA"), batch, std::shared_ptr<const X>(x), B, nv, 1, [](FB& b, const X& s, int m, M& out) {
      b.aba(s.q.leftCols(m), s.v.leftCols(m), s.u.leftCols(m), out);
    });
    if (threads != 1) continue;
    register_batch(name("GravityTorques"), batch, std::shared_ptr<const X>(x), B, nv, 1,
                   [](FB& b, const X& s, int m, M& out) { b.gravity(s.q.leftCols(m), out); });
    register_batch(name("FD_CRBA_LTDL"), batch, std::shared_ptr<const X>(x), B, nv, 1,
                   [](FB& b, const X& s, int m, M& out) {
                     b.forward_dynamics_crba(s.q.leftCols(m), s.v.leftCols(m), s.u.leftCols(m), out);
                   });
    register_batch(name("FK"), batch, std::shared_ptr<const X>(x), B, 3, 4, [frame](FB& b, const X& s, int m, M& out) {
      b.frame_placement(s.q.leftCols(m), frame, out);
    });
    register_batch(name("ComputeFrameJacobian"), batch, std::shared_ptr<const X>(x), B, 6, nv,
                   [frame](FB& b, const X& s, int m, M& out) {
                     b.frame_jacobian(s.q.leftCols(m), frame, ReferenceFrame::LocalWorldAligned, out);
                   });
  }
  for (const peers::PeerCheck* c : {&tau, &grav, &H, &fd, &qdd, &T, &J}) c->report();
}

const bool registered = [] {
  add_build_context();
  benchmark::AddCustomContext("spatial_batch_lanes_double", std::to_string(Batch<double, DynamicTree>::lanes));
  benchmark::AddCustomContext("spatial_batch_lanes_float", std::to_string(Batch<float, DynamicTree>::lanes));
  benchmark::AddCustomContext("spatial_batch_arch", xsimd::default_arch::name());
  for_each_bench_model([](const auto& entry) {
    // stance21 and torso8 (the models); not pendulum2, not even instantiated
    if constexpr (!std::is_same_v<typename std::decay_t<decltype(entry)>::tree_type, Pendulum2Tree>) {
      register_scalar<double>(entry);
      register_scalar<float>(entry);
    }
  });
  register_floating<double>();
  register_floating<float>();
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

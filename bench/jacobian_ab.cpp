// One frame's Jacobian in one walk (the left sole, LocalWorldAligned) and its placement, and the same Jacobian taken
// from the joint Jacobians (LocalWorldAligned and Local), for scripts/ab.sh: old against new headers in one process,
// interleaved.
//   bash scripts/ab.sh HEAD bench/jacobian_ab.cpp                 # g++
//   bash scripts/ab.sh --cxx clang++ HEAD bench/jacobian_ab.cpp
// Batched (`Batch::frame_jacobian`, 256 states per call, one thread; time per call) on stance21 in double and float
// and on floating27 in double, the same frame's batched placement (`Batch::frame_placement`, FK_batch in
// bench_batch), and the single-state `compute_frame_jacobian` on floating27 (the AVX2 walk when the build has
// AVX2). Standalone (not in the CMake build).
#include <benchmark/benchmark.h>
#include "ab.hpp"
#include <spatial/batch.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <random>
#include <vector>

namespace {
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;
constexpr int kStates = 256;

Eigen::MatrixXd floating_states(const FloatingModel<double, F::Tree>& m) {
  std::mt19937 rng(7);
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(21, -1), hi = Eigen::VectorXd::Constant(21, 1);
  Eigen::MatrixXd Q(28, kStates);
  for (int k = 0; k < kStates; ++k) Q.col(k) = random_configuration(m, lo, hi, rng);
  return Q;
}

/// Times call(b, Q, out) (one call over the kStates states of Q).
template <class B, class X, class Call>
void time_calls(benchmark::State& st, B& b, const X& Q, X& out, Call call) {
  for (auto _ : st) {
    call(b, Q, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
}
/// The left sole's batched Jacobian (LocalWorldAligned; jacobian) or placement, on stance21 in S.
template <class S, bool Jacobian>
void stance21(benchmark::State& st) {
  using MX = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  Batch<S, M::Tree> b(M::model().template cast<S>(), 1);
  const MX Q = Eigen::MatrixXd::Random(21, kStates).cast<S>();
  MX out(Jacobian ? 6 : 3, (Jacobian ? 21 : 4) * kStates);
  const int f = M::frame_index("L_SOLE");
  time_calls(st, b, Q, out, [f](auto& bb, const MX& q, MX& o) {
    if constexpr (Jacobian) bb.frame_jacobian(q, f, ReferenceFrame::LocalWorldAligned, o);
    else bb.frame_placement(q, f, o);
  });
}
/// The same on floating27, double.
template <bool Jacobian>
void floating27(benchmark::State& st) {
  const auto m = F::floating_model<double>();
  FloatingBatch<double, F::Tree> b(m, 1);
  const Eigen::MatrixXd Q = floating_states(m);
  Eigen::MatrixXd out(Jacobian ? 6 : 3, (Jacobian ? 27 : 4) * kStates);
  const int f = F::frame_index("L_SOLE");
  time_calls(st, b, Q, out, [f](auto& bb, const Eigen::MatrixXd& q, Eigen::MatrixXd& o) {
    if constexpr (Jacobian) bb.frame_jacobian(q, f, ReferenceFrame::LocalWorldAligned, o);
    else bb.frame_placement(q, f, o);
  });
}
void single_floating27(benchmark::State& st) {
  const auto m = F::floating_model<double>();
  FloatingData<double, F::Tree> d(m);
  const Eigen::MatrixXd Q = floating_states(m);
  Eigen::MatrixXd J(6, 27);
  const int f = F::frame_index("L_SOLE");
  int k = 0;
  for (auto _ : st) {
    compute_frame_jacobian(m, d, Q.col(k), f, ReferenceFrame::LocalWorldAligned, J);
    k = (k + 1) % kStates;
    benchmark::DoNotOptimize(J.data());
    benchmark::ClobberMemory();
  }
}
/// The left sole's Jacobian from the joint Jacobians (`frame_jacobian` after `compute_joint_jacobians` at one state,
/// bench_floating's FrameJacobian), in rf, on floating27 or stance21.
template <bool Floating>
void from_joint_jacobians(benchmark::State& st, ReferenceFrame rf) {
  const auto run = [&](const auto& m, auto& d, const auto& q, int f, Eigen::MatrixXd& J) {
    compute_joint_jacobians(m, d, q);
    for (auto _ : st) {
      frame_jacobian(m, d, f, rf, J);
      benchmark::DoNotOptimize(J.data());
      benchmark::ClobberMemory();
    }
  };
  if constexpr (Floating) {
    const auto m = F::floating_model<double>();
    FloatingData<double, F::Tree> d(m);
    Eigen::MatrixXd J(6, 27);
    run(m, d, floating_states(m).col(0), F::frame_index("L_SOLE"), J);
  } else {
    const auto& m = M::model();
    Data<double, M::Tree> d(m);
    Eigen::MatrixXd J(6, 21);
    run(m, d, Eigen::VectorXd::Constant(21, 0.3), M::frame_index("L_SOLE"), J);
  }
}
template <bool Floating>
void from_joint_jacobians_lwa(benchmark::State& st) {
  from_joint_jacobians<Floating>(st, ReferenceFrame::LocalWorldAligned);
}
void from_joint_jacobians_local(benchmark::State& st) { from_joint_jacobians<true>(st, ReferenceFrame::Local); }
}  // namespace

BENCHMARK(from_joint_jacobians_lwa<true>)->Name(AB_TAG "FrameJacobian_LWA/floating27/double");
BENCHMARK(from_joint_jacobians_local)->Name(AB_TAG "FrameJacobian_Local/floating27/double");
BENCHMARK(from_joint_jacobians_lwa<false>)->Name(AB_TAG "FrameJacobian_LWA/stance21/double");
BENCHMARK(stance21<double, true>)->Name(AB_TAG "ComputeFrameJacobian_batch256/stance21/double");
BENCHMARK(stance21<float, true>)->Name(AB_TAG "ComputeFrameJacobian_batch256/stance21/float");
BENCHMARK(floating27<true>)->Name(AB_TAG "ComputeFrameJacobian_batch256/floating27/double");
BENCHMARK(single_floating27)->Name(AB_TAG "ComputeFrameJacobian/floating27/double");
BENCHMARK(stance21<double, false>)->Name(AB_TAG "FK_batch256/stance21/double");
BENCHMARK(stance21<float, false>)->Name(AB_TAG "FK_batch256/stance21/float");
BENCHMARK(floating27<false>)->Name(AB_TAG "FK_batch256/floating27/double");

// Pinocchio on every bench model, from the same model (peers/pinocchio_peer.hpp) and the same input pool as
// bench_algorithms: rnea, computeGeneralizedGravity, nonLinearEffects, crba (upper triangle only, as Pinocchio
// computes it), aba, crba + nonLinearEffects + cholesky::decompose + cholesky::solve, and forwardKinematics; in
// double, and in float with SPATIAL_PINOCCHIO_FLOAT (CMake option of the same name; off by default because
// instantiating Pinocchio twice doubles the compile time). The binary's other parts: bench_pinocchio_derivatives.cpp
// and bench_pinocchio_floating.cpp (pinocchio_bench.hpp says what they share and why they are three).
//
// Before any timing, Pinocchio's results are compared with spatial's on the first 32 pool states and the program
// aborts on a mismatch (double: τ, G, C, H and poses ≤ 1e-12 relative, q̈ ≤ 1e-10; float against spatial's double:
// ≤ 1e-3).
#include "pinocchio_bench.hpp"

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/cholesky.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace {
using namespace spatial;
using namespace spatial::bench;
using namespace spatial::peers;

/// crba + nonLinearEffects + cholesky::decompose + cholesky::solve: Pinocchio's forward dynamics by CRBA.
template <class S>
const typename PinFixture<S>::Vector& pinocchio_fd_crba(PinFixture<S>& f, std::size_t k) {
  const auto& m = f.peer.model;
  pinocchio::crba(m, f.data, f.q[k]);
  pinocchio::nonLinearEffects(m, f.data, f.q[k], f.v[k]);
  pinocchio::cholesky::decompose(m, f.data);
  f.x = f.u[k] - f.data.nle;
  pinocchio::cholesky::solve(m, f.data, f.x);
  return f.x;
}

template <class S, class TreeT>
void check(const BenchModel<TreeT>& entry, PinFixture<S>& f, const InputPool<double>& pool) {
  const Model<double> model = entry.model.to_runtime();  // ours on the run-time twin: see pinocchio_bench.hpp
  Data<double> data(model);
  const bool is_double = std::is_same_v<S, double>;
  const double tight = is_double ? 1e-12 : 1e-3, loose = is_double ? 1e-10 : 1e-3;
  const std::string on = std::string(" (") + scalar_name<S>() + ") on " + entry.name;
  PeerCheck tau{"Pinocchio rnea tau" + on, tight}, grav{"Pinocchio computeGeneralizedGravity" + on, tight},
      nle{"Pinocchio nonLinearEffects" + on, tight}, mass{"Pinocchio crba H (upper triangle)" + on, tight},
      fd_aba{"Pinocchio aba qdd" + on, loose}, fd_crba{"Pinocchio crba+cholesky qdd" + on, loose},
      fk{"Pinocchio forwardKinematics poses" + on, tight};
  const auto& pm = f.peer.model;
  for (int k = 0; k < 32 && k < pool.size(); ++k) {
    const auto s = static_cast<std::size_t>(k);
    tau.compare(f.peer.from_pinocchio(pinocchio::rnea(pm, f.data, f.q[s], f.v[s], f.u[s])),
                rnea(model, data, pool.q[s], pool.qd[s], pool.u[s]));
    grav.compare(f.peer.from_pinocchio(pinocchio::computeGeneralizedGravity(pm, f.data, f.q[s])),
                 gravity_torques(model, data, pool.q[s]));
    nle.compare(f.peer.from_pinocchio(pinocchio::nonLinearEffects(pm, f.data, f.q[s], f.v[s])),
                bias_forces(model, data, pool.q[s], pool.qd[s]));
    Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic> M = pinocchio::crba(pm, f.data, f.q[s]);
    M.template triangularView<Eigen::StrictlyLower>() = M.transpose().template triangularView<Eigen::StrictlyLower>();
    mass.compare(f.peer.from_pinocchio_matrix(M), crba(model, data, pool.q[s]));
    fd_aba.compare(f.peer.from_pinocchio(pinocchio::aba(pm, f.data, f.q[s], f.v[s], f.u[s])),
                   aba(model, data, pool.q[s], pool.qd[s], pool.u[s]));
    fd_crba.compare(f.peer.from_pinocchio(pinocchio_fd_crba(f, s)),
                    forward_dynamics_crba(model, data, pool.q[s], pool.qd[s], pool.u[s]));
    pinocchio::forwardKinematics(pm, f.data, f.q[s]);
    forward_kinematics(model, data, pool.q[s]);
    for (std::size_t j = 0; j < f.peer.order.size(); ++j) {
      const auto pose = body_pose(data, f.peer.order[j]);
      const auto& oMi = f.data.oMi[j + 1];
      Eigen::Matrix<double, 3, 4> ours, theirs;
      ours << pose.linear(), pose.translation();
      theirs << oMi.rotation().template cast<double>(), oMi.translation().template cast<double>();
      fk.compare(theirs, ours);
    }
  }
  for (const PeerCheck* c : {&tau, &grav, &nle, &mass, &fd_aba, &fd_crba, &fk}) c->report();
}

template <class S, class TreeT>
void register_pinocchio(const BenchModel<TreeT>& entry) {
  const InputPool<double> pool(entry.range);
  auto fx = make_pin_fixture<S>(entry, pool);
  check(entry, *fx, pool);
#ifdef SPATIAL_PINOCCHIO_BATCH
  // bench_pinocchio_batch.cpp, beside bench_batch: stance21 and torso8, 10000 states (the first 256: `pool`'s)
  if constexpr (std::is_same_v<S, double> && !std::is_same_v<TreeT, Pendulum2Tree>) {
    const InputPool<double> big(entry.range, 10000);
    const Eigen::Index n = entry.model.size();
    Eigen::MatrixXd q(n, big.size()), v(n, big.size()), u(n, big.size());
    for (int k = 0; k < big.size(); ++k) {
      const auto s = static_cast<std::size_t>(k);
      q.col(k) = fx->peer.to_pinocchio(big.q[s]);
      v.col(k) = fx->peer.to_pinocchio(big.qd[s]);
      u.col(k) = fx->peer.to_pinocchio(big.u[s]);
    }
    register_pinocchio_batch(entry.name, fx->peer.model, std::move(q), std::move(v), std::move(u));
  }
#endif

  using Fx = PinFixture<S>;
  const auto reg = [&](const char* algorithm, auto body) {
    register_pinocchio_call(fx, entry.name, scalar_name<S>(), algorithm, body);
  };
  reg("RNEA", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::rnea(f.peer.model, f.data, f.q[k], f.v[k], f.u[k]).data());
  });
  reg("GravityTorques", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::computeGeneralizedGravity(f.peer.model, f.data, f.q[k]).data());
  });
  reg("BiasForces", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::nonLinearEffects(f.peer.model, f.data, f.q[k], f.v[k]).data());
  });
  reg("CRBA", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::crba(f.peer.model, f.data, f.q[k]).data());
  });
  reg("FD_CRBA_LTDL", [](Fx& f, std::size_t k) { benchmark::DoNotOptimize(pinocchio_fd_crba(f, k).data()); });
  reg("ABA", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::aba(f.peer.model, f.data, f.q[k], f.v[k], f.u[k]).data());
  });
  reg("FK", [](Fx& f, std::size_t k) {
    pinocchio::forwardKinematics(f.peer.model, f.data, f.q[k]);
    benchmark::DoNotOptimize(f.data.oMi.back().translation().data());
    benchmark::ClobberMemory();
  });
}

}  // namespace

namespace spatial::bench {
const Eigen::VectorXd& pinocchio_rnea(const pinocchio::Model& m, pinocchio::Data& d, const Eigen::VectorXd& q,
                                      const Eigen::VectorXd& v, const Eigen::VectorXd& a) {
  return pinocchio::rnea(m, d, q, v, a);
}
const Eigen::VectorXd& pinocchio_aba(const pinocchio::Model& m, pinocchio::Data& d, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& v, const Eigen::VectorXd& tau) {
  return pinocchio::aba(m, d, q, v, tau);
}
const Eigen::MatrixXd& pinocchio_crba(const pinocchio::Model& m, pinocchio::Data& d, const Eigen::VectorXd& q) {
  return pinocchio::crba(m, d, q);
}
}  // namespace spatial::bench

namespace {
const bool registered = [] {
  benchmark::AddCustomContext("pinocchio_version", PINOCCHIO_VERSION);
  benchmark::AddCustomContext("spatial_eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                                   std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                                   std::to_string(EIGEN_MINOR_VERSION));
#ifdef SPATIAL_BENCH_FLAGS
  benchmark::AddCustomContext("spatial_flags", SPATIAL_BENCH_FLAGS);
#endif
#if defined(__clang__)
  benchmark::AddCustomContext("spatial_compiler", std::string("clang ") + __clang_version__);
#elif defined(__GNUC__)
  benchmark::AddCustomContext("spatial_compiler", std::string("gcc ") + __VERSION__);
#endif
  for_each_bench_model([](const auto& entry) {
    register_pinocchio<double>(entry);
#ifdef SPATIAL_PINOCCHIO_FLOAT
    register_pinocchio<float>(entry);
#endif
  });
  return true;
}();

}  // namespace

BENCHMARK_MAIN();

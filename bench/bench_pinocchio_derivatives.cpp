// Part of bench_pinocchio (pinocchio_bench.hpp): Pinocchio's computeRNEADerivatives, computeABADerivatives and
// computeMinverse on every bench model (double) and on floating27, against spatial's rnea_derivatives,
// aba_derivatives and inverse_inertia on the same states, then timed ("RNEA_derivatives", "ABA_derivatives",
// "Minv").
#include "pinocchio_bench.hpp"

#include <spatial/derivatives.hpp>
#include <spatial/minv.hpp>

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>

#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <type_traits>

namespace {
using namespace spatial;
using namespace spatial::bench;
using namespace spatial::peers;

/// Pinocchio's computeRNEADerivatives and computeABADerivatives against ours on the first 32 states (double):
/// ∂τ/∂q, ∂τ/∂v ≤ 1e-12 and ∂q̈/∂q, ∂q̈/∂v, ∂q̈/∂τ = M⁻¹ (Pinocchio fills its upper triangle) ≤ 1e-10, relative.
/// Ours on the run-time twin of the model (pinocchio_bench.hpp says why).
template <class Fx, class ModelT, class OQ, class OV>
void check_derivatives(Fx& f, const ModelT& model, const OQ& oq, const OV& ov, const OV& ou, const std::string& name) {
  using Peer = decltype(f.peer);
  const Peer& peer = f.peer;
  const pinocchio::Model& pm = f.model();
  pinocchio::Data& pd = f.data;
  const auto &q = f.q, &v = f.v, &u = f.u;
  using Deriv = std::conditional_t<std::is_same_v<Peer, PinocchioPeer<double>>,
                                   DerivativeData<double, typename ModelT::tree_type>,
                                   FloatingDerivativeData<double, typename ModelT::tree_type>>;
  using D = std::conditional_t<std::is_same_v<Peer, PinocchioPeer<double>>, Data<double, typename ModelT::tree_type>,
                               FloatingData<double, typename ModelT::tree_type>>;
  using MinvT = std::conditional_t<std::is_same_v<Peer, PinocchioPeer<double>>,
                                   MinvData<double, typename ModelT::tree_type>,
                                   FloatingMinvData<double, typename ModelT::tree_type>>;
  D data(model);
  Deriv dd(model);
  MinvT md(model);
  const std::string on = " (double) on " + name;
  PeerCheck rq{"Pinocchio computeRNEADerivatives dtau_dq" + on, 1e-12},
      rv{"Pinocchio computeRNEADerivatives dtau_dv" + on, 1e-12},
      aq{"Pinocchio computeABADerivatives ddq_dq" + on, 1e-10}, av{"Pinocchio computeABADerivatives ddq_dv" + on, 1e-10},
      mi{"Pinocchio computeABADerivatives Minv" + on, 1e-10}, cm{"Pinocchio computeMinverse" + on, 1e-10};
  for (std::size_t s = 0; s < 32 && s < q.size(); ++s) {
    pinocchio::computeRNEADerivatives(pm, pd, q[s], v[s], u[s]);
    rnea_derivatives(model, data, dd, oq[s], ov[s], ou[s]);
    rq.compare(peer.from_pinocchio_matrix(pd.dtau_dq), dd.dtau_dq);
    rv.compare(peer.from_pinocchio_matrix(pd.dtau_dv), dd.dtau_dv);
    pinocchio::computeABADerivatives(pm, pd, q[s], v[s], u[s]);
    aba_derivatives(model, data, dd, oq[s], ov[s], ou[s]);
    aq.compare(peer.from_pinocchio_matrix(pd.ddq_dq), dd.dqdd_dq);
    av.compare(peer.from_pinocchio_matrix(pd.ddq_dv), dd.dqdd_dv);
    Eigen::MatrixXd M = pd.Minv;
    M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
    mi.compare(peer.from_pinocchio_matrix(M), dd.dqdd_dtau);
    pinocchio::computeMinverse(pm, pd, q[s]);
    M = pd.Minv;
    M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
    cm.compare(peer.from_pinocchio_matrix(M), inverse_inertia(model, data, md, oq[s]));
  }
  for (const PeerCheck* c : {&rq, &rv, &aq, &av, &mi, &cm}) c->report();
}

/// The three timed calls, on a fixture with `model()`, `data` and the states `q`, `v` and `u` (PinFixture or
/// FloatingPinStates).
template <class Fx>
void register_derivatives(const std::shared_ptr<Fx>& fx, const std::string& name) {
  register_pinocchio_call(fx, name, "double", "RNEA_derivatives", [](Fx& f, std::size_t k) {
    pinocchio::computeRNEADerivatives(f.model(), f.data, f.q[k], f.v[k], f.u[k]);
    benchmark::DoNotOptimize(f.data.dtau_dq.data());
    benchmark::ClobberMemory();
  });
  register_pinocchio_call(fx, name, "double", "ABA_derivatives", [](Fx& f, std::size_t k) {
    pinocchio::computeABADerivatives(f.model(), f.data, f.q[k], f.v[k], f.u[k]);
    benchmark::DoNotOptimize(f.data.ddq_dq.data());
    benchmark::ClobberMemory();
  });
  register_pinocchio_call(fx, name, "double", "Minv", [](Fx& f, std::size_t k) {
    benchmark::DoNotOptimize(pinocchio::computeMinverse(f.model(), f.data, f.q[k]).data());
    benchmark::ClobberMemory();
  });
}

const bool registered = [] {
  for_each_bench_model([](const auto& entry) {
    const InputPool<double> pool(entry.range);
    auto fx = make_pin_fixture<double>(entry, pool);
    check_derivatives(*fx, entry.model.to_runtime(), pool.q, pool.qd, pool.u, entry.name);
    register_derivatives(fx, entry.name);
  });
  auto fl = std::make_shared<FloatingPinStates>(make_pinocchio_floating_peer(floating27()));
  const auto& pool = floating_pool();
  check_derivatives(*fl, floating27().to_runtime(), pool.q, pool.v, pool.u, "floating27");
  register_derivatives(fl, "floating27");
  return true;
}();

}  // namespace

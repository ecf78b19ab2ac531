#pragma once
// Benchmarks of the analytical derivatives (derivatives.hpp) and of the finite differences they replace:
// RNEA_derivatives (∂τ/∂q and ∂τ/∂q̇), ABA_derivatives (∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ) and RNEA_derivatives_fd, the same two
// matrices of RNEA by forward differences: 2n + 1 RNEA calls (n + 1 for ∂τ/∂q alone), on the configuration manifold
// for a floating base (q ⊕ h eₖ through `integrate`). Also Minv: H⁻¹ computed directly (minv.hpp).
#include "bench_common.hpp"
#include "fd_derivatives.hpp"

#include <spatial/derivatives.hpp>
#include <spatial/minv.hpp>

#include <memory>
#include <string>

namespace spatial::bench {

/// Registers RNEA_derivatives, ABA_derivatives, RNEA_derivatives_fd and Minv for `model` (fixed or floating) on the states
/// of `pool` (q, v or qd, u), under `name(algorithm)`.
/// With `central`, also RNEA_derivatives_central (central differences, 4n RNEA calls; fixed base only).
template <class ModelT, class DataT, class DerivT, class Pool, class Name>
void register_derivatives(const ModelT& model, const Pool& pool, Name&& name, bool central = false) {
  using S = typename ModelT::Scalar;
  using T = typename ModelT::tree_type;
  using MinvT = std::conditional_t<std::is_same_v<ModelT, Model<S, T>>, MinvData<S, T>, FloatingMinvData<S, T>>;
  struct Fx {
    ModelT model;
    DataT data;
    DerivT dd;
    MinvT md;
    Pool pool;
    decltype(DerivT::dtau_dq) dq, dv;
    explicit Fx(const ModelT& m, const Pool& p)
        : model(m), data(model), dd(model), md(model), pool(p), dq(dd.dtau_dq), dv(dq) {}
  };
  auto fx = std::make_shared<Fx>(model, pool);
  const auto at = [](const auto& v, int k) -> const auto& { return v[static_cast<std::size_t>(k)]; };
  const auto vel = [](const Pool& p) -> const auto& {
    if constexpr (std::is_same_v<ModelT, Model<typename ModelT::Scalar, typename ModelT::tree_type>>) return p.qd;
    else return p.v;
  };
  register_one(name("RNEA_derivatives"), fx, [at, vel](Fx& f, int k) {
    rnea_derivatives(f.model, f.data, f.dd, at(f.pool.q, k), at(vel(f.pool), k), at(f.pool.u, k));
    benchmark::DoNotOptimize(f.dd.dtau_dq.data());
    benchmark::ClobberMemory();
  });
  register_one(name("ABA_derivatives"), fx, [at, vel](Fx& f, int k) {
    aba_derivatives(f.model, f.data, f.dd, at(f.pool.q, k), at(vel(f.pool), k), at(f.pool.u, k));
    benchmark::DoNotOptimize(f.dd.dqdd_dq.data());
    benchmark::ClobberMemory();
  });
  register_one(name("Minv"), fx, [at](Fx& f, int k) {
    benchmark::DoNotOptimize(inverse_inertia(f.model, f.data, f.md, at(f.pool.q, k)).data());
    benchmark::ClobberMemory();
  });
  register_one(name("RNEA_derivatives_fd"), fx, [at, vel](Fx& f, int k) {
    rnea_derivatives_fd(f.model, f.data, at(f.pool.q, k), at(vel(f.pool), k), at(f.pool.u, k), f.dq, f.dv,
                        forward_difference_step<S>());
    benchmark::DoNotOptimize(f.dq.data());
    benchmark::ClobberMemory();
  });
  if constexpr (std::is_same_v<ModelT, Model<S, T>>) {
    if (central)
      register_one(name("RNEA_derivatives_central"), fx, [at, vel](Fx& f, int k) {
        rnea_derivatives_central(f.model, f.data, at(f.pool.q, k), at(vel(f.pool), k), at(f.pool.u, k), f.dq, f.dv,
                                 central_difference_step<S>());
        benchmark::DoNotOptimize(f.dq.data());
        benchmark::ClobberMemory();
      });
  }
}

}  // namespace spatial::bench

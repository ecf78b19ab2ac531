#pragma once
// Benchmarks of the analytical derivatives (derivatives.hpp) and of the finite differences they replace:
// RNEA_derivatives (∂τ/∂q and ∂τ/∂q̇), ABA_derivatives (∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ) and RNEA_derivatives_fd, the same two
// matrices of RNEA by forward differences: 2n + 1 RNEA calls (n + 1 for ∂τ/∂q alone), on the configuration manifold
// for a floating base (q ⊕ h eₖ through `integrate`). Also Minv: H⁻¹ computed directly (minv.hpp).
#include "bench_common.hpp"

#include <spatial/derivatives.hpp>
#include <spatial/minv.hpp>

#include <memory>
#include <string>

namespace spatial::bench {

/// ∂τ/∂q and ∂τ/∂q̇ by forward differences with step h (fixed base). `data.tau` is the base point.
template <class S, class T, class Q, class V, class A, class M>
void rnea_derivatives_fd(const Model<S, T>& model, Data<S, T>& data, const Q& q, const V& v, const A& a, M& dq,
                         M& dv, S h) {
  const typename Data<S, T>::VectorN tau = rnea(model, data, q, v, a);
  Q x = q;
  V y = v;
  for (int k = 0; k < model.size(); ++k) {
    x[k] += h;
    dq.col(k) = (rnea(model, data, x, v, a) - tau) / h;
    x[k] = q[k];
    y[k] += h;
    dv.col(k) = (rnea(model, data, q, y, a) - tau) / h;
    y[k] = v[k];
  }
}

/// The same on a floating base: column k of ∂τ/∂q from integrate(q, h eₖ).
template <class S, class T, class Q, class V, class A, class M>
void rnea_derivatives_fd(const FloatingModel<S, T>& model, FloatingData<S, T>& data, const Q& q, const V& v,
                         const A& a, M& dq, M& dv, S h) {
  const typename FloatingData<S, T>::VectorV tau = rnea(model, data, q, v, a);
  Q x = q;
  V y = v, e = V::Zero(model.nv());
  for (int k = 0; k < model.nv(); ++k) {
    e[k] = h;
    integrate(model, q, e, S(1), x);
    e[k] = S(0);
    dq.col(k) = (rnea(model, data, x, v, a) - tau) / h;
    y[k] += h;
    dv.col(k) = (rnea(model, data, q, y, a) - tau) / h;
    y[k] = v[k];
  }
}

/// Registers RNEA_derivatives, ABA_derivatives, RNEA_derivatives_fd and Minv for `model` (fixed or floating) on the states
/// of `pool` (q, v or qd, u), under `name(algorithm)`.
template <class ModelT, class DataT, class DerivT, class Pool, class Name>
void register_derivatives(const ModelT& model, const Pool& pool, Name&& name) {
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
                        S(std::is_same_v<S, float> ? 1e-3 : 1e-7));
    benchmark::DoNotOptimize(f.dq.data());
    benchmark::ClobberMemory();
  });
}

}  // namespace spatial::bench

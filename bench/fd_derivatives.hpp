#pragma once
// ∂τ/∂q and ∂τ/∂q̇ of RNEA by finite differences: forward (2n + 1 RNEA calls) and central (4n calls), on the
// configuration manifold for a floating base (q ⊕ h eₖ through `integrate`). What the analytical derivatives
// (derivatives.hpp) replace: timed in bench_derivatives.hpp, their accuracy measured by the error study.
#include <spatial/spatial.hpp>

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

/// ∂τ/∂q and ∂τ/∂q̇ by central differences with step h (fixed base): 4n RNEA calls.
template <class S, class T, class Q, class V, class A, class M>
void rnea_derivatives_central(const Model<S, T>& model, Data<S, T>& data, const Q& q, const V& v, const A& a, M& dq,
                              M& dv, S h) {
  Q x = q;
  V y = v;
  for (int k = 0; k < model.size(); ++k) {
    x[k] = q[k] + h;
    dq.col(k) = rnea(model, data, x, v, a);
    x[k] = q[k] - h;
    dq.col(k) = (dq.col(k) - rnea(model, data, x, v, a)) / (S(2) * h);
    x[k] = q[k];
    y[k] = v[k] + h;
    dv.col(k) = rnea(model, data, q, y, a);
    y[k] = v[k] - h;
    dv.col(k) = (dv.col(k) - rnea(model, data, q, y, a)) / (S(2) * h);
    y[k] = v[k];
  }
}

/// Steps of the finite differences: forward √ε, central ∛ε (ε: the scalar's machine epsilon), rounded.
template <class S>
constexpr S forward_difference_step() { return std::is_same_v<S, float> ? S(1e-3) : S(1e-7); }
template <class S>
constexpr S central_difference_step() { return std::is_same_v<S, float> ? S(5e-3) : S(5e-6); }

}  // namespace spatial::bench

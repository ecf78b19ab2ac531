#pragma once
// Fixed-step integrators of q̈ = f(q, q̇) for the test suites and the error study (not part of the installed
// library); by default the passive dynamics q̈ = ABA(q, q̇, τ = 0). State (q, q̇); one step of size h.
//
//   semi-implicit Euler  q̇ ← q̇ + h q̈(q, q̇);  q ← q + h q̇   (symplectic, order 1: bounded energy error O(h))
//   midpoint (RK2)       explicit midpoint rule, order 2
//   RK4                  classic Runge–Kutta, order 4

#include <spatial/spatial.hpp>

namespace spatial::testing {

enum class Integrator { SemiImplicitEuler, Midpoint, RK4 };

inline const char* integrator_name(Integrator m) {
  switch (m) {
    case Integrator::SemiImplicitEuler: return "semi-implicit Euler";
    case Integrator::Midpoint: return "midpoint (RK2)";
    case Integrator::RK4: return "RK4";
  }
  return "?";
}

/// The order p of the method's global error (energy error ∝ hᵖ).
inline int integrator_order(Integrator m) {
  return m == Integrator::SemiImplicitEuler ? 1 : m == Integrator::Midpoint ? 2 : 4;
}

/// Evaluations of the acceleration per step.
inline int integrator_evaluations(Integrator m) {
  return m == Integrator::SemiImplicitEuler ? 1 : m == Integrator::Midpoint ? 2 : 4;
}

/// Advances (q, qd) by one step of size h of q̈ = acc(q, q̇).
template <class S, class V, class Acc>
void integrator_step(Integrator method, Acc&& acc, V& q, V& qd, S h) {
  switch (method) {
    case Integrator::SemiImplicitEuler: {
      qd += h * acc(q, qd);
      q += h * qd;
      break;
    }
    case Integrator::Midpoint: {
      const V a1 = acc(q, qd);
      const V qm = q + (h / S(2)) * qd, vm = qd + (h / S(2)) * a1;
      const V a2 = acc(qm, vm);
      q += h * vm;
      qd += h * a2;
      break;
    }
    case Integrator::RK4: {
      const V k1q = qd, k1v = acc(q, qd);
      const V k2q = qd + (h / S(2)) * k1v, k2v = acc(q + (h / S(2)) * k1q, k2q);
      const V k3q = qd + (h / S(2)) * k2v, k3v = acc(q + (h / S(2)) * k2q, k3q);
      const V k4q = qd + h * k3v, k4v = acc(q + h * k3q, k4q);
      q += (h / S(6)) * (k1q + S(2) * k2q + S(2) * k3q + k4q);
      qd += (h / S(6)) * (k1v + S(2) * k2v + S(2) * k3v + k4v);
      break;
    }
  }
}

/// Advances (q, qd) by one step of size h of the unforced, undamped dynamics, using forward dynamics by ABA.
template <class S, class T, class V>
void integrator_step(Integrator method, const Model<S, T>& model, Data<S, T>& data, V& q, V& qd, S h) {
  const V zero = V::Zero(q.size());
  integrator_step(method, [&](const V& qq, const V& vv) -> V { return aba(model, data, qq, vv, zero); }, q, qd, h);
}

}  // namespace spatial::testing

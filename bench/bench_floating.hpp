#pragma once
/// \file bench_floating.hpp
/// The floating-base bench model, floating27 = `hoap3_floating` (the HOAP-3 free-flying at the pelvis: nq = 28,
/// nv = 27), and its input pool: the root anywhere in a 1 m box with a uniformly random orientation, the joints
/// uniform within their URDF limits, v, v̇ and τ uniform in [−1, 1].
/// Shared by bench_floating (spatial) and bench_pinocchio (the peer), so both time the same states.

#include "bench_models.hpp"

#include <spatial/models/hoap3_floating.hpp>

#include <random>
#include <vector>

namespace spatial::bench {

using Floating27Tree = models::hoap3_floating::Tree;

/// The floating bench model (compile-time tree).
inline const FloatingModel<double, Floating27Tree>& floating27() {
  static const auto m = models::hoap3_floating::floating_model<double>();
  return m;
}

/// The frame whose Jacobian the benchmarks time: the left sole (a fixed frame on the last body of the left leg).
inline int floating27_frame() { return models::hoap3_floating::frame_index("L_SOLE"); }

template <class S, int NQ = Eigen::Dynamic, int NV = Eigen::Dynamic>
struct FloatingPool {
  std::vector<Eigen::Matrix<S, NQ, 1>> q;
  std::vector<Eigen::Matrix<S, NV, 1>> v, u;  ///< u: v̇ for inverse dynamics, τ for forward dynamics
  int next = 0;
  int size() const { return static_cast<int>(q.size()); }
  int take() {
    next = next + 1 == size() ? 0 : next + 1;
    return next;
  }
  template <class T, int MQ = NQ, int MV = NV>
  FloatingPool<T, MQ, MV> cast() const {
    FloatingPool<T, MQ, MV> out;
    for (std::size_t k = 0; k < q.size(); ++k) {
      out.q.push_back(q[k].template cast<T>());
      out.v.push_back(v[k].template cast<T>());
      out.u.push_back(u[k].template cast<T>());
    }
    return out;
  }
};

/// 256 states of floating27, generated once in double.
inline const FloatingPool<double>& floating_pool() {
  static const FloatingPool<double> pool = [] {
    namespace fb = models::hoap3_floating;
    FloatingPool<double> p;
    const InputRange range = limit_range(fb::lower, fb::upper);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto& m = floating27();
    for (int k = 0; k < 256; ++k) {
      p.q.push_back(random_configuration(m, range.lower, range.upper, rng));
      Eigen::VectorXd v(m.nv()), u(m.nv());
      for (int i = 0; i < m.nv(); ++i) v[i] = unit(rng), u[i] = unit(rng);
      p.v.push_back(v);
      p.u.push_back(u);
    }
    return p;
  }();
  return pool;
}

}  // namespace spatial::bench

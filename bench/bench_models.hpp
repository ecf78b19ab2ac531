#pragma once
/// \file bench_models.hpp
/// The models every benchmark, peer comparison and error study runs on, and the random inputs they share.
///
/// To benchmark another model, add one line to `bench_models()` below: a name and a `Model<double, Tree>` (a
/// compile-time tree; its run-time twin is derived from it). Every binary picks it up: bench_algorithms (all
/// algorithms, double and float, compile-time and run-time tree), bench_kdl and bench_pinocchio (the peers, built
/// from the very same model), error_study (accuracy against long double) and the report.
///
/// The models are the reference study's HOAP-3 models, generated at build time from urdf/ (src/models/, target
/// spatial::hoap3_models), with inputs drawn within each joint's URDF limits:
///  - stance21:  `hoap3_stance_right`, the whole body in single support on the right foot (21 DoF; head and wrists
///               locked), rooted at the right sole;
///  - torso8:    `hoap3_torso`, the chest with both arms (8 DoF), rooted at the chest;
///  - pendulum2: `hoap3_double_pendulum`, the study's double inverted pendulum (2 DoF; no URDF limits: ±π).

// With -march=native on an AVX-512 machine, GCC 12 reports false positives (uninitialized, array bounds,
// string-op over-read) inside its own AVX-512 intrinsic headers when Eigen's packet code is inlined: in Eigen's
// dynamic-size kernels (the run-time models' dense Cholesky, long double references) and all over Pinocchio. The
// diagnostics are located in the intrinsic headers that Eigen includes, so ignoring them around Eigen's first
// inclusion silences exactly those and nothing in our code.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Warray-bounds"
#if __GNUC__ >= 11
#pragma GCC diagnostic ignored "-Wstringop-overread"
#endif
#endif
#include <Eigen/Core>
#include <Eigen/Cholesky>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <spatial/spatial.hpp>

#include "support/random_model.hpp"

#include <spatial/models/hoap3_double_pendulum.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_torso.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace spatial::bench {

inline constexpr JointType Rz = JointType::RevoluteZ;

namespace detail {
template <int N, class Seq = std::make_integer_sequence<int, N>>
struct ChainTreeOf;
template <int N, int... I>
struct ChainTreeOf<N, std::integer_sequence<int, I...>> {
  using type = Tree<Parents<(I - 1)...>, Joints<static_cast<JointType>(I % 3)...>>;
};
template <int N, class Seq = std::make_integer_sequence<int, N>>
struct BinaryTreeOf;
template <int N, int... I>
struct BinaryTreeOf<N, std::integer_sequence<int, I...>> {
  using type = Tree<Parents<(I == 0 ? -1 : (I - 1) / 2)...>, Joints<static_cast<JointType>(I % 3)...>>;
};
}  // namespace detail

// Joint types cycle RevoluteX, RevoluteY, RevoluteZ (enumerators 0, 1, 2).
static_assert(static_cast<int>(JointType::RevoluteX) == 0 && static_cast<int>(JointType::RevoluteZ) == 2);

/// An n-body chain (body i's parent is i-1), revolute joints cycling about x, y, z.
template <int N>
using ChainTree = typename detail::ChainTreeOf<N>::type;
/// A balanced binary tree of n bodies (body i's parent is (i-1)/2), revolute joints cycling about x, y, z.
template <int N>
using BinaryTree = typename detail::BinaryTreeOf<N>::type;

/// A run-time model with the topology and joint types of `TreeT` and the random geometry and inertias of
/// `spatial::testing::random_bodies(n, …, seed)`.
template <class TreeT>
Model<double> random_runtime_model(unsigned seed) {
  std::vector<testing::RandomBody> bodies = testing::random_bodies(TreeT::size, testing::Shape::Chain, seed, false);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].parent = TreeT::parent[i];
    bodies[i].type = TreeT::joint[i];
    switch (bodies[i].type) {
      case JointType::RevoluteX: case JointType::PrismaticX: bodies[i].axis = Vector3<double>::UnitX(); break;
      case JointType::RevoluteY: case JointType::PrismaticY: bodies[i].axis = Vector3<double>::UnitY(); break;
      case JointType::RevoluteZ: case JointType::PrismaticZ: bodies[i].axis = Vector3<double>::UnitZ(); break;
      default: break;
    }
  }
  return testing::build_model(bodies);
}
template <class TreeT>
Model<double, TreeT> random_model(unsigned seed) {
  return Model<double, TreeT>::from(random_runtime_model<TreeT>(seed));
}

/// Where the random inputs are drawn: qᵢ uniform in [lowerᵢ, upperᵢ]; q̇, q̈ and τ uniform in [−1, 1].
struct InputRange {
  Eigen::VectorXd lower, upper;
};
/// ±1 rad for every joint: for models without joint limits (random trees).
inline InputRange unit_range(int n) { return {Eigen::VectorXd::Constant(n, -1.0), Eigen::VectorXd::Constant(n, 1.0)}; }
/// A generated model's URDF position limits; a joint without limits (±kInf) gets [−π, π].
template <std::size_t N>
InputRange limit_range(const std::array<double, N>& lower, const std::array<double, N>& upper) {
  InputRange r{Eigen::VectorXd(static_cast<Eigen::Index>(N)), Eigen::VectorXd(static_cast<Eigen::Index>(N))};
  const double pi = 3.14159265358979323846;
  for (std::size_t i = 0; i < N; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    r.lower[k] = std::isfinite(lower[i]) ? lower[i] : -pi;
    r.upper[k] = std::isfinite(upper[i]) ? upper[i] : pi;
  }
  return r;
}

/// One entry of the model list.
template <class TreeT>
struct BenchModel {
  using tree_type = TreeT;
  std::string name;
  Model<double, TreeT> model;
  InputRange range;
};
template <class TreeT>
BenchModel<TreeT> bench_model(std::string name, Model<double, TreeT> model) {
  InputRange r = unit_range(model.size());
  return {std::move(name), std::move(model), std::move(r)};
}
template <class TreeT>
BenchModel<TreeT> bench_model(std::string name, Model<double, TreeT> model, InputRange range) {
  return {std::move(name), std::move(model), std::move(range)};
}

/// The generated HOAP-3 models' topologies (compile-time trees).
using Stance21Tree = models::hoap3_stance_right::Tree;
using Torso8Tree = models::hoap3_torso::Tree;
using Pendulum2Tree = models::hoap3_double_pendulum::Tree;

/// THE LIST of bench models. Adding a model is one line here.
inline const auto& bench_models() {
  namespace stance = models::hoap3_stance_right;
  namespace torso = models::hoap3_torso;
  namespace pendulum = models::hoap3_double_pendulum;
  static const auto models = std::make_tuple(  //
      bench_model("stance21", stance::model(), limit_range(stance::lower, stance::upper)),
      bench_model("torso8", torso::model(), limit_range(torso::lower, torso::upper)),
      bench_model("pendulum2", pendulum::model(), limit_range(pendulum::lower, pendulum::upper)));
  return models;
}

/// Calls f(entry) for every bench model (entry is a `BenchModel<Tree>`).
template <class F>
void for_each_bench_model(F&& f) {
  std::apply([&](const auto&... m) { (f(m), ...); }, bench_models());
}

/// A pool of random states, generated once in double (the same numbers for every scalar type and every peer), so
/// that each call of a benchmark takes a fresh state and nothing is cached between calls.
template <class S, int N = Eigen::Dynamic>
struct InputPool {
  using Vector = Eigen::Matrix<S, N, 1>;
  std::vector<Vector> q, qd, u;  ///< u: q̈ for inverse dynamics, τ for forward dynamics
  int next = 0;

  InputPool() = default;
  InputPool(const InputRange& range, int size = 256, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto n = range.lower.size();
    for (int k = 0; k < size; ++k) {
      Vector a(n), b(n), c(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        a[i] = S(range.lower[i] + (range.upper[i] - range.lower[i]) * unit(rng));
        b[i] = S(2.0 * unit(rng) - 1.0);
        c[i] = S(2.0 * unit(rng) - 1.0);
      }
      q.push_back(a);
      qd.push_back(b);
      u.push_back(c);
    }
  }
  /// The same numbers in another scalar type or vector type.
  template <class T, int M = N>
  InputPool<T, M> cast() const {
    InputPool<T, M> out;
    for (std::size_t k = 0; k < q.size(); ++k) {
      out.q.push_back(q[k].template cast<T>());
      out.qd.push_back(qd[k].template cast<T>());
      out.u.push_back(u[k].template cast<T>());
    }
    return out;
  }
  int size() const { return static_cast<int>(q.size()); }
  /// Index of the next state (cycling through the pool).
  int take() {
    next = next + 1 == size() ? 0 : next + 1;
    return next;
  }
};

/// Forward dynamics by CRBA and a DENSE Cholesky factorisation (Eigen's LLT of the full H): the baseline that the
/// tree-sparse LTDL of `forward_dynamics_crba` is measured against, in time and in error. Uses only the public API,
/// so bias forces and CRBA each compute their own joint transforms (forward_dynamics_crba shares them). `llt` is
/// kept by the caller so that run-time trees do not allocate per call. Right-hand side in data.tmp, result in
/// data.qdd.
template <class S, class TreeT, class Q, class QD, class Tau>
const typename Data<S, TreeT>::VectorN& forward_dynamics_dense(const Model<S, TreeT>& model, Data<S, TreeT>& data,
                                                               Eigen::LLT<typename Data<S, TreeT>::MatrixN>& llt,
                                                               const Eigen::MatrixBase<Q>& q,
                                                               const Eigen::MatrixBase<QD>& qd,
                                                               const Eigen::MatrixBase<Tau>& tau) {
  data.tmp = tau - bias_forces(model, data, q, qd);
  llt.compute(crba(model, data, q));
  data.qdd = data.tmp;
  llt.solveInPlace(data.qdd);
  return data.qdd;
}

/// Name of a scalar type in benchmark names and reports.
template <class S>
constexpr const char* scalar_name() {
  if constexpr (std::is_same_v<S, float>) return "float";
  else if constexpr (std::is_same_v<S, double>) return "double";
  else return "long double";
}

/// Benchmark names are "<implementation>/<algorithm>/<model>/<scalar>/<tree>", e.g.
/// "spatial/RNEA/stance21/double/static"; tools/report.py parses them. tree is "static" (compile-time tree),
/// "runtime" (run-time tree) or "-" (peers).
inline std::string bench_name(const std::string& impl, const std::string& algorithm, const std::string& model,
                              const std::string& scalar, const std::string& tree) {
  return impl + "/" + algorithm + "/" + model + "/" + scalar + "/" + tree;
}

}  // namespace spatial::bench

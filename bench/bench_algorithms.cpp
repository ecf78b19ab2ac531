// Run time of every algorithm on a 21-body tree with the topology of the HOAP-3 single-support model (a 7-body
// chain from the stance foot to the waist, then two 4-body arms and a 6-body leg), revolute joints about each
// body's z axis as in the reference study, with random geometry and inertias. Compile-time and run-time trees, in
// double and float. Each iteration takes the next state from a pre-generated pool, so nothing is cached.
#include <spatial/spatial.hpp>

#include "support/random_model.hpp"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace {
using namespace spatial;
using spatial::testing::RandomBody;

constexpr JointType Rz = JointType::RevoluteZ;
// Parent array of the study's 21-DoF single-support model (0-based; -1 = the stance foot).
using Stance21 = Tree<Parents<-1, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 6, 11, 12, 13, 6, 15, 16, 17, 18, 19>,
                      Joints<Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz, Rz>>;

Model<double> stance21_runtime() {
  std::vector<RandomBody> bodies = spatial::testing::random_bodies(21, spatial::testing::Shape::Chain, 2026, false);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].parent = Stance21::parent[i];
    bodies[i].type = Rz;
    bodies[i].axis = Vector3<double>::UnitZ();
  }
  return spatial::testing::build_model(bodies);
}

template <class S, class T>
struct Fixture {
  Model<S, T> model;
  Data<S, T> data;
  static constexpr int kPool = 256;
  std::vector<Eigen::Matrix<S, Model<S, T>::NB, 1>> q, qd, qdd;
  int next = 0;

  explicit Fixture(const Model<S, T>& m) : model(m), data(model) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int n = model.size();
    for (int k = 0; k < kPool; ++k) {
      Eigen::Matrix<S, Model<S, T>::NB, 1> a(n), b(n), c(n);
      for (int i = 0; i < n; ++i) {
        a[i] = S(u(rng));
        b[i] = S(u(rng));
        c[i] = S(u(rng));
      }
      q.push_back(a);
      qd.push_back(b);
      qdd.push_back(c);
    }
  }
  int take() {
    next = (next + 1) % kPool;
    return next;
  }
};

template <class S, class T>
Fixture<S, T>& fixture() {
  static Fixture<S, T> f = [] {
    const Model<double> rt = stance21_runtime();
    if constexpr (is_static_tree_v<T>) return Fixture<S, T>(Model<double, T>::from(rt).template cast<S>());
    else return Fixture<S, T>(rt.template cast<S>());
  }();
  return f;
}

template <class S, class T>
void BM_RNEA(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    benchmark::DoNotOptimize(rnea(f.model, f.data, f.q[k], f.qd[k], f.qdd[k]).data());
  }
}
template <class S, class T>
void BM_BiasForces(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    benchmark::DoNotOptimize(bias_forces(f.model, f.data, f.q[k], f.qd[k]).data());
  }
}
template <class S, class T>
void BM_GravityTorques(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    benchmark::DoNotOptimize(gravity_torques(f.model, f.data, f.q[k]).data());
  }
}
template <class S, class T>
void BM_CRBA(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    benchmark::DoNotOptimize(crba(f.model, f.data, f.q[k]).data());
  }
}
template <class S, class T>
void BM_FD_CRBA_LTDL(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    benchmark::DoNotOptimize(forward_dynamics_crba(f.model, f.data, f.q[k], f.qd[k], f.qdd[k]).data());
  }
}
template <class S, class T>
void BM_ABA(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    benchmark::DoNotOptimize(aba(f.model, f.data, f.q[k], f.qd[k], f.qdd[k]).data());
  }
}
template <class S, class T>
void BM_ForwardKinematics(benchmark::State& st) {
  auto& f = fixture<S, T>();
  for (auto _ : st) {
    const int k = f.take();
    forward_kinematics(f.model, f.data, f.q[k]);
    benchmark::DoNotOptimize(f.data.X_base.back().r.data());
  }
}

#define SPATIAL_BENCH_ALL(S, T, LABEL)                                       \
  BENCHMARK_TEMPLATE(BM_RNEA, S, T)->Name("RNEA/" LABEL);                    \
  BENCHMARK_TEMPLATE(BM_BiasForces, S, T)->Name("BiasForces/" LABEL);        \
  BENCHMARK_TEMPLATE(BM_GravityTorques, S, T)->Name("GravityTorques/" LABEL);\
  BENCHMARK_TEMPLATE(BM_CRBA, S, T)->Name("CRBA/" LABEL);                    \
  BENCHMARK_TEMPLATE(BM_FD_CRBA_LTDL, S, T)->Name("FD_CRBA_LTDL/" LABEL);    \
  BENCHMARK_TEMPLATE(BM_ABA, S, T)->Name("ABA/" LABEL);                      \
  BENCHMARK_TEMPLATE(BM_ForwardKinematics, S, T)->Name("FK/" LABEL);

SPATIAL_BENCH_ALL(double, Stance21, "stance21_static/double")
SPATIAL_BENCH_ALL(float, Stance21, "stance21_static/float")
SPATIAL_BENCH_ALL(double, DynamicTree, "stance21_runtime/double")

}  // namespace

BENCHMARK_MAIN();

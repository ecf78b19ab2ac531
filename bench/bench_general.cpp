// Trees of multi-DoF joints (general.hpp) in double, timed beside Pinocchio, names as in bench_models.hpp
// ("<impl>/<algorithm>/<model>/double/<tree>", tree "general" for a `GeneralModel`):
//  - ball38: a humanoid whose hips, ankles, shoulders, wrists and neck are spherical joints (free-flyer pelvis, waist
//    revolute, spherical neck, and per limb spherical – revolute – spherical; nq = 48, nv = 38), as a `GeneralModel`
//    and as the Pinocchio model of the same numbers (peers/pinocchio_peer.hpp's make_pinocchio_general:
//    JointModelSpherical, JointModelFreeFlyer). Before timing, RNEA, CRBA and ABA are checked against Pinocchio's
//    on its 32 states (abort on a mismatch).
//  - stance21 and floating27 as `GeneralModel`s (general_model(...) of their run-time twins): what the general tree
//    costs where the one-DoF trees apply (report: beside Pinocchio's and the run-time tree's times of bench_pinocchio
//    and bench_algorithms / bench_floating, which time other states of the same models).
// RNEA, CRBA and ABA, states cycled. Built with Pinocchio (bench/CMakeLists.txt); scripts/main.sh runs it, and
// scripts/test.sh runs its peer check (--benchmark_filter=^$).
#include "bench_models.hpp"  // first: it silences GCC's false positives in the AVX-512 headers around Eigen
#include "peers/peer_check.hpp"
#include "peers/pinocchio_peer.hpp"

#include <spatial/general.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {
using namespace spatial;
using Vec = Eigen::VectorXd;
using V3 = Vector3<double>;

/// The ball-jointed humanoid, bodies in depth-first order (Pinocchio's requirement); masses and placements of a
/// 1.5 m, 60 kg person, inertias of boxes, each body's centre of mass along its segment.
GeneralModel<double> ball38() {
  GeneralModel<double> m;
  const auto box = [](double mass, const V3& size, const V3& com) {
    const V3 s2 = size.cwiseProduct(size);
    const Eigen::Matrix3d Ic = (mass / 12.0 * V3(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
    return Inertia<double>::from_com(mass, com, Ic);
  };
  const auto add = [&](int parent, const GeneralJoint<double>& j, const V3& at, const Inertia<double>& I,
                       const std::string& name) {
    return m.add_body(parent, j, xlt(at), I, name + "_joint", name);
  };
  const auto sph = GeneralJoint<double>::spherical();
  const auto rev = [](JointType t) { return GeneralJoint<double>::one_dof(t); };
  const int pelvis = add(-1, GeneralJoint<double>::free_flyer(), V3::Zero(), box(10, V3(0.3, 0.2, 0.15), V3::Zero()),
                         "pelvis");
  for (int side : {1, -1}) {  // legs: hip (ball), knee (revolute y), ankle (ball)
    const std::string s = side > 0 ? "l_" : "r_";
    const int thigh = add(pelvis, sph, V3(0, 0.1 * side, -0.08), box(7, V3(0.12, 0.12, 0.4), V3(0, 0, -0.2)),
                          s + "thigh");
    const int shank = add(thigh, rev(JointType::RevoluteY), V3(0, 0, -0.4), box(3.5, V3(0.1, 0.1, 0.4), V3(0, 0, -0.2)),
                          s + "shank");
    add(shank, sph, V3(0, 0, -0.4), box(1, V3(0.22, 0.09, 0.06), V3(0.04, 0, -0.04)), s + "foot");
  }
  const int torso = add(pelvis, rev(JointType::RevoluteZ), V3(0, 0, 0.1), box(18, V3(0.25, 0.35, 0.45), V3(0, 0, 0.22)),
                        "torso");
  add(torso, sph, V3(0, 0, 0.48), box(4.5, V3(0.18, 0.15, 0.22), V3(0, 0, 0.1)), "head");
  for (int side : {1, -1}) {  // arms: shoulder (ball), elbow (revolute y), wrist (ball)
    const std::string s = side > 0 ? "l_" : "r_";
    const int upper = add(torso, sph, V3(0, 0.2 * side, 0.4), box(2, V3(0.08, 0.08, 0.28), V3(0, 0, -0.14)),
                          s + "upper_arm");
    const int fore = add(upper, rev(JointType::RevoluteY), V3(0, 0, -0.28), box(1.2, V3(0.07, 0.07, 0.25),
                                                                                 V3(0, 0, -0.12)),
                         s + "forearm");
    add(fore, sph, V3(0, 0, -0.25), box(0.4, V3(0.08, 0.03, 0.15), V3(0, 0, -0.07)), s + "hand");
  }
  return m;
}

/// A model, its data and 32 random states (quaternions uniform, other coordinates and v, u in [−1, 1]).
struct Fixture {
  GeneralModel<double> model;
  GeneralData<double> data{model};
  std::vector<Vec> q, v, u;
  int next = 0;
  explicit Fixture(GeneralModel<double> m) : model(std::move(m)) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> x(-1, 1);
    const Vec lo = Vec::Constant(model.nq(), -1), hi = Vec::Constant(model.nq(), 1);
    for (int k = 0; k < 32; ++k) {
      q.push_back(random_configuration(model, lo, hi, rng));
      Vec a(model.nv()), b(model.nv());
      for (int c = 0; c < model.nv(); ++c) a[c] = x(rng), b[c] = x(rng);
      v.push_back(a);
      u.push_back(b);
    }
  }
  std::size_t take() { return std::size_t(next = next + 1 == 32 ? 0 : next + 1); }
};
Fixture& ball() {
  static Fixture f(ball38());
  return f;
}
struct PinFixture {
  pinocchio::Model pm = peers::make_pinocchio_general(ball().model);
  pinocchio::Data pd{pm};
};
PinFixture& pin() {
  static PinFixture f;
  return f;
}
Fixture& stance() {
  static Fixture f(general_model(models::hoap3_stance_right::model<double>().to_runtime()));
  return f;
}
Fixture& floating() {
  static Fixture f(general_model(models::hoap3_floating::floating_model<double>().to_runtime()));
  return f;
}

void check() {
  Fixture& f = ball();
  PinFixture& p = pin();
  if (p.pm.nq != f.model.nq() || p.pm.nv != f.model.nv()) {
    std::fprintf(stderr, "peer check FAILED: Pinocchio's ball38 has nq %d nv %d, ours %d %d\n", p.pm.nq, p.pm.nv,
                 f.model.nq(), f.model.nv());
    std::abort();
  }
  peers::PeerCheck tau{"ball38 RNEA (spherical joints)", 1e-12}, mass{"ball38 CRBA (spherical joints)", 1e-12},
      fd{"ball38 ABA (spherical joints)", 1e-10};
  for (std::size_t s = 0; s < 32; ++s) {
    tau.compare(pinocchio::rnea(p.pm, p.pd, f.q[s], f.v[s], f.u[s]), rnea(f.model, f.data, f.q[s], f.v[s], f.u[s]));
    Eigen::MatrixXd M = pinocchio::crba(p.pm, p.pd, f.q[s]);
    M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
    mass.compare(M, crba(f.model, f.data, f.q[s]));
    fd.compare(pinocchio::aba(p.pm, p.pd, f.q[s], f.v[s], f.u[s]), aba(f.model, f.data, f.q[s], f.v[s], f.u[s]));
  }
  tau.report();
  mass.report();
  fd.report();
}

void ours(benchmark::State& st, Fixture& f, int algorithm) {
  for (auto _ : st) {
    const std::size_t k = f.take();
    if (algorithm == 0) benchmark::DoNotOptimize(rnea(f.model, f.data, f.q[k], f.v[k], f.u[k]).data());
    else if (algorithm == 1) benchmark::DoNotOptimize(crba(f.model, f.data, f.q[k]).data());
    else benchmark::DoNotOptimize(aba(f.model, f.data, f.q[k], f.v[k], f.u[k]).data());
  }
}
void pinocchio_ball(benchmark::State& st, int algorithm) {
  Fixture& f = ball();
  PinFixture& p = pin();
  for (auto _ : st) {
    const std::size_t k = f.take();
    if (algorithm == 0) benchmark::DoNotOptimize(pinocchio::rnea(p.pm, p.pd, f.q[k], f.v[k], f.u[k]).data());
    else if (algorithm == 1) benchmark::DoNotOptimize(pinocchio::crba(p.pm, p.pd, f.q[k]).data());
    else benchmark::DoNotOptimize(pinocchio::aba(p.pm, p.pd, f.q[k], f.v[k], f.u[k]).data());
  }
}

void register_all() {
  const char* names[] = {"RNEA", "CRBA", "ABA"};
  for (int a = 0; a < 3; ++a) {
    const std::string alg = names[a];
    benchmark::RegisterBenchmark(("spatial/" + alg + "/ball38/double/general").c_str(),
                                 [a](benchmark::State& st) { ours(st, ball(), a); });
    benchmark::RegisterBenchmark(("pinocchio/" + alg + "/ball38/double/-").c_str(),
                                 [a](benchmark::State& st) { pinocchio_ball(st, a); });
    benchmark::RegisterBenchmark(("spatial/" + alg + "/stance21/double/general").c_str(),
                                 [a](benchmark::State& st) { ours(st, stance(), a); });
    benchmark::RegisterBenchmark(("spatial/" + alg + "/floating27/double/general").c_str(),
                                 [a](benchmark::State& st) { ours(st, floating(), a); });
  }
}
}  // namespace

int main(int argc, char** argv) {
  check();
  register_all();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

// Instruction counts of the stance21 algorithms under callgrind (docs/performance.md, "AVX2 kernels"): calls crba,
// rnea, aba, forward_dynamics_crba and gravity_torques N times on random states, each from its own non-inlined
// wrapper so that callgrind_annotate --inclusive=yes gives a count per call. Valgrind has no AVX-512, so build with
// -march=x86-64-v3 (AVX2 path) or add -DSPATIAL_NO_SIMD (scalar path):
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_algorithms.cpp -o /tmp/cg
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cg.out /tmp/cg 1000 &&
//     callgrind_annotate --inclusive=yes /tmp/cg.out | grep do_
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <cstdio>
#include <cstdlib>
#include <random>
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
using VN = Eigen::Matrix<double, 21, 1>;
__attribute__((noinline)) void do_crba(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q) { crba(m, d, q); }
__attribute__((noinline)) void do_rnea(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q, const VN& qd) { rnea(m, d, q, qd, qd); }
__attribute__((noinline)) void do_aba(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q, const VN& qd) { aba(m, d, q, qd, qd); }
__attribute__((noinline)) void do_fd(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q, const VN& qd) { forward_dynamics_crba(m, d, q, qd, qd); }
__attribute__((noinline)) void do_grav(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q) { gravity_torques(m, d, q); }
int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  auto model = M::model();
  Data<double, M::Tree> d(model);
  std::vector<VN> pool(64);
  for (auto& q : pool) q.setRandom();
  double s = 0;
  for (int t = 0; t < n; ++t) { const VN& q = pool[t & 63]; const VN& qd = pool[(t + 7) & 63];
    do_crba(model, d, q); s += d.H(3, 2);
    do_rnea(model, d, q, qd); s += d.tau[0];
    do_aba(model, d, q, qd); s += d.qdd[0];
    do_fd(model, d, q, qd); s += d.qdd[0];
    do_grav(model, d, q); s += d.tau[0]; }
  std::printf("%g\n", s);
}

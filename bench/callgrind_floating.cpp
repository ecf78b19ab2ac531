// Instruction counts of the floating-base algorithms on hoap3_floating (floating27) under callgrind, next to the
// same tree with a fixed base (do_f*: floating, do_t*: the tree alone; do_fag: the centroidal momentum matrix; do_fjj:
// every joint's Jacobian, compute_joint_jacobians).
// docs/performance.md, "Floating base".
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_floating.cpp -o /tmp/cgf
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cgf.out /tmp/cgf 500 &&
//     callgrind_annotate --inclusive=yes /tmp/cgf.out | grep do_
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <cstdio>
#include <random>
using namespace spatial;
namespace F = spatial::models::hoap3_floating;
using FM = FloatingModel<double, F::Tree>;
using FD = FloatingData<double, F::Tree>;
using VQ = Eigen::Matrix<double, 28, 1>;
using VV = Eigen::Matrix<double, 27, 1>;
using VJ = Eigen::Matrix<double, 21, 1>;
__attribute__((noinline)) void do_fcrba(const FM& m, FD& d, const VQ& q) { crba(m, d, q); }
__attribute__((noinline)) void do_tcrba(const FM& m, FD& d, const VJ& q) { crba(m.tree(), d.tree, q); }
__attribute__((noinline)) void do_frnea(const FM& m, FD& d, const VQ& q, const VV& v) { rnea(m, d, q, v, v); }
__attribute__((noinline)) void do_trnea(const FM& m, FD& d, const VJ& q, const VJ& v) { rnea(m.tree(), d.tree, q, v, v); }
__attribute__((noinline)) void do_faba(const FM& m, FD& d, const VQ& q, const VV& v) { aba(m, d, q, v, v); }
__attribute__((noinline)) void do_taba(const FM& m, FD& d, const VJ& q, const VJ& v) { aba(m.tree(), d.tree, q, v, v); }
__attribute__((noinline)) void do_ffd(const FM& m, FD& d, const VQ& q, const VV& v) { forward_dynamics_crba(m, d, q, v, v); }
__attribute__((noinline)) void do_fag(const FM& m, FD& d, const VQ& q, Eigen::Matrix<double, 6, 27>& A) {
  centroidal_momentum_matrix(m, d, q, A);
}
__attribute__((noinline)) void do_fjj(const FM& m, FD& d, const VQ& q) { compute_joint_jacobians(m, d, q); }
__attribute__((noinline)) void do_tfd(const FM& m, FD& d, const VJ& q, const VJ& v) { forward_dynamics_crba(m.tree(), d.tree, q, v, v); }
int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  const FM m = F::floating_model();
  FD d(m);
  std::vector<VQ> qs(64); std::vector<VV> vs(64);
  std::mt19937 rng(1);
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(21, -1), hi = -lo;
  for (auto& q : qs) q = random_configuration(m, lo, hi, rng);
  for (auto& v : vs) v.setRandom();
  Eigen::Matrix<double, 6, 27> A;
  double s = 0;
  for (int t = 0; t < n; ++t) { const VQ& q = qs[t & 63]; const VV& v = vs[(t + 7) & 63];
    const VJ qj = q.tail<21>(), vj = v.tail<21>();
    do_fcrba(m, d, q); s += d.H(3, 2); do_tcrba(m, d, qj); s += d.tree.H(3, 2);
    do_frnea(m, d, q, v); s += d.tau[0]; do_trnea(m, d, qj, vj); s += d.tree.tau[0];
    do_faba(m, d, q, v); s += d.qdd[0]; do_taba(m, d, qj, vj); s += d.tree.qdd[0];
    do_ffd(m, d, q, v); s += d.qdd[0]; do_tfd(m, d, qj, vj); s += d.tree.qdd[0];
    do_fag(m, d, q, A); s += A.sum();
    do_fjj(m, d, q); s += d.J(3, 2); }
  std::printf("%g\n", s);
}

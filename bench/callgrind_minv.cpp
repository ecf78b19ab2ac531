// Instruction counts of inverse_inertia (minv.hpp) under callgrind, as quoted in docs/performance.md ("Derivatives
// and H⁻¹", 2026-12-03): stance21 as a compile-time and as a run-time tree, and hoap3_floating, each from its own
// non-inlined wrapper (N calls on random states). Valgrind has no AVX-512, so build with -march=x86-64-v3:
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_minv.cpp -o /tmp/cg_minv
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cg_minv.out /tmp/cg_minv 500 &&
//     callgrind_annotate --inclusive=yes /tmp/cg_minv.out | grep do_minv     (÷ 500 for a count per call)
#include <spatial/spatial.hpp>
#include <spatial/minv.hpp>
#include <spatial/derivatives.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <cstdio>
#include <cstdlib>
#include <vector>
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
namespace F = spatial::models::hoap3_floating;
using CM = decltype(M::model());
using CD = Data<double, M::Tree>;
using RM = Model<double, DynamicTree>;
using RD = Data<double, DynamicTree>;
using FM = decltype(F::model());
__attribute__((noinline)) void do_minv_ct(const CM& m, CD& d, MinvData<double, M::Tree>& md, const Eigen::Matrix<double,21,1>& q) { inverse_inertia(m, d, md, q); }
__attribute__((noinline)) void do_minv_rt(const RM& m, RD& d, MinvData<double>& md, const Eigen::VectorXd& q) { inverse_inertia(m, d, md, q); }
template <class FMm, class FD, class FMD, class Q>
__attribute__((noinline)) void do_minv_fl(const FMm& m, FD& d, FMD& md, const Q& q) { inverse_inertia(m, d, md, q); }
int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  auto cm = M::model(); CD cd(cm); MinvData<double, M::Tree> cmd(cm);
  auto rm = cm.to_runtime(); RD rd(rm); MinvData<double> rmd(rm);
  auto fm = F::floating_model(); FloatingData<double, F::Tree> fd(fm); FloatingMinvData<double, F::Tree> fmd(fm);
  std::vector<Eigen::Matrix<double,21,1>> pool(64);
  for (auto& q : pool) q.setRandom();
  auto qf = neutral(fm); 
  double s = 0;
  for (int t = 0; t < n; ++t) { const auto& q = pool[t & 63]; Eigen::VectorXd qr = q;
    do_minv_ct(cm, cd, cmd, q); s += cmd.Minv(3, 2);
    do_minv_rt(rm, rd, rmd, qr); s += rmd.Minv(3, 2);
    qf.tail(21) = q; do_minv_fl(fm, fd, fmd, qf); s += fmd.Minv(3,2); }
  std::printf("%g\n", s);
}

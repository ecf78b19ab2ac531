// Instruction counts of the AVX2 first passes shared through simd.hpp's base_transform / transformed_inertia:
// stance21 CRBA, forward kinematics and H⁻¹ (inverse_inertia), compile-time and run-time tree, each from its own
// non-inlined wrapper (the review of 2026-12-03, docs/performance.md). Standalone, not in the build:
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_first_pass.cpp -o /tmp/cg_fp
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cg_fp.out /tmp/cg_fp 500 &&
//     callgrind_annotate --inclusive=yes /tmp/cg_fp.out | grep "=> .*do_"     (÷ 500 for a count per call)
// The printed checksum must not change when the passes are only restructured.
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <cstdio>
#include <cstdlib>
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
using VN = Eigen::Matrix<double, 21, 1>;
__attribute__((noinline)) void do_crba(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q) { crba(m, d, q); }
__attribute__((noinline)) void do_crba_rt(const Model<double>& m, Data<double>& d, const Eigen::VectorXd& q) { crba(m, d, q); }
__attribute__((noinline)) void do_fk(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, const VN& q) { forward_kinematics(m, d, q); }
__attribute__((noinline)) void do_fk_rt(const Model<double>& m, Data<double>& d, const Eigen::VectorXd& q) { forward_kinematics(m, d, q); }
__attribute__((noinline)) void do_minv(const Model<double, M::Tree>& m, Data<double, M::Tree>& d, MinvData<double, M::Tree>& md, const VN& q) { inverse_inertia(m, d, md, q); }
__attribute__((noinline)) void do_minv_rt(const Model<double>& m, Data<double>& d, MinvData<double>& md, const Eigen::VectorXd& q) { inverse_inertia(m, d, md, q); }
int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  auto model = M::model(); Data<double, M::Tree> d(model); MinvData<double, M::Tree> md(model);
  auto rt = model.to_runtime(); Data<double> drt(rt); MinvData<double> mdr(rt);
  double s = 0;
  VN q = VN::Random(); Eigen::VectorXd qx = q;
  for (int t = 0; t < n; ++t) {
    q[t % 21] += 1e-3; qx[t % 21] += 1e-3;
    do_crba(model, d, q); s += d.H(3, 2);
    do_crba_rt(rt, drt, qx); s += drt.H(3, 2);
    do_fk(model, d, q); s += d.X_base[20].r[0];
    do_fk_rt(rt, drt, qx); s += drt.X_base[20].r[0];
    do_minv(model, d, md, q); s += md.Minv(3, 2);
    do_minv_rt(rt, drt, mdr, qx); s += mdr.Minv(3, 2);
  }
  std::printf("%.12g\n", s);
}

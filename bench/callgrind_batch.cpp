// Instruction counts of the batched algorithms (include/spatial/batch.hpp) on stance21, double (do_*, frame placement
// and Jacobian on frame 3, base_link) and float
// (do_f_*: RNEA, CRBA, gravity torques, frame placement, frame Jacobian, 8 lanes with AVX2), 256 states per call,
// one thread: each call from its own non-inlined wrapper, so that callgrind_annotate --inclusive=yes gives a count per
// call (÷ 10 calls; a call is 256 / lanes groups). Valgrind has no AVX-512, so build for AVX2 (4 lanes):
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_batch.cpp -o /tmp/cgb
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cgb.out /tmp/cgb 10 &&
//     callgrind_annotate --inclusive=yes /tmp/cgb.out | grep do_
// The program prints a checksum of every result (the same digits before and after a change that should not move a
// number). Standalone, not built by CMake (not named bench_*.cpp).
#include <spatial/batch.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <cstdio>
#include <cstdlib>
using namespace spatial;
namespace M = spatial::models::hoap3_stance_right;
using MX = Eigen::MatrixXd;
__attribute__((noinline)) void do_rnea(Batch<double, M::Tree>& b, const MX& q, const MX& v, const MX& a, MX& t) { b.rnea(q, v, a, t); }
__attribute__((noinline)) void do_aba(Batch<double, M::Tree>& b, const MX& q, const MX& v, const MX& a, MX& t) { b.aba(q, v, a, t); }
__attribute__((noinline)) void do_crba(Batch<double, M::Tree>& b, const MX& q, MX& H) { b.crba(q, H); }
__attribute__((noinline)) void do_grav(Batch<double, M::Tree>& b, const MX& q, MX& t) { b.gravity(q, t); }
__attribute__((noinline)) void do_fd(Batch<double, M::Tree>& b, const MX& q, const MX& v, const MX& a, MX& t) { b.forward_dynamics_crba(q, v, a, t); }
__attribute__((noinline)) void do_jac(Batch<double, M::Tree>& b, const MX& q, MX& J) { b.frame_jacobian(q, 3, ReferenceFrame::LocalWorldAligned, J); }
__attribute__((noinline)) void do_fk(Batch<double, M::Tree>& b, const MX& q, MX& T) { b.frame_placement(q, 3, T); }
using MF = Eigen::MatrixXf;
__attribute__((noinline)) void do_f_rnea(Batch<float, M::Tree>& b, const MF& q, const MF& v, const MF& a, MF& t) { b.rnea(q, v, a, t); }
__attribute__((noinline)) void do_f_crba(Batch<float, M::Tree>& b, const MF& q, MF& H) { b.crba(q, H); }
__attribute__((noinline)) void do_f_grav(Batch<float, M::Tree>& b, const MF& q, MF& t) { b.gravity(q, t); }
__attribute__((noinline)) void do_f_fk(Batch<float, M::Tree>& b, const MF& q, MF& T) { b.frame_placement(q, 3, T); }
__attribute__((noinline)) void do_f_jac(Batch<float, M::Tree>& b, const MF& q, MF& J) { b.frame_jacobian(q, 3, ReferenceFrame::LocalWorldAligned, J); }
int main(int argc, char** argv) {
  auto model = M::model();
  const int B = 256, n = 21, reps = argc > 1 ? std::atoi(argv[1]) : 10;
  srand(1);
  MX q = MX::Random(n, B), v = MX::Random(n, B), a = MX::Random(n, B), tau(n, B), H(n, n * B), J(6, n * B),
      T(3, 4 * B);
  Batch<double, M::Tree> b(model, 1);
  double s = 0;
  for (int r = 0; r < reps; ++r) {
    do_rnea(b, q, v, a, tau); s += tau.sum();
    do_aba(b, q, v, a, tau); s += tau.sum();
    do_crba(b, q, H); s += H.sum();
    do_grav(b, q, tau); s += tau.sum();
    do_fd(b, q, v, a, tau); s += tau.sum();
    do_jac(b, q, J); s += J.sum();
    do_fk(b, q, T); s += T.sum();
  }
  const auto model_f = model.cast<float>();
  MF qf = q.cast<float>(), vf = v.cast<float>(), af = a.cast<float>(), tf(n, B), Hf(n, n * B), Tf(3, 4 * B),
      Jf(6, n * B);
  Batch<float, M::Tree> bf(model_f, 1);
  for (int r = 0; r < reps; ++r) {
    do_f_rnea(bf, qf, vf, af, tf); s += tf.sum();
    do_f_crba(bf, qf, Hf); s += Hf.sum();
    do_f_grav(bf, qf, tf); s += tf.sum();
    do_f_fk(bf, qf, Tf); s += Tf.sum();
    do_f_jac(bf, qf, Jf); s += Jf.sum();
  }
  std::printf("%.17g\n", s);
}

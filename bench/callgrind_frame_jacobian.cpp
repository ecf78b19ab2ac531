// Instruction count of one frame Jacobian taken from the joint Jacobians (frame_jacobian after
// compute_joint_jacobians, Pinocchio's getFrameJacobian), LocalWorldAligned, the left sole of hoap3_floating
// (floating27), into a 6 × 27 MatrixXd, under callgrind. docs/performance.md, "A frame's Jacobian from the joint
// Jacobians": 600 -> 412 (g++) and 536 -> 392 (clang) per call, headers of 805a366 -> a981442.
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_frame_jacobian.cpp -o /tmp/cgj
//   valgrind --tool=callgrind --toggle-collect='do_fj*' --callgrind-out-file=/tmp/cgj.out /tmp/cgj 1000
//   (instructions per call: the "I refs" total / 1000)
// do_cfj: the same Jacobian in one walk (compute_frame_jacobian); build with -DSPATIAL_NO_SIMD for the scalar walk
// (what ARM and run-time trees of general axes take) and count it with --toggle-collect='do_cfj*'. README, "Frame
// Jacobians and placements on the lanes": 3 258 -> 2 619 per call (g++, headers of cf68d17 -> the root-first walk).
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <cstdio>
#include <random>
using namespace spatial;
namespace F = spatial::models::hoap3_floating;
using FM = FloatingModel<double, F::Tree>;
using FD = FloatingData<double, F::Tree>;
using VQ = Eigen::Matrix<double, 28, 1>;
using JM = Eigen::MatrixXd;
__attribute__((noinline)) void do_fj(const FM& m, const FD& d, int f, JM& J) { frame_jacobian(m, d, f, ReferenceFrame::LocalWorldAligned, J); }
__attribute__((noinline)) void do_cfj(const FM& m, FD& d, const VQ& q, int f, JM& J) {
  compute_frame_jacobian(m, d, q, f, ReferenceFrame::LocalWorldAligned, J);
}
int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  const FM m = F::floating_model();
  FD d(m);
  std::mt19937 rng(1);
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(21, -1), hi = -lo;
  const VQ q = random_configuration(m, lo, hi, rng);
  compute_joint_jacobians(m, d, q);
  const int f = F::frame_index("L_SOLE");
  JM J(6, 27); double s = 0;
  for (int t = 0; t < n; ++t) { do_fj(m, d, f, J); s += J.sum(); }
  for (int t = 0; t < n; ++t) { do_cfj(m, d, q, f, J); s += J.sum(); }
  std::printf("%.17g\n", s);
}

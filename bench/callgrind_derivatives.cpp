// Instruction counts of the analytical derivatives (RNEA derivatives, ABA derivatives) on stance21 (hoap3_stance_right,
// compile-time tree) and floating27 (hoap3_floating), do_rd … do_fad, and on their run-time twins (`to_runtime()`),
// do_rt_rd … do_rt_fad, under callgrind. docs/performance.md, "Derivatives and H⁻¹".
//   g++|clang++ -std=c++17 -O3 -march=x86-64-v3 -g -DNDEBUG -Iinclude -Ibuild/src/models/include
//     -isystem /usr/include/eigen3 bench/callgrind_derivatives.cpp -o /tmp/cgd
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cgd.out /tmp/cgd 500 &&
//     callgrind_annotate --inclusive=yes /tmp/cgd.out | grep do_
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <cstdio>
#include <random>
using namespace spatial;
namespace F = spatial::models::hoap3_floating;
namespace R = spatial::models::hoap3_stance_right;
using FM = FloatingModel<double, F::Tree>;
using FD = FloatingData<double, F::Tree>;
using FDD = FloatingDerivativeData<double, F::Tree>;
using RM = Model<double, R::Tree>;
using RD = Data<double, R::Tree>;
using RDD = DerivativeData<double, R::Tree>;
using VQ = Eigen::Matrix<double, 28, 1>;
using VV = Eigen::Matrix<double, 27, 1>;
using VJ = Eigen::Matrix<double, 21, 1>;
__attribute__((noinline)) void do_rd(const RM& m, RD& d, RDD& dd, const VJ& q, const VJ& v, const VJ& a) {
  rnea_derivatives(m, d, dd, q, v, a);
}
__attribute__((noinline)) void do_ad(const RM& m, RD& d, RDD& dd, const VJ& q, const VJ& v, const VJ& t) {
  aba_derivatives(m, d, dd, q, v, t);
}
__attribute__((noinline)) void do_frd(const FM& m, FD& d, FDD& dd, const VQ& q, const VV& v, const VV& a) {
  rnea_derivatives(m, d, dd, q, v, a);
}
__attribute__((noinline)) void do_fad(const FM& m, FD& d, FDD& dd, const VQ& q, const VV& v, const VV& t) {
  aba_derivatives(m, d, dd, q, v, t);
}
using RTM = Model<double, DynamicTree>;
using RTD = Data<double, DynamicTree>;
using RTDD = DerivativeData<double, DynamicTree>;
using FTM = FloatingModel<double, DynamicTree>;
using FTD = FloatingData<double, DynamicTree>;
using FTDD = FloatingDerivativeData<double, DynamicTree>;
using VX = Eigen::VectorXd;
__attribute__((noinline)) void do_rt_rd(const RTM& m, RTD& d, RTDD& dd, const VX& q, const VX& v, const VX& a) {
  rnea_derivatives(m, d, dd, q, v, a);
}
__attribute__((noinline)) void do_rt_ad(const RTM& m, RTD& d, RTDD& dd, const VX& q, const VX& v, const VX& t) {
  aba_derivatives(m, d, dd, q, v, t);
}
__attribute__((noinline)) void do_rt_frd(const FTM& m, FTD& d, FTDD& dd, const VX& q, const VX& v, const VX& a) {
  rnea_derivatives(m, d, dd, q, v, a);
}
__attribute__((noinline)) void do_rt_fad(const FTM& m, FTD& d, FTDD& dd, const VX& q, const VX& v, const VX& t) {
  aba_derivatives(m, d, dd, q, v, t);
}
int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 1000;
  const RM rm = R::model();
  RD rd(rm);
  RDD rdd(rm);
  const FM fm = F::floating_model();
  FD fd(fm);
  FDD fdd(fm);
  const RTM rtm = rm.to_runtime();
  RTD rtd(rtm);
  RTDD rtdd(rtm);
  const FTM ftm = fm.to_runtime();
  FTD ftd(ftm);
  FTDD ftdd(ftm);
  std::vector<VQ> qs(64);
  std::vector<VV> vs(64);
  std::mt19937 rng(1);
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(21, -1), hi = -lo;
  for (auto& q : qs) q = random_configuration(fm, lo, hi, rng);
  for (auto& v : vs) v.setRandom();
  double s = 0;
  for (int t = 0; t < n; ++t) {
    const VQ& q = qs[t & 63];
    const VV& v = vs[(t + 7) & 63];
    const VV& a = vs[(t + 19) & 63];
    const VJ qj = q.tail<21>(), vj = v.tail<21>(), aj = a.tail<21>();
    do_rd(rm, rd, rdd, qj, vj, aj);
    s += rdd.dtau_dq.sum() + rdd.dtau_dv.sum();
    do_ad(rm, rd, rdd, qj, vj, aj);
    s += rdd.dqdd_dq.sum() + rdd.dqdd_dv.sum();
    do_frd(fm, fd, fdd, q, v, a);
    s += fdd.dtau_dq.sum() + fdd.dtau_dv.sum();
    do_fad(fm, fd, fdd, q, v, a);
    s += fdd.dqdd_dq.sum() + fdd.dqdd_dv.sum();
    const VX qx = q, vx = v, ax = a, qjx = qj, vjx = vj, ajx = aj;
    do_rt_rd(rtm, rtd, rtdd, qjx, vjx, ajx);
    s += rtdd.dtau_dq.sum() + rtdd.dtau_dv.sum();
    do_rt_ad(rtm, rtd, rtdd, qjx, vjx, ajx);
    s += rtdd.dqdd_dq.sum() + rtdd.dqdd_dv.sum();
    do_rt_frd(ftm, ftd, ftdd, qx, vx, ax);
    s += ftdd.dtau_dq.sum() + ftdd.dtau_dv.sum();
    do_rt_fad(ftm, ftd, ftdd, qx, vx, ax);
    s += ftdd.dqdd_dq.sum() + ftdd.dqdd_dv.sum();
  }
  std::printf("%.12g\n", s);
}

// rnea_derivatives and aba_derivatives never allocate (derivatives.hpp): the DerivativeData is built before the
// guarded region; inside it, calls on fixed and floating, run-time and compile-time models, with and without external
// forces in both frames. Guarded by Eigen's run-time check and by the counting global operator new of
// nomalloc_algorithms.cpp (same executable).

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/no_allocation.hpp"
#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace {

using namespace spatial;
namespace st = spatial::testing;

volatile double g_sink = 0;

using spatial::testing::NoAllocationRegion;

template <class M, class D, class DD, class Q, class V, class F>
void exercise(const M& model, D& data, DD& dd, const Q& q, const V& v, const V& a, const F& f) {
  NoAllocationRegion guard;
  rnea_derivatives(model, data, dd, q, v, a);
  g_sink = g_sink + dd.dtau_dq.sum() + dd.dtau_dv.sum();
  rnea_derivatives(model, data, dd, q, v, a, f, ForceFrame::Body);
  rnea_derivatives(model, data, dd, q, v, a, f, ForceFrame::Base);
  g_sink = g_sink + dd.dtau_dq.sum();
  aba_derivatives(model, data, dd, q, v, a);
  aba_derivatives(model, data, dd, q, v, a, f, ForceFrame::Base);
  g_sink = g_sink + dd.dqdd_dq.sum() + dd.dqdd_dv.sum() + dd.dqdd_dtau.sum();
  EXPECT_EQ(guard.new_calls(), 0);
}

TEST(NoMallocDerivatives, FixedRunTimeAndCompileTime) {
  std::mt19937 rng(3);
  const Model<double> rt = st::random_model(12, st::Shape::Branched, 3);
  Data<double> d(rt);
  DerivativeData<double> dd(rt);
  const Eigen::VectorXd q = st::random_vector(12, rng), v = st::random_vector(12, rng), a = st::random_vector(12, rng);
  const std::vector<Force<double>> f(12, Force<double>(Vector6<double>::Ones()));
  exercise(rt, d, dd, q, v, a, f);

  namespace sr = models::hoap3_stance_right;
  const auto ct = sr::model();
  Data<double, sr::Tree> dc(ct);
  DerivativeData<double, sr::Tree> ddc(ct);
  const Eigen::Matrix<double, sr::dof, 1> qc = st::random_vector(sr::dof, rng), vc = st::random_vector(sr::dof, rng),
                                          ac = st::random_vector(sr::dof, rng);
  const std::vector<Force<double>> fc(sr::dof, Force<double>(Vector6<double>::Ones()));
  exercise(ct, dc, ddc, qc, vc, ac, fc);
}

TEST(NoMallocDerivatives, FloatingRunTimeAndCompileTime) {
  std::mt19937 rng(4);
  const FloatingModel<double> rt = st::random_floating(10, st::Shape::Branched, 4);
  FloatingData<double> d(rt);
  FloatingDerivativeData<double> dd(rt);
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(10, -1.0), hi = -lo;
  const Eigen::VectorXd q = random_configuration(rt, lo, hi, rng);
  const Eigen::VectorXd v = st::random_vector(rt.nv(), rng), a = st::random_vector(rt.nv(), rng);
  const std::vector<Force<double>> f(11, Force<double>(Vector6<double>::Ones()));
  exercise(rt, d, dd, q, v, a, f);

  namespace fb = models::hoap3_floating;
  const auto ct = fb::floating_model();
  FloatingData<double, fb::Tree> dc(ct);
  FloatingDerivativeData<double, fb::Tree> ddc(ct);
  const Eigen::Matrix<double, fb::nq, 1> qc = neutral(ct);
  const Eigen::Matrix<double, fb::nv, 1> vc = st::random_vector(fb::nv, rng), ac = st::random_vector(fb::nv, rng);
  const std::vector<Force<double>> fc(fb::dof + 1, Force<double>(Vector6<double>::Ones()));
  exercise(ct, dc, ddc, qc, vc, ac, fc);
}

}  // namespace

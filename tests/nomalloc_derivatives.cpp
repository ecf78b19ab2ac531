// rnea_derivatives, aba_derivatives, frame_kinematics_derivatives (derivatives.hpp) and inverse_inertia (minv.hpp)
// never allocate: their buffers are built before the guarded region; inside it, calls on fixed and floating, run-time and compile-time models, with and without external
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

template <class S, class T>
int n_frames(const Model<S, T>& m) { return static_cast<int>(m.frames().size()); }
template <class S, class T>
int n_frames(const FloatingModel<S, T>& m) { return static_cast<int>(m.tree().frames().size()); }

template <class M, class D, class DD, class MD, class FK, class Q, class V, class F>
void exercise(const M& model, D& data, DD& dd, MD& md, FK& fkd, const Q& q, const V& v, const V& a, const F& f) {
  NoAllocationRegion guard;
  rnea_derivatives(model, data, dd, q, v, a);
  g_sink = g_sink + dd.dtau_dq.sum() + dd.dtau_dv.sum();
  rnea_derivatives(model, data, dd, q, v, a, f, ForceFrame::Body);
  rnea_derivatives(model, data, dd, q, v, a, f, ForceFrame::Base);
  g_sink = g_sink + dd.dtau_dq.sum();
  aba_derivatives(model, data, dd, q, v, a);
  aba_derivatives(model, data, dd, q, v, a, f, ForceFrame::Base);
  g_sink = g_sink + dd.dqdd_dq.sum() + dd.dqdd_dv.sum() + dd.dqdd_dtau.sum();
  g_sink = g_sink + inverse_inertia(model, data, md, q).sum();
  const int frame = n_frames(model) - 1;  // the last frame (none on the random trees)
  for (ReferenceFrame rf : {ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned}) {
    if (frame < 0) break;
    frame_kinematics_derivatives(model, data, fkd, q, v, a, frame, rf);
    g_sink = g_sink + fkd.a_dq.sum();
  }
  EXPECT_EQ(guard.new_calls(), 0);
}

TEST(NoMallocDerivatives, FixedRunTimeAndCompileTime) {
  std::mt19937 rng(3);
  const Model<double> rt = st::random_model(12, st::Shape::Branched, 3);
  Data<double> d(rt);
  DerivativeData<double> dd(rt);
  MinvData<double> md(rt);
  FrameKinematicsDerivatives<double> fkd(rt);
  const Eigen::VectorXd q = st::random_vector(12, rng), v = st::random_vector(12, rng), a = st::random_vector(12, rng);
  const std::vector<Force<double>> f(12, Force<double>(Vector6<double>::Ones()));
  exercise(rt, d, dd, md, fkd, q, v, a, f);

  namespace sr = models::hoap3_stance_right;
  const auto ct = sr::model();
  Data<double, sr::Tree> dc(ct);
  DerivativeData<double, sr::Tree> ddc(ct);
  MinvData<double, sr::Tree> mdc(ct);
  FrameKinematicsDerivatives<double, sr::dof> fkdc(ct);
  const Eigen::Matrix<double, sr::dof, 1> qc = st::random_vector(sr::dof, rng), vc = st::random_vector(sr::dof, rng),
                                          ac = st::random_vector(sr::dof, rng);
  const std::vector<Force<double>> fc(sr::dof, Force<double>(Vector6<double>::Ones()));
  exercise(ct, dc, ddc, mdc, fkdc, qc, vc, ac, fc);
}

TEST(NoMallocDerivatives, FloatingRunTimeAndCompileTime) {
  std::mt19937 rng(4);
  const FloatingModel<double> rt = st::random_floating(10, st::Shape::Branched, 4);
  FloatingData<double> d(rt);
  FloatingDerivativeData<double> dd(rt);
  FloatingMinvData<double> md(rt);
  FrameKinematicsDerivatives<double> fkd(rt);
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(10, -1.0), hi = -lo;
  const Eigen::VectorXd q = random_configuration(rt, lo, hi, rng);
  const Eigen::VectorXd v = st::random_vector(rt.nv(), rng), a = st::random_vector(rt.nv(), rng);
  const std::vector<Force<double>> f(11, Force<double>(Vector6<double>::Ones()));
  exercise(rt, d, dd, md, fkd, q, v, a, f);

  namespace fb = models::hoap3_floating;
  const auto ct = fb::floating_model();
  FloatingData<double, fb::Tree> dc(ct);
  FloatingDerivativeData<double, fb::Tree> ddc(ct);
  FloatingMinvData<double, fb::Tree> mdc(ct);
  FrameKinematicsDerivatives<double, fb::nv> fkdc(ct);
  const Eigen::Matrix<double, fb::nq, 1> qc = neutral(ct);
  const Eigen::Matrix<double, fb::nv, 1> vc = st::random_vector(fb::nv, rng), ac = st::random_vector(fb::nv, rng);
  const std::vector<Force<double>> fc(fb::dof + 1, Force<double>(Vector6<double>::Ones()));
  exercise(ct, dc, ddc, mdc, fkdc, qc, vc, ac, fc);
}

}  // namespace

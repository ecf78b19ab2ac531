// Derivatives of frame velocities and accelerations (frame_kinematics_derivatives, derivatives.hpp) against central
// finite differences of forward_kinematics + frame_velocity / frame_acceleration (on the configuration manifold for
// floating bases), in the three reference frames, on random fixed and floating trees of every joint type with frames
// on the base, a middle body and the last body, and on the compile-time HOAP-3 stance model; ∂v/∂v and ∂a/∂a against
// frame_jacobian.
#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include "support/compile_time_trees.hpp"  // SPATIAL_TEST_COMPILE_TIME_TREES: 0 in the sanitizer build

namespace {

using namespace spatial;
using spatial::testing::random_vector;
using spatial::testing::Shape;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

// Central differences, step 1e-5: truncation h²/6 |f'''| and rounding ε|f|/h stay below 1e-8 for these states
// (|f| ≲ 1e2); 1e-6 relative to the largest entry leaves a margin of a hundred and is far below a wrong term.
constexpr double kStep = 1e-5;
constexpr double kTol = 1e-6;

double rel_err(const Mat& a, const Mat& b) { return (a - b).cwiseAbs().maxCoeff() / (1.0 + b.cwiseAbs().maxCoeff()); }

Vec linear_first(const Motion<double>& m) {
  Vec x(6);
  x << m.v, m.w;
  return x;
}

std::vector<spatial::testing::RandomBody> bodies_of(int n, Shape shape, unsigned seed) {
  return spatial::testing::random_bodies(n, shape, seed);
}

/// Random bodies as a model with frames 0, 1, 2 on the base (root), the last body and a middle body.
Model<double> with_frames(const std::vector<spatial::testing::RandomBody>& bodies, unsigned seed) {
  return spatial::testing::build_model_with_frames(bodies, seed);
}

const char* name(ReferenceFrame rf) {
  switch (rf) {
    case ReferenceFrame::Local: return "Local";
    case ReferenceFrame::World: return "World";
    case ReferenceFrame::LocalWorldAligned: return "LocalWorldAligned";
  }
  return "?";
}

/// All checks on one model (fixed or floating), every frame, the three reference frames; `step(q, k, h)` = q ⊕ h eₖ.
template <class M, class D, class Step>
void check(const M& model, int n_frames, const Vec& q, const Vec& v, const Vec& a, Step&& step) {
  const int nv = model.nv();
  D data(model), ref(model);
  FrameKinematicsDerivatives<double> out(model);
  for (int f = 0; f < n_frames; ++f)
    for (ReferenceFrame rf : {ReferenceFrame::Local, ReferenceFrame::World, ReferenceFrame::LocalWorldAligned}) {
      SCOPED_TRACE(std::string("frame ") + std::to_string(f) + " in " + name(rf));
      frame_kinematics_derivatives(model, data, out, q, v, a, f, rf);
      const auto vel = [&](const Vec& x, const Vec& y) {
        forward_kinematics(model, ref, x, y, a);
        return linear_first(frame_velocity(model, ref, f, rf));
      };
      const auto acc = [&](const Vec& x, const Vec& y, const Vec& z) {
        forward_kinematics(model, ref, x, y, z);
        return linear_first(frame_acceleration(model, ref, f, rf));
      };
      Mat vq(6, nv), vv(6, nv), aq(6, nv), av(6, nv), aa(6, nv);
      for (int k = 0; k < nv; ++k) {
        const Vec qp = step(q, k, kStep), qm = step(q, k, -kStep);
        Vec vp = v, vm = v, ap = a, am = a;
        vp[k] += kStep, vm[k] -= kStep, ap[k] += kStep, am[k] -= kStep;
        vq.col(k) = (vel(qp, v) - vel(qm, v)) / (2 * kStep);
        vv.col(k) = (vel(q, vp) - vel(q, vm)) / (2 * kStep);
        aq.col(k) = (acc(qp, v, a) - acc(qm, v, a)) / (2 * kStep);
        av.col(k) = (acc(q, vp, a) - acc(q, vm, a)) / (2 * kStep);
        aa.col(k) = (acc(q, v, ap) - acc(q, v, am)) / (2 * kStep);
      }
      EXPECT_LT(rel_err(out.v_dq, vq), kTol) << "analytic\n" << out.v_dq << "\nfinite differences\n" << vq;
      EXPECT_LT(rel_err(out.v_dv, vv), kTol);
      EXPECT_LT(rel_err(out.a_dq, aq), kTol) << "analytic\n" << out.a_dq << "\nfinite differences\n" << aq;
      EXPECT_LT(rel_err(out.a_dv, av), kTol) << "analytic\n" << out.a_dv << "\nfinite differences\n" << av;
      EXPECT_LT(rel_err(out.a_da, aa), kTol);
      // ∂v/∂v and ∂a/∂a are the frame's Jacobian, to round-off.
      Mat J = Mat::Zero(6, nv);
      compute_joint_jacobians(model, ref, q);
      frame_jacobian(model, ref, f, rf, J);
      EXPECT_LT(rel_err(out.v_dv, J), 1e-12);
      EXPECT_LT(rel_err(out.a_da, J), 1e-12);
    }
}

TEST(FrameKinematicsDerivatives, RandomFixedTreesAgainstFiniteDifferences) {
  for (const auto& [n, shape, seed] : {std::tuple{1, Shape::Chain, 1u}, std::tuple{6, Shape::Chain, 2u},
                                       std::tuple{11, Shape::Branched, 3u}}) {
    const Model<double> model = with_frames(bodies_of(n, shape, seed), seed);
    std::mt19937 rng(seed);
    const Vec q = random_vector(n, rng, 2.0), v = random_vector(n, rng, 2.0), a = random_vector(n, rng, 2.0);
    check<Model<double>, Data<double>>(model, 3, q, v, a, [](const Vec& x, int k, double h) {
      Vec y = x;
      y[k] += h;
      return y;
    });
  }
}

TEST(FrameKinematicsDerivatives, RandomFloatingTreesOnTheManifoldAgainstFiniteDifferences) {
  for (const auto& [n, shape, seed] : {std::tuple{1, Shape::Chain, 4u}, std::tuple{9, Shape::Branched, 5u}}) {
    std::mt19937 rng(seed);
    const FloatingModel<double> model(with_frames(bodies_of(n, shape, seed), seed),
                                      spatial::testing::random_root_inertia(rng), "root");
    const Vec lo = Vec::Constant(n, -2.0), hi = Vec::Constant(n, 2.0);
    const Vec q = random_configuration(model, lo, hi, rng);
    const Vec v = random_vector(model.nv(), rng, 2.0), a = random_vector(model.nv(), rng, 2.0);
    check<FloatingModel<double>, FloatingData<double>>(model, 3, q, v, a, [&](const Vec& x, int k, double h) {
      Vec d = Vec::Zero(model.nv());
      d[k] = h;
      return Vec(integrate(model, x, d, 1.0));
    });
  }
}

#if SPATIAL_TEST_COMPILE_TIME_TREES
TEST(FrameKinematicsDerivatives, Hoap3StanceCompileTimeTree) {
  const auto model = models::hoap3_stance_right::model();
  using T = models::hoap3_stance_right::Tree;
  const int n = model.size();
  std::mt19937 rng(6);
  const Vec q = random_vector(n, rng, 1.0), v = random_vector(n, rng, 2.0), a = random_vector(n, rng, 2.0);
  // The frame farthest down the tree (the free hand's or foot's end): every joint on its path moves it.
  int hand = 0;
  for (int f = 0; f < static_cast<int>(model.frames().size()); ++f)
    if (model.frames()[static_cast<std::size_t>(f)].body > model.frames()[static_cast<std::size_t>(hand)].body) hand = f;
  Data<double, T> data(model), ref(model);
  FrameKinematicsDerivatives<double, models::hoap3_stance_right::dof> out(model);
  frame_kinematics_derivatives(model, data, out, q, v, a, hand, ReferenceFrame::LocalWorldAligned);
  // Against the run-time twin of the same model (same numbers through the run-time code paths).
  const Model<double> rt = model.to_runtime();
  Data<double> rdata(rt);
  FrameKinematicsDerivatives<double> rout(rt);
  frame_kinematics_derivatives(rt, rdata, rout, q, v, a, hand, ReferenceFrame::LocalWorldAligned);
  EXPECT_LT(rel_err(out.a_dq, rout.a_dq), 1e-12);
  EXPECT_GT(out.a_dq.cwiseAbs().maxCoeff(), 0.0);
  check<Model<double>, Data<double>>(rt, 1, q, v, a, [](const Vec& x, int k, double h) {
    Vec y = x;
    y[k] += h;
    return y;
  });
}
#endif

}  // namespace

// Compile-time options of RNEA, ABA and forward dynamics by CRBA (include/spatial/options.hpp): each option
// against the full computation with the switched-off inputs zeroed (or gravity set to zero), on random trees of every
// joint type (run-time models) and on the HOAP-3 stance model (compile-time). Inputs that an option switches off are
// passed as NaN: a result that stays finite and equal proves they are never read.
//
// Bound: the option and the full computation do the same operations except for terms that are exactly zero
// (v = 0, q̈ = 0, a_g = 0), so the results agree up to the order of a few additions per body along a path of at
// most n bodies: |Δ| ≤ 16 n ε max(1, ‖ref‖∞) (ε: unit round-off of double). For n = 21 this is 7.5e-14.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/random_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using spatial::testing::random_model;
using spatial::testing::random_vector;
using spatial::testing::Shape;
namespace stance = spatial::models::hoap3_stance_right;

constexpr double kEps = std::numeric_limits<double>::epsilon();
const double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class A, class B>
void expect_close(const Eigen::MatrixBase<A>& got, const Eigen::MatrixBase<B>& ref, const std::string& what) {
  ASSERT_EQ(got.size(), ref.size()) << what;
  ASSERT_TRUE(got.allFinite()) << what << ": " << got.transpose();
  const double tol = 16.0 * double(ref.size()) * kEps * std::max(1.0, ref.cwiseAbs().maxCoeff());
  EXPECT_LE((got - ref).cwiseAbs().maxCoeff(), tol) << what << "\n got " << got.transpose() << "\n ref "
                                                      << ref.transpose();
}

/// Every option of every algorithm against the full computation, on one model and state.
template <class S, class T, class V>
void check_all_options(const Model<S, T>& model, const V& q, const V& qd, const V& qdd, const V& tau,
                       const std::string& name) {
  const int n = model.size();
  const Model<S, T> no_g = model.with_gravity(Vector3<S>::Zero());
  Data<S, T> d(model), d0(no_g), dr(model);
  V zero = V::Zero(n), nan = V::Constant(n, kNaN);
  std::vector<Force<S>> fext;
  std::mt19937 rng(7);
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd x = random_vector(6, rng, 2.0);
    fext.emplace_back(Vector3<S>(x.head<3>()), Vector3<S>(x.tail<3>()));
  }

  // RNEA
  V ref = rnea(model, dr, q, qd, qdd);
  EXPECT_EQ(V(rnea<Dyn::Full>(model, d, q, qd, qdd)), ref) << name << ": Full is the call without options";
  ref = rnea(model, dr, q, zero, zero);
  expect_close(rnea<Dyn::Static>(model, d, q, nan, nan), ref, name + ": rnea Static = rnea(q, 0, 0)");
  // rnea<Dyn::Static> also leaves the per-body results of the full RNEA (gravity_torques does not promise them):
  // the same transforms, and accelerations and transmitted forces within the bound above.
  const double tol_body = 16.0 * double(n) * kEps;
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const std::string body = name + ": rnea Static leaves the full RNEA's data, body " + std::to_string(i);
    EXPECT_EQ(d.X_up[k].matrix(), dr.X_up[k].matrix()) << body << " X_up";
    const Vector6<S> a = d.a[k].vector(), a_ref = dr.a[k].vector();
    const Vector6<S> f = d.f[k].vector(), f_ref = dr.f[k].vector();
    EXPECT_LE((a - a_ref).cwiseAbs().maxCoeff(), tol_body * std::max(1.0, a_ref.cwiseAbs().maxCoeff())) << body << " a";
    EXPECT_LE((f - f_ref).cwiseAbs().maxCoeff(), tol_body * std::max(1.0, f_ref.cwiseAbs().maxCoeff())) << body << " f";
  }
  expect_close(gravity_torques(model, dr, q), ref, name + ": rnea Static = gravity_torques");
  ref = rnea(model, dr, q, zero, qdd);
  expect_close(rnea<Dyn::QuasiStatic>(model, d, q, nan, qdd), ref, name + ": rnea QuasiStatic = rnea(q, 0, qdd)");
  ref = rnea(model, dr, q, qd, zero);
  expect_close(rnea<Dyn::Gravity | Dyn::Velocity>(model, d, q, qd, nan), ref, name + ": rnea G|V = bias forces");
  ref = rnea(no_g, dr, q, qd, qdd);
  expect_close(rnea<Dyn::NoGravity>(model, d, q, qd, qdd), ref, name + ": rnea NoGravity = rnea with g = 0");
  ref = rnea(no_g, dr, q, zero, qdd);
  expect_close(rnea<Dyn::Acceleration>(model, d, q, nan, qdd), ref, name + ": rnea Acceleration = H qdd");
  const V Hqdd = crba(model, dr, q) * qdd;
  expect_close(rnea<Dyn::Acceleration>(model, d, q, nan, qdd), Hqdd, name + ": rnea Acceleration = CRBA H qdd");
  ref = rnea(no_g, dr, q, qd, zero);
  expect_close(rnea<Dyn::Velocity>(model, d, q, qd, nan), ref, name + ": rnea Velocity = C qd");
  for (ForceFrame fr : {ForceFrame::Body, ForceFrame::Base}) {
    const std::string w = fr == ForceFrame::Body ? " (fext in body frames)" : " (fext in the base frame)";
    ref = rnea(model, dr, q, zero, zero, fext, fr);
    expect_close(rnea<Dyn::Static>(model, d, q, nan, nan, fext, fr), ref, name + ": rnea Static with fext" + w);
    ref = rnea(no_g, dr, q, qd, qdd, fext, fr);
    expect_close(rnea<Dyn::NoGravity>(model, d, q, qd, qdd, fext, fr), ref, name + ": rnea NoGravity with fext" + w);
  }

  // Per-body forces in base coordinates: same torques; f⁰ᵢ = ⁰Xᵢ* fᵢ with ⁰Xᵢ from forward kinematics.
  for (ForceFrame fr : {ForceFrame::Body, ForceFrame::Base}) {
    const V tau_body = rnea(model, dr, q, qd, qdd, fext, fr);
    const V tau_base = rnea<Dyn::Full | Dyn::BaseForces>(model, d, q, qd, qdd, fext, fr);
    EXPECT_EQ(tau_base, tau_body) << name << ": BaseForces changes no torque";
    forward_kinematics(model, d0, q);
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const Force<S> want = d0.X_base[k].apply_force_inverse(dr.f[k]);
      const Eigen::Matrix<S, 6, 1> got = d.f[k].vector(), exp = want.vector();
      expect_close(got, exp, name + ": BaseForces f of body " + std::to_string(i));
    }
  }

  // ABA
  V fd = aba(model, dr, q, zero, tau);
  expect_close(aba<Dyn::Static>(model, d, q, nan, tau), fd, name + ": aba Static = aba(q, 0, tau)");
  fd = aba(no_g, dr, q, qd, tau);
  expect_close(aba<Dyn::Velocity>(model, d, q, qd, tau), fd, name + ": aba Velocity = aba with g = 0");
  fd = aba(no_g, dr, q, zero, tau);
  expect_close(aba<Dyn::None>(model, d, q, nan, tau), fd, name + ": aba None = H⁻¹ tau");
  fd = aba(model, dr, q, qd, tau);
  expect_close(aba<Dyn::Full>(model, d, q, qd, tau), fd, name + ": aba Full = aba");
  for (ForceFrame fr : {ForceFrame::Body, ForceFrame::Base}) {
    fd = aba(model, dr, q, zero, tau, fext, fr);
    expect_close(aba<Dyn::Static>(model, d, q, nan, tau, fext, fr), fd, name + ": aba Static with fext");
    fd = aba(no_g, dr, q, qd, tau, fext, fr);
    expect_close(aba<Dyn::Velocity>(model, d, q, qd, tau, fext, fr), fd, name + ": aba Velocity with fext");
  }

  // Forward dynamics by CRBA + LTDL
  fd = forward_dynamics_crba(model, dr, q, zero, tau);
  expect_close(forward_dynamics_crba<Dyn::Static>(model, d, q, nan, tau), fd, name + ": fd_crba Static");
  fd = forward_dynamics_crba(no_g, dr, q, qd, tau);
  expect_close(forward_dynamics_crba<Dyn::Velocity>(model, d, q, qd, tau), fd, name + ": fd_crba Velocity");
  fd = forward_dynamics_crba(no_g, dr, q, zero, tau);
  expect_close(forward_dynamics_crba<Dyn::None>(model, d, q, nan, tau), fd, name + ": fd_crba None");
  fd = forward_dynamics_crba(model, dr, q, qd, tau);
  expect_close(forward_dynamics_crba<Dyn::Full>(model, d, q, qd, tau), fd, name + ": fd_crba Full");
  // Round trip through the reduced physics: static RNEA of the static FD result gives tau back.
  const V qdd_static = aba<Dyn::Static>(model, d, q, nan, tau);
  const V tau_back = rnea<Dyn::QuasiStatic>(model, dr, q, nan, qdd_static);
  // H q̈ = τ − G loses accuracy with cond(H); checked as a residual against the size of the terms.
  const double scale = std::max(tau.cwiseAbs().maxCoeff(), gravity_torques(model, dr, q).cwiseAbs().maxCoeff());
  EXPECT_LE((tau_back - tau).cwiseAbs().maxCoeff(), 64.0 * n * kEps * std::max(1.0, scale)) << name;
}

TEST(Options, FlagAlgebra) {
  static_assert(Dyn::Full == (Dyn::Gravity | Dyn::Velocity | Dyn::Acceleration));
  static_assert(Dyn::QuasiStatic == (Dyn::Gravity | Dyn::Acceleration));
  static_assert(Dyn::NoGravity == (Dyn::Velocity | Dyn::Acceleration));
  static_assert(has(Dyn::Full, Dyn::Velocity) && !has(Dyn::Static, Dyn::Velocity));
  static_assert(detail::rnea_terms(Dyn::Full | Dyn::BaseForces) == 7u);
  SUCCEED();
}

TEST(Options, RandomTreesEveryJointType) {
  for (Shape shape : {Shape::Chain, Shape::Branched}) {
    for (unsigned seed = 1; seed <= 6; ++seed) {
      const int n = 3 + static_cast<int>(seed) * 3;
      const Model<double> model = random_model(n, shape, 100 + seed);
      std::mt19937 rng(seed);
      const Eigen::VectorXd q = random_vector(n, rng), qd = random_vector(n, rng, 2.0),
                            qdd = random_vector(n, rng, 3.0), tau = random_vector(n, rng, 5.0);
      check_all_options(model, q, qd, qdd, tau,
                        std::string(shape == Shape::Chain ? "chain" : "tree") + " n=" + std::to_string(n));
    }
  }
}

TEST(Options, Hoap3StanceCompileTime) {
  const auto model = stance::model();
  using V = Data<double, stance::Tree>::VectorN;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int rep = 0; rep < 5; ++rep) {
    V q, qd, qdd, tau;
    for (int i = 0; i < stance::dof; ++i) {
      const auto k = static_cast<std::size_t>(i);
      q[i] = stance::lower[k] + u(rng) * (stance::upper[k] - stance::lower[k]);
      qd[i] = 2.0 * u(rng) - 1.0;
      qdd[i] = 6.0 * u(rng) - 3.0;
      tau[i] = 2.0 * u(rng) - 1.0;
    }
    check_all_options(model, q, qd, qdd, tau, "hoap3 stance #" + std::to_string(rep));
  }
}

// The run-time and compile-time trees give the same numbers with options too.
TEST(Options, RunTimeEqualsCompileTime) {
  const auto fixed = stance::model();
  ModelBuilder<double> b;  // the same model as a run-time tree, body by body
  b.set_gravity(fixed.gravity());
  for (int i = 0; i < fixed.size(); ++i)
    b.add_body(fixed.body_name(i), fixed.parent(i), fixed.joint_type(i), fixed.tree_transform(i), fixed.inertia(i),
               fixed.axis(i), fixed.joint_name(i));
  const Model<double> runtime = b.build();
  Data<double, stance::Tree> df(fixed);
  Data<double> dr(runtime);
  std::mt19937 rng(3);
  const Eigen::VectorXd q = random_vector(stance::dof, rng), qdd = random_vector(stance::dof, rng);
  const Data<double, stance::Tree>::VectorN qf = q, qddf = qdd;
  const Eigen::VectorXd a = rnea<Dyn::QuasiStatic>(runtime, dr, q, q, qdd);
  const Eigen::VectorXd c = rnea<Dyn::QuasiStatic>(fixed, df, qf, qf, qddf);
  expect_close(a, c, "QuasiStatic run-time vs compile-time");
}

// Physics of the per-body forces: standing still on the right sole, the force passed from the base to the first
// body (the right ankle) in base coordinates carries the weight of every moving body: f = −m g, and its moment
// about the sole origin is that of the weight at the centre of mass: n = c × (−m g).
TEST(Options, BaseForcesCarryTheWeightOnTheSole) {
  const auto model = stance::model();
  Data<double, stance::Tree> d(model);
  using V = Data<double, stance::Tree>::VectorN;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  V q;
  for (int i = 0; i < stance::dof; ++i)
    q[i] = stance::lower[static_cast<std::size_t>(i)] +
           u(rng) * (stance::upper[static_cast<std::size_t>(i)] - stance::lower[static_cast<std::size_t>(i)]);
  rnea<Dyn::Static | Dyn::BaseForces>(model, d, q, q, q);
  const Force<double> f0 = d.f[0];
  const double m = model.total_mass();
  const Vector3<double> weight = m * model.gravity();
  Data<double, stance::Tree> d2(model);
  const Vector3<double> com = center_of_mass(model, d2, q);
  const double tol = 16.0 * stance::dof * kEps * (m * 9.81);
  EXPECT_LE((f0.f + weight).cwiseAbs().maxCoeff(), tol) << f0.f.transpose();
  EXPECT_LE((f0.n - com.cross(-weight)).cwiseAbs().maxCoeff(), tol) << f0.n.transpose();
}

}  // namespace

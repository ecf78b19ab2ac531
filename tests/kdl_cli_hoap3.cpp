// The "done when": `spatial-dyn id` on urdf/hoap3.urdf, rooted at the pelvis and at a foot, reproduces the
// torques that KDL's TreeIdSolver_RNE gives for the same file. The states go to the tool through a CSV file (columns
// shuffled, an extra column), its output is read back from a CSV file, and KDL's tree is built from urdfdom's
// numbers by tests/support/kdl_urdf.hpp, not by our loader.

#include "support/kdl_urdf.hpp"  // first: sets EIGEN_MALLOC_ALREADY_ALIGNED under ASan (kdl_bridge.hpp)

#include <gtest/gtest.h>

#include <spatial/spatial.hpp>
#include <spatial/urdf.hpp>

#include "support/cli_runner.hpp"
#include "support/urdf_reference.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace spatial;
namespace uio = spatial::urdf_io;
using spatial::testing::urdf_path;

#ifdef SPATIAL_DYN_EXE
void compare_with_kdl(const std::string& root, const std::map<std::string, double>& locked, unsigned seed) {
  SCOPED_TRACE("hoap3.urdf rooted at " + (root.empty() ? std::string("the pelvis (base_link)") : root));
  const std::string file = urdf_path("hoap3.urdf");
  const auto urdf = spatial::testing::parse_urdf_or_throw(file);
  std::vector<std::string> args = {"id", "--urdf", file};
  if (!root.empty()) args.insert(args.end(), {"--root", root});
  std::string lock_list;
  for (const auto& [joint, angle] : locked) lock_list += (lock_list.empty() ? "" : ",") + joint + "=" + std::to_string(angle);
  if (!lock_list.empty()) args.insert(args.end(), {"--lock", lock_list});

  // The joints the tool will expect: every moving URDF joint that is not locked (names from urdfdom).
  std::vector<std::string> joints;
  std::map<std::string, std::pair<double, double>> limits;
  for (const auto& [name, j] : urdf->joints_)
    if (j->type == urdf::Joint::REVOLUTE && !locked.count(name)) {
      joints.push_back(name);
      limits[name] = {j->limits->lower, j->limits->upper};
    }

  // States within the joint limits, columns in a shuffled order plus a column the tool ignores.
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-1.0, 1.0);
  spatial::testing::Csv in;
  in.header.push_back("time");
  for (const auto& j : joints)
    for (const char* kind : {"q:", "qd:", "qdd:"}) in.header.push_back(kind + j);
  std::shuffle(in.header.begin(), in.header.end(), rng);
  const int samples = 6;
  for (int r = 0; r < samples; ++r) {
    std::vector<std::string> row;
    for (const auto& h : in.header) {
      double x = 0.01 * r;  // time
      if (h.rfind("q:", 0) == 0) {
        const auto [lo, hi] = limits.at(h.substr(2));
        x = lo + (hi - lo) * u(rng);
      } else if (h.rfind("qd:", 0) == 0) {
        x = r == 0 ? 0.0 : 2.0 * s(rng);
      } else if (h.rfind("qdd:", 0) == 0) {
        x = r == 0 ? 0.0 : 5.0 * s(rng);
      }
      row.push_back(spatial::testing::exact(x));
    }
    in.rows.push_back(row);
  }
  spatial::testing::ScratchDir dir("kdl_cli");
  in.write(dir.file("states.csv"));
  args.insert(args.end(), {"--in", dir.file("states.csv"), "--out", dir.file("tau.csv")});
  const auto run = spatial::testing::run_program(SPATIAL_DYN_EXE, args);
  ASSERT_EQ(run.status, 0) << run.err;
  const auto out = spatial::testing::parse_csv(spatial::testing::slurp(dir.file("tau.csv")));
  ASSERT_EQ(out.rows.size(), static_cast<std::size_t>(samples));
  ASSERT_EQ(out.header.size(), joints.size());

  // KDL on the same states. Its tree is rooted at the same link; the model only provides the joint numbering.
  uio::LoadOptions opt;
  opt.root = root;
  for (const auto& l : locked) opt.locked.push_back(l);
  const uio::LoadedModel numbering = uio::load_file(file, opt);
  const int n = numbering.model.size();
  ASSERT_EQ(n, static_cast<int>(joints.size()));
  const std::string kdl_root = root.empty() ? urdf->getRoot()->name : root;
  const KDL::Tree tree = spatial::testing::kdl_tree(*urdf, kdl_root, locked);
  const std::vector<int> index = spatial::testing::model_index_of_kdl_joints(tree, numbering.model);
  const Eigen::Vector3d g(0, 0, -9.81);  // the tool's default: -z of the root link (R_SOLE, base_link: z up)
  for (int r = 0; r < samples; ++r) {
    Eigen::VectorXd q(n), qd(n), qdd(n);
    for (int i = 0; i < n; ++i) {
      const std::string& j = numbering.model.joint_name(i);
      q[i] = in.number(static_cast<std::size_t>(r), "q:" + j);
      qd[i] = in.number(static_cast<std::size_t>(r), "qd:" + j);
      qdd[i] = in.number(static_cast<std::size_t>(r), "qdd:" + j);
    }
    const Eigen::VectorXd ktau = spatial::testing::kdl_inverse_dynamics(tree, g, index, q, qd, qdd);
    const double scale = std::max(1.0, ktau.cwiseAbs().maxCoeff());
    for (int i = 0; i < n; ++i) {
      const std::string& j = numbering.model.joint_name(i);
      EXPECT_NEAR(out.number(static_cast<std::size_t>(r), "tau:" + j), ktau[i], 1e-12 * scale) << j << " row " << r;
    }
  }
}

TEST(KdlCli, Hoap3RootedAtThePelvis) { compare_with_kdl("", {}, 1); }

TEST(KdlCli, Hoap3RootedAtAFoot) {
  compare_with_kdl("R_SOLE", {}, 2);
  compare_with_kdl("L_SOLE", {}, 3);
  // The study's single-support models: head and wrists locked (at angles other than 0 as well), 21 DoF.
  compare_with_kdl("R_SOLE", {{"CHEST_H_PAN_joint", 0.0}, {"H_PAN_H_TILT_joint", 0.0}, {"H_TILT_H_ROLL_joint", 0.0},
                              {"R_EB_R_WR_joint", 0.0}, {"L_EB_L_WR_joint", 0.0}}, 4);
  compare_with_kdl("L_SOLE", {{"CHEST_H_PAN_joint", 0.25}, {"H_PAN_H_TILT_joint", -0.5}, {"H_TILT_H_ROLL_joint", 0.125},
                              {"R_EB_R_WR_joint", 0.75}, {"L_EB_L_WR_joint", -1.0}}, 5);
}
#else
TEST(KdlCli, Skipped) { GTEST_SKIP() << "spatial-dyn is not built (SPATIAL_BUILD_TOOLS or SPATIAL_WITH_URDF off)"; }
#endif

}  // namespace

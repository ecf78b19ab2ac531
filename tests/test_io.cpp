// Printing (include/spatial/io.hpp): operator<< of Motion, Force, Transform and Inertia in the notation of
// algebra.hpp, and describe(model) against what spatial-dyn info prints for the same robot.

#include <spatial/spatial.hpp>
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/robots.hpp>
#include <spatial/urdf.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace {

using namespace spatial;
namespace stance = spatial::models::hoap3_stance_right;
namespace uio = spatial::urdf_io;

template <class T>
std::string str(const T& x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(Io, SpatialTypesPrintInTheNotationOfTheDocs) {
  EXPECT_EQ(str(Motion<double>(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6))), "[w (1, 2, 3); v (4, 5, 6)]");
  EXPECT_EQ(str(Force<float>(Eigen::Vector3f(0.5f, 0, -1), Eigen::Vector3f(0, 0, 9.81f))),
            "[n (0.5, 0, -1); f (0, 0, 9.81)]");
  Eigen::Matrix3d E;
  E << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  EXPECT_EQ(str(Transform<double>(E, Eigen::Vector3d(0.1, 0, -2))),
            "rot(E) xlt(r): E [0 1 0; -1 0 0; 0 0 1], r (0.1, 0, -2)");
  const Inertia<double> I = Inertia<double>::from_com(2.0, Eigen::Vector3d(0, 0, 0.5), Eigen::Matrix3d::Identity());
  EXPECT_EQ(str(I), "{m 2; h (0, 0, 1); I [1.5 0 0; 0 1.5 0; 0 0 1]}");
  // The stream's precision is honoured.
  std::ostringstream os;
  os.precision(3);
  os << Motion<double>(Eigen::Vector3d(1.0 / 3, 0, 0), Eigen::Vector3d::Zero());
  EXPECT_EQ(os.str(), "[w (0.333, 0, 0); v (0, 0, 0)]");
}

TEST(Io, DescribeCompileTimeModel) {
  const auto model = stance::model();
  const std::string d = describe(model, JointLimits::from(stance::lower, stance::upper, stance::effort, stance::velocity));
  EXPECT_TRUE(contains(d, "model:     21 joints (dof), compile-time tree")) << d;
  EXPECT_TRUE(contains(d, "gravity:   0 0 -9.81 m/s^2")) << d;
  // Joint 2 with its body, parent, type and limits.
  const std::string type(joint_type_name(model.joint_type(2)));
  EXPECT_TRUE(contains(d, "  2   R_LFE_R_KN_joint   R_LFE  1       " + type + std::string(15 - type.size(), ' ') +
                              "0.0873      2.2689      4.5")) << d;
  EXPECT_TRUE(contains(d, "mass:      8.8024 kg (moving bodies 8.6484 kg, fixed base 0.154 kg)")) << d;
  EXPECT_TRUE(contains(d, "massless:  none")) << d;
  EXPECT_TRUE(contains(d, "R_SOLE (base)")) << d;
  EXPECT_TRUE(contains(d, "R_HAND (R_EB)")) << d;
  EXPECT_FALSE(contains(d, " \n")) << "trailing blanks";
  // Without limits, no limit columns.
  EXPECT_FALSE(contains(describe(model), "lower")) << describe(model);
}

TEST(Io, DescribeLoadedModelMatchesSpatialDynInfo) {
  uio::LoadOptions opt;
  opt.root = "R_SOLE";
  for (const auto& j : stance::locked_joints) opt.locked.emplace_back(std::string(j), 0.0);
  const uio::LoadedModel robot = uio::load_file(std::string(SPATIAL_SOURCE_DIR) + "/urdf/hoap3.urdf", opt);
  const std::string d = describe(robot);
  EXPECT_TRUE(contains(d, "root:      R_SOLE (the fixed base)")) << d;
  EXPECT_TRUE(contains(d, "model:     21 joints (dof), run-time tree")) << d;
  EXPECT_TRUE(contains(d, "mass:      8.8024 kg (moving bodies 8.6484 kg, fixed base 0.154 kg)")) << d;
  // The whole-body CoM at q = 0, as in the README's table: (−0.01374, +0.04435, +0.31743) m from the right sole.
  Data<double> data(robot.model);
  const Eigen::Vector3d c = uio::whole_body_com(robot, data, Eigen::VectorXd::Zero(21));
  std::ostringstream com;
  com.precision(12);
  com << "com:       " << c.x() << " " << c.y() << " " << c.z() << " m at q = 0 (whole body, base frame)";
  EXPECT_TRUE(contains(d, com.str())) << d << "\nexpected: " << com.str();
  EXPECT_NEAR(c.z(), 0.31743, 1e-5);
  EXPECT_TRUE(contains(d, "-0.4363")) << d;  // limits of the URDF
  // Massless joints (the wrists, when not locked) are named.
  const std::string w = describe(uio::load_file(std::string(SPATIAL_SOURCE_DIR) + "/urdf/hoap3.urdf"));
  EXPECT_TRUE(contains(w, "massless:  ")) << w;
  EXPECT_TRUE(contains(w, "R_EB_R_WR_joint")) << w;
  EXPECT_FALSE(contains(w, "massless:  none")) << w;
}

// A floating base: the free-flyer line, the whole mass with the root body, the CoM in the root frame; a model loaded
// with LoadOptions::floating is described the same way, with the URDF limits.
TEST(Io, DescribeFloatingModel) {
  uio::LoadOptions opt;
  opt.floating = true;
  for (const auto& j : stance::locked_joints) opt.locked.emplace_back(std::string(j), 0.0);
  const uio::LoadedModel loaded = uio::load_file(spatial::urdf_path("hoap3.urdf"), opt);
  const FloatingModel<double> model = uio::floating_model(loaded);
  const std::string d = describe(model);
  EXPECT_EQ(d.rfind("root:      base_link (free-flying: joint 'floating_base', nq = 28, nv = 27;", 0), 0u) << d;
  EXPECT_TRUE(contains(d, "model:     21 joints (dof), run-time tree")) << d;
  EXPECT_TRUE(contains(d, "m/s^2 (world frame)")) << d;
  std::ostringstream mass;
  mass.precision(12);
  mass << "mass:      " << model.total_mass() << " kg (moving bodies " << model.tree().total_mass() << " kg, root body "
       << model.root_inertia().m << " kg)";
  EXPECT_TRUE(contains(d, mass.str())) << d << "\nexpected: " << mass.str();
  EXPECT_NEAR(model.total_mass(), 8.8024, 1e-9);
  // The CoM printed is that of the whole robot at the neutral configuration (root frame = world frame there).
  FloatingData<double> data(model);
  const Eigen::Vector3d c = center_of_mass(model, data, neutral(model));
  std::ostringstream com;
  com.precision(12);
  com << "com:       " << c.x() << " " << c.y() << " " << c.z() << " m at q = 0 (whole body, root frame)";
  EXPECT_TRUE(contains(d, com.str())) << d << "\nexpected: " << com.str();
  EXPECT_FALSE(contains(d, "fixed base")) << d;
  EXPECT_FALSE(contains(d, " \n")) << "trailing blanks";
  const std::string l = describe(loaded);
  EXPECT_EQ(l.rfind("root:      base_link (free-flying", 0), 0u) << l;
  EXPECT_TRUE(contains(l, "-0.4363")) << l;  // limits of the URDF
  EXPECT_TRUE(contains(l, com.str())) << l;
}

// spatial::urdf_dir (<spatial/robots.hpp>) in the build tree: the source tree's urdf/ (the installed path is checked
// by the packaging test).
TEST(Robots, UrdfDirInTheBuildTreeIsTheSourceTree) {
  EXPECT_EQ(std::string(spatial::urdf_dir), std::string(SPATIAL_SOURCE_DIR) + "/urdf");
  EXPECT_EQ(spatial::urdf_path("hoap3.urdf"), std::string(SPATIAL_SOURCE_DIR) + "/urdf/hoap3.urdf");
  EXPECT_TRUE(std::ifstream(spatial::urdf_path("hoap3.urdf")).good());
  EXPECT_EQ(uio::load_file(spatial::urdf_path("double_pendulum.urdf")).model.size(), 2);
}

}  // namespace

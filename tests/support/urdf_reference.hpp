#pragma once
// Test helpers for the URDF suites (not part of the installed library): where the robot descriptions are, and an
// independent forward kinematics of a URDF straight from urdfdom's parsed numbers, written without the loader's
// code (its own rpy matrices, its own recursion), so that the loader's frames can be checked against it.

#include <spatial/urdf.hpp>

#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

namespace spatial::testing {

/// The source tree root: SPATIAL_SOURCE_DIR from the build, otherwise three levels above this header (which is
/// right when compiling from the source root with relative paths, e.g. `g++ ... tests/test_urdf_x.cpp`).
inline std::string source_dir() {
#ifdef SPATIAL_SOURCE_DIR
  return SPATIAL_SOURCE_DIR;
#else
  std::string f = __FILE__;  // .../tests/support/urdf_reference.hpp
  for (int up = 0; up < 3; ++up) {
    const std::size_t k = f.find_last_of('/');
    if (k == std::string::npos) return ".";
    f = f.substr(0, k);
  }
  return f.empty() ? "." : f;
#endif
}

inline std::string urdf_path(const std::string& name) { return source_dir() + "/urdf/" + name; }

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

inline urdf::ModelInterfaceSharedPtr parse_urdf_or_throw(const std::string& path) {
  urdf::ModelInterfaceSharedPtr m = urdf::parseURDF(read_text(path));
  if (!m) throw std::runtime_error("urdfdom cannot parse " + path);
  return m;
}

/// R = Rz(yaw) Ry(pitch) Rx(roll), written out (URDF's fixed-axis roll-pitch-yaw).
inline Eigen::Matrix3d rpy_matrix(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  Eigen::Matrix3d Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, cr, -sr, 0, sr, cr;
  Ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  Rz << cy, -sy, 0, sy, cy, 0, 0, 0, 1;
  return Rz * Ry * Rx;
}

inline Eigen::Isometry3d origin_pose(const urdf::Pose& p) {
  double r, pi, y;
  p.rotation.getRPY(r, pi, y);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rpy_matrix(r, pi, y);
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

/// Pose of every link in the URDF root frame at joint positions `q` (by joint name; missing: 0).
inline std::map<std::string, Eigen::Isometry3d> reference_link_poses(const urdf::ModelInterface& m,
                                                                     const std::map<std::string, double>& q) {
  std::map<std::string, Eigen::Isometry3d> out;
  std::vector<urdf::LinkConstSharedPtr> stack{m.getRoot()};
  out[m.getRoot()->name] = Eigen::Isometry3d::Identity();
  while (!stack.empty()) {
    urdf::LinkConstSharedPtr link = stack.back();
    stack.pop_back();
    for (const urdf::JointSharedPtr& j : link->child_joints) {
      const auto it = q.find(j->name);
      const double qj = it == q.end() ? 0.0 : it->second;
      Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
      const Eigen::Vector3d a = Eigen::Vector3d(j->axis.x, j->axis.y, j->axis.z).normalized();
      if (j->type == urdf::Joint::REVOLUTE || j->type == urdf::Joint::CONTINUOUS)
        M.linear() = Eigen::AngleAxisd(qj, a).toRotationMatrix();
      else if (j->type == urdf::Joint::PRISMATIC)
        M.translation() = qj * a;
      out[j->child_link_name] = out[link->name] * origin_pose(j->parent_to_joint_origin_transform) * M;
      stack.push_back(m.getLink(j->child_link_name));
    }
  }
  return out;
}

}  // namespace spatial::testing

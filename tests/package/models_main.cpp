// Built against an installed spatial by the package_consumer test: the generated reference models, from
// <prefix>/include/spatial/models/ through spatial::hoap3_models, without urdfdom; and the installed robots
// (spatial::urdf_dir, <prefix>/share/spatial/urdf).
#include <spatial/models/hoap3_stance_right.hpp>
#include <spatial/robots.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

int main() {
  namespace stance = spatial::models::hoap3_stance_right;
  const auto model = stance::model();
  spatial::Data<double, stance::Tree> data(model);
  const Eigen::Matrix<double, stance::dof, 1> q = Eigen::Matrix<double, stance::dof, 1>::Zero();
  const auto& tau = spatial::gravity_torques(model, data, q);
  const Eigen::Vector3d com = stance::whole_body_com(model, data, q);
  if (stance::dof != 21 || std::abs(stance::whole_body_mass - 8.8024) > 1e-12 || std::abs(com.z() - 0.317) > 5e-4 ||
      !tau.allFinite()) {
    std::fprintf(stderr, "unexpected numbers from the installed hoap3_stance_right model\n");
    return 1;
  }
  // The installed robots, through the C++ constant.
  if (spatial::urdf_dir != EXPECTED_URDF_DIR || !std::ifstream(spatial::urdf_path("hoap3.urdf")).good()) {
    std::fprintf(stderr, "spatial::urdf_dir '%s' is not '%s' or has no hoap3.urdf\n",
                 std::string(spatial::urdf_dir).c_str(), EXPECTED_URDF_DIR);
    return 1;
  }
  std::printf("spatial models consumer: ok, %d DoF, %.4f kg, CoM %.4f m above the sole\n", stance::dof,
              stance::whole_body_mass, com.z());
  return 0;
}

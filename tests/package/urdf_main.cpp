// Built against an installed spatial by the package_consumer test when spatial::urdf is exported: loads a small
// URDF from a string and checks the model it gives.
#include <spatial/urdf.hpp>

#include <cstdio>

int main() {
  const char* xml = R"(<robot name="arm">
    <link name="base"/>
    <link name="upper"><inertial><mass value="1"/><origin xyz="0.25 0 0"/>
      <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>
    <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  </robot>)";
  const spatial::urdf_io::LoadedModel loaded = spatial::urdf_io::load_string(xml, {}, "arm.urdf");
  if (loaded.model.size() != 1 || loaded.model.joint_name(0) != "shoulder") {
    std::fprintf(stderr, "unexpected model from the URDF\n");
    return 1;
  }
  std::printf("spatial URDF consumer: ok, %d joint '%s'\n", loaded.model.size(), loaded.model.joint_name(0).c_str());
  return 0;
}

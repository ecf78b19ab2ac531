#pragma once
/// \file robots.hpp
/// Where the robot descriptions are: `spatial::urdf_dir` is the directory of hoap3.urdf, double_pendulum.urdf and
/// the small test robots (urdf/README.md). Linking `spatial::hoap3_models` defines it: in the build tree it is the
/// source tree's urdf/, in an installed package <prefix>/share/spatial/urdf (also the CMake variable
/// `spatial_URDF_DIR` after `find_package(spatial)`).
///
///   #include <spatial/robots.hpp>
///   auto robot = spatial::urdf_io::load_file(spatial::urdf_path("hoap3.urdf"), opt);
///
/// Why a compile definition and not a generated header: the path is that of the installed package, which is known
/// only when the package is found (`cmake --install --prefix` can put it anywhere, and the tree can be moved), so the
/// package config computes it from its own location and gives it to the target.

#ifndef SPATIAL_URDF_DIR
#error "SPATIAL_URDF_DIR is not defined: link the CMake target spatial::hoap3_models (or define it as the path of the installed share/spatial/urdf)"
#endif

#include <string>
#include <string_view>

namespace spatial {

/// The directory of the robot descriptions (no trailing slash).
inline constexpr std::string_view urdf_dir = SPATIAL_URDF_DIR;

/// urdf_dir + "/" + file, e.g. urdf_path("hoap3.urdf").
inline std::string urdf_path(std::string_view file) {
  std::string out(urdf_dir);
  out += '/';
  out += file;
  return out;
}

}  // namespace spatial

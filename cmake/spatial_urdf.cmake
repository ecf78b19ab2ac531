# spatial::urdf: URDF loading (include/spatial/urdf.hpp) through urdfdom (Debian: liburdfdom-dev).
#
# Include this file from the top-level CMakeLists.txt after the `spatial` INTERFACE target (alias spatial::spatial)
# exists:
#     include(cmake/spatial_urdf.cmake)
# It defines
#   - spatial_urdf (alias spatial::urdf, exported as spatial::urdf): INTERFACE, links spatial::spatial and
#     urdfdom::urdfdom_model (whose interface brings console_bridge, urdfdom_headers and tinyxml, which urdf.hpp
#     also uses directly);
#   - update_double_pendulum (custom target, not built by default): regenerates urdf/double_pendulum.urdf from
#     urdf/hoap3.urdf with tools/make_double_pendulum.py (a test fails when the two disagree).
# For the package config (install(EXPORT ...)): Config.cmake must call find_dependency(urdfdom) when spatial::urdf is
# exported. Hand builds without CMake link: -lurdfdom_model -lconsole_bridge -ltinyxml.

option(SPATIAL_WITH_URDF "Build spatial::urdf (URDF loading through urdfdom)" ON)

if(SPATIAL_WITH_URDF)
  # Debian bookworm: /usr/lib/x86_64-linux-gnu/urdfdom/cmake/urdfdom-config.cmake, which also finds
  # urdfdom_headers and console_bridge.
  find_package(urdfdom CONFIG)
  if(NOT urdfdom_FOUND OR NOT TARGET urdfdom::urdfdom_model)
    message(FATAL_ERROR "spatial: urdfdom not found (install liburdfdom-dev, or configure with "
                        "-DSPATIAL_WITH_URDF=OFF to build without URDF loading)")
  endif()

  add_library(spatial_urdf INTERFACE)
  add_library(spatial::urdf ALIAS spatial_urdf)
  set_target_properties(spatial_urdf PROPERTIES EXPORT_NAME urdf)
  target_link_libraries(spatial_urdf INTERFACE spatial::spatial urdfdom::urdfdom_model)
  target_compile_features(spatial_urdf INTERFACE cxx_std_17)

  find_package(Python3 COMPONENTS Interpreter QUIET)
  if(Python3_Interpreter_FOUND)
    add_custom_target(update_double_pendulum
      COMMAND Python3::Interpreter ${CMAKE_CURRENT_LIST_DIR}/../tools/make_double_pendulum.py
              --urdf ${CMAKE_CURRENT_LIST_DIR}/../urdf/hoap3.urdf
              --out ${CMAKE_CURRENT_LIST_DIR}/../urdf/double_pendulum.urdf
      COMMENT "Regenerating urdf/double_pendulum.urdf from urdf/hoap3.urdf"
      VERBATIM)
  endif()
endif()

# spatial_find_orocos_kdl(): Orocos KDL (Debian's liborocos-kdl-dev) for the KDL cross-checks and bench_kdl.
# Debian's orocos_kdl config defines no imported target; this defines "orocos-kdl" where it is missing, with the
# library's full path and include directory, so that ${orocos_kdl_LIBRARIES} means the same thing either way.
macro(spatial_find_orocos_kdl)
  find_package(orocos_kdl REQUIRED)
  if(NOT TARGET orocos-kdl)
    find_library(SPATIAL_OROCOS_KDL_LIBRARY NAMES orocos-kdl)
    find_path(SPATIAL_OROCOS_KDL_INCLUDE_DIR NAMES kdl/chain.hpp)
    if(NOT SPATIAL_OROCOS_KDL_LIBRARY OR NOT SPATIAL_OROCOS_KDL_INCLUDE_DIR)
      message(FATAL_ERROR "orocos_kdl was found (${orocos_kdl_DIR}) but its library or headers were not: "
                          "library '${SPATIAL_OROCOS_KDL_LIBRARY}', headers '${SPATIAL_OROCOS_KDL_INCLUDE_DIR}'")
    endif()
    add_library(orocos-kdl UNKNOWN IMPORTED)
    set_target_properties(orocos-kdl PROPERTIES
      IMPORTED_LOCATION "${SPATIAL_OROCOS_KDL_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${SPATIAL_OROCOS_KDL_INCLUDE_DIR}"
      INTERFACE_LINK_LIBRARIES Eigen3::Eigen)
  endif()
endmacro()

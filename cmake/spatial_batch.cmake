# spatial::batch: the batched algorithms (include/spatial/batch.hpp) on xsimd's SIMD batches (Debian: libxsimd-dev).
#
# Included from the top-level CMakeLists.txt after the `spatial` INTERFACE target exists. It defines spatial_batch
# (alias spatial::batch, exported as spatial::batch): INTERFACE, links spatial::spatial, threads and xsimd's headers.
# The instruction set is the consumer's: xsimd uses the widest one its compile flags enable (-march=native, or e.g.
# -mavx2 -mfma), SSE2 on a default x86-64 target, NEON on aarch64.
# For the package config: Config.cmake calls find_dependency(xsimd) for the component batch.

option(SPATIAL_WITH_BATCH "Build spatial::batch (batched algorithms over xsimd)" ON)

if(SPATIAL_WITH_BATCH)
  find_package(xsimd 8 CONFIG)
  if(NOT xsimd_FOUND OR NOT TARGET xsimd)
    message(FATAL_ERROR "spatial: xsimd not found (install libxsimd-dev, or configure with "
                        "-DSPATIAL_WITH_BATCH=OFF to build without the batched algorithms)")
  endif()
  find_package(Threads REQUIRED)
  add_library(spatial_batch INTERFACE)
  add_library(spatial::batch ALIAS spatial_batch)
  set_target_properties(spatial_batch PROPERTIES EXPORT_NAME batch)
  # xsimd's include directory rather than its target: Debian's xsimd 8.1 target lists `xtl` as a link library (an
  # optional companion library, not needed here and not installed with it), so linking the target gives `-lxtl`.
  get_target_property(SPATIAL_XSIMD_INCLUDE_DIRS xsimd INTERFACE_INCLUDE_DIRECTORIES)
  target_include_directories(spatial_batch SYSTEM INTERFACE ${SPATIAL_XSIMD_INCLUDE_DIRS})
  target_link_libraries(spatial_batch INTERFACE spatial::spatial Threads::Threads)
  target_compile_features(spatial_batch INTERFACE cxx_std_17)
endif()

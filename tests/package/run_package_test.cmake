# Packaging test, run as `cmake -P` by the ctest test "package_consumer".
#
# 1. cmake --install SPATIAL_BUILD_DIR into WORK_DIR/prefix
# 2. configure, build and run CONSUMER_SOURCE_DIR with the core only (WORK_DIR/core; urdfdom made unfindable), then
#    with the component urdf (WORK_DIR/urdf), with CMAKE_PREFIX_PATH=WORK_DIR/prefix
# 3. the same for QUICKSTART_SOURCE_DIR (examples/quickstart, the README's quick start), when WITH_URDF
# 4. find_package(spatial COMPONENTS urdf) with urdfdom made unfindable must fail, naming urdfdom
# Any failing step stops the test and prints that step's command and full output.
#
# Required: SPATIAL_BUILD_DIR, CONSUMER_SOURCE_DIR, WORK_DIR.
# Optional: CONFIG, GENERATOR, MAKE_PROGRAM, CXX_COMPILER, Eigen3_DIR, SPATIAL_VERSION, WITH_URDF, WITH_BATCH,
# QUICKSTART_SOURCE_DIR.
cmake_minimum_required(VERSION 3.16)

foreach(var SPATIAL_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_package_test.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix "${WORK_DIR}/prefix")

# Runs one step; on failure prints everything and stops.
function(run_step description)
  string(REPLACE ";" " " command_line "${ARGN}")
  message(STATUS "package test: ${description}")
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE result
    OUTPUT_VARIABLE output
    ERROR_VARIABLE output)
  if(NOT result EQUAL 0)
    # Plain message() prints the output verbatim; FATAL_ERROR would re-wrap it.
    message("---- output of: ${command_line} ----\n${output}---- end of output ----")
    message(FATAL_ERROR "package test FAILED at step: ${description} (result: ${result})")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${prefix}")

set(config_args)
if(CONFIG)
  set(config_args --config "${CONFIG}")
endif()

run_step("install ${SPATIAL_BUILD_DIR} into ${prefix}"
  "${CMAKE_COMMAND}" --install "${SPATIAL_BUILD_DIR}" --prefix "${prefix}" ${config_args})

# Configures and builds one outside project SOURCE in WORK_DIR/NAME against the prefix, with extra -D arguments.
function(configure_and_build name source)
  set(build "${WORK_DIR}/${name}")
  file(MAKE_DIRECTORY "${build}")
  set(configure_args
    -S "${source}"
    -B "${build}"
    "-DCMAKE_PREFIX_PATH=${prefix}"
    "-DSPATIAL_EXPECTED_PREFIX=${prefix}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    ${ARGN})
  if(GENERATOR)
    list(APPEND configure_args -G "${GENERATOR}")
  endif()
  if(MAKE_PROGRAM)
    list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
  endif()
  if(CXX_COMPILER)
    list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
  endif()
  if(CONFIG)
    list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONFIG}")
  endif()
  if(Eigen3_DIR)
    list(APPEND configure_args "-DEigen3_DIR=${Eigen3_DIR}")
  endif()
  if(SPATIAL_VERSION)
    list(APPEND configure_args "-DSPATIAL_VERSION=${SPATIAL_VERSION}")
  endif()
  run_step("configure ${name}" "${CMAKE_COMMAND}" ${configure_args})
  run_step("build ${name}" "${CMAKE_COMMAND}" --build "${build}" ${config_args})
endfunction()

function(run_exe path)
  if(NOT EXISTS "${path}" AND EXISTS "${path}.exe")
    set(path "${path}.exe")
  endif()
  run_step("run ${path}" "${path}")
endfunction()

# 1. The core alone: find_package(spatial) must not need urdfdom, so find_package(urdfdom) is disabled here.
# Nor xsimd (the component batch).
configure_and_build(core "${CONSUMER_SOURCE_DIR}" -DSPATIAL_CONSUMER_URDF=OFF -DCMAKE_DISABLE_FIND_PACKAGE_urdfdom=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_xsimd=ON)
run_exe("${WORK_DIR}/core/bin/spatial_consumer")
run_exe("${WORK_DIR}/core/bin/spatial_models_consumer")

if(WITH_URDF)
  # 2. The component urdf: spatial::urdf and urdfdom; with WITH_BATCH also the component batch (spatial::batch, xsimd).
  configure_and_build(urdf "${CONSUMER_SOURCE_DIR}" -DSPATIAL_CONSUMER_URDF=ON "-DSPATIAL_CONSUMER_BATCH=${WITH_BATCH}")
  run_exe("${WORK_DIR}/urdf/bin/spatial_urdf_consumer")
  if(WITH_BATCH)
    run_exe("${WORK_DIR}/urdf/bin/spatial_batch_consumer")
  endif()
  # 3. The README's quick start (examples/quickstart), so that it keeps compiling and giving the right numbers.
  if(QUICKSTART_SOURCE_DIR)
    configure_and_build(quickstart "${QUICKSTART_SOURCE_DIR}")
    run_exe("${WORK_DIR}/quickstart/quickstart")
  endif()
  # 4. Asking for the component urdf where urdfdom cannot be found fails, with the reason.
  set(no_urdfdom "${WORK_DIR}/no_urdfdom")
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${CONSUMER_SOURCE_DIR}" -B "${no_urdfdom}"
      "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DSPATIAL_CONSUMER_URDF=ON
      -DCMAKE_DISABLE_FIND_PACKAGE_urdfdom=ON "-DEigen3_DIR=${Eigen3_DIR}"
    RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(result EQUAL 0 OR NOT output MATCHES "the component urdf needs urdfdom")
    message("---- output ----\n${output}---- end of output ----")
    message(FATAL_ERROR "package test FAILED: COMPONENTS urdf without urdfdom did not fail with the reason")
  endif()
  message(STATUS "package test: COMPONENTS urdf without urdfdom fails as it should")
endif()

message(STATUS "package test: passed")

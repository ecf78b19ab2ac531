# Packaging test, run as `cmake -P` by the ctest test "package_consumer".
#
# 1. cmake --install SPATIAL_BUILD_DIR into WORK_DIR/prefix
# 2. configure CONSUMER_SOURCE_DIR in a fresh WORK_DIR/build with CMAKE_PREFIX_PATH=WORK_DIR/prefix
# 3. build it
# 4. run the consumer executable
# Any failing step stops the test and prints that step's command and full output.
#
# Required: SPATIAL_BUILD_DIR, CONSUMER_SOURCE_DIR, WORK_DIR.
# Optional: CONFIG, GENERATOR, MAKE_PROGRAM, CXX_COMPILER, Eigen3_DIR, SPATIAL_VERSION.
cmake_minimum_required(VERSION 3.16)

foreach(var SPATIAL_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run_package_test.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix "${WORK_DIR}/prefix")
set(consumer_build "${WORK_DIR}/build")

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
file(MAKE_DIRECTORY "${prefix}" "${consumer_build}")

set(config_args)
if(CONFIG)
  set(config_args --config "${CONFIG}")
endif()

run_step("install ${SPATIAL_BUILD_DIR} into ${prefix}"
  "${CMAKE_COMMAND}" --install "${SPATIAL_BUILD_DIR}" --prefix "${prefix}" ${config_args})

set(configure_args
  -S "${CONSUMER_SOURCE_DIR}"
  -B "${consumer_build}"
  "-DCMAKE_PREFIX_PATH=${prefix}"
  "-DSPATIAL_EXPECTED_PREFIX=${prefix}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
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

run_step("configure the consumer project" "${CMAKE_COMMAND}" ${configure_args})
run_step("build the consumer project" "${CMAKE_COMMAND}" --build "${consumer_build}" ${config_args})

set(consumer_exe "${consumer_build}/bin/spatial_consumer")
if(NOT EXISTS "${consumer_exe}" AND EXISTS "${consumer_exe}.exe")
  set(consumer_exe "${consumer_exe}.exe")
endif()
run_step("run the consumer" "${consumer_exe}")
set(models_consumer_exe "${consumer_build}/bin/spatial_models_consumer")
if(NOT EXISTS "${models_consumer_exe}" AND EXISTS "${models_consumer_exe}.exe")
  set(models_consumer_exe "${models_consumer_exe}.exe")
endif()
run_step("run the models consumer" "${models_consumer_exe}")
set(urdf_consumer_exe "${consumer_build}/bin/spatial_urdf_consumer")
if(EXISTS "${urdf_consumer_exe}")
  run_step("run the URDF consumer" "${urdf_consumer_exe}")
endif()

message(STATUS "package test: passed")

# ctest examples_against_installed_package: installs the build tree into a fresh prefix, checks
# that the installed CLI finds its scenes there, then configures, builds and runs examples/ as
# a project of its own with find_package(lgvi) from that prefix.
# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCOMPILER=c++ [-DLAUNCHER=ccache]
#   [-DSANITIZER_FLAGS=-fsanitize=...] -P install_consumer_test.cmake
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "install_consumer_test: ${var} not set")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# The installed CLI reads the scenes installed beside it, not the source tree.
run(${prefix}/bin/lgvi-testbed scenes)
if(NOT run_output MATCHES "free-body")
  message(FATAL_ERROR "the installed lgvi-testbed lists no free-body scene:\n${run_output}")
endif()
run(${prefix}/bin/lgvi-testbed --help)
if(NOT run_output MATCHES "${prefix}/share/lgvi/scenes")
  message(FATAL_ERROR "the installed lgvi-testbed's --scenes-dir default is not under the prefix:\n${run_output}")
endif()

# validate --accept never rewrites the installation's accepted values: without --accepted FILE it
# is refused (exit 1, naming --accepted) before any metric is computed, the file unchanged.
set(installed_accepted ${prefix}/share/lgvi/validation/accepted-quick.txt)
file(SHA256 ${installed_accepted} accepted_before)
execute_process(COMMAND ${prefix}/bin/lgvi-testbed validate --quick --accept
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
file(SHA256 ${installed_accepted} accepted_after)
if(NOT rc EQUAL 1 OR NOT err MATCHES "--accepted" OR NOT accepted_before STREQUAL accepted_after)
  message(FATAL_ERROR "the installed validate --accept was not refused (exit ${rc}):\n${out}\n${err}")
endif()

set(launcher)
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
# The consumer compiles with the build's compiler; against a sanitized build (LGVI_SANITIZE) it
# links the sanitizers' runtime the installed static libraries call.
set(consumer_flags)
if(SANITIZER_FLAGS)
  string(REPLACE ";" " " flags "${SANITIZER_FLAGS}")
  set(consumer_flags "-DCMAKE_CXX_FLAGS=${flags}" "-DCMAKE_EXE_LINKER_FLAGS=${flags}")
endif()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${WORK_DIR}/build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${COMPILER} ${consumer_flags} ${launcher})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build -j2)
foreach(example free_body user_potential indirect_ocp)
  run(${WORK_DIR}/build/example_${example})
  message(STATUS "example_${example}:\n${run_output}")
endforeach()

# The core alone needs Eigen alone: a project asking for no component configures, builds and
# runs with the optional libraries' dependencies unfindable.
file(MAKE_DIRECTORY ${WORK_DIR}/core)
file(WRITE ${WORK_DIR}/core/CMakeLists.txt "cmake_minimum_required(VERSION 3.25)
project(lgvi_core_consumer LANGUAGES CXX)
find_package(lgvi 0.1 REQUIRED)
if(TARGET lgvi::direct OR TARGET lgvi::baselines)
  message(FATAL_ERROR \"a component not requested was read\")
endif()
add_executable(user_potential ${SOURCE_DIR}/examples/user_potential.cpp)
target_link_libraries(user_potential PRIVATE lgvi::lgvi)
")
run(${CMAKE_COMMAND} -S ${WORK_DIR}/core -B ${WORK_DIR}/core-build -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${COMPILER} ${consumer_flags} ${launcher}
    -DCMAKE_DISABLE_FIND_PACKAGE_NLopt=ON -DCMAKE_DISABLE_FIND_PACKAGE_PkgConfig=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_SUNDIALS=ON -DCMAKE_DISABLE_FIND_PACKAGE_GSL=ON)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/core-build -j2)
run(${WORK_DIR}/core-build/user_potential)
file(REMOVE_RECURSE ${WORK_DIR})

# Installs the build tree to a temporary prefix and uses it as a stranger would (issue 14): the installed CLI runs;
# the consumer project (consumer/) finds it with find_package(scanfill), builds, runs a completion through the library
# and scores it; and a program built with nothing but `pkg-config --cflags --libs scanfill` links and runs.
#   cmake -DBUILD=DIR -DWORK=DIR -DSOURCE=tests/install -DGENERATOR=G -DBUILD_TYPE=T -DCXX=C++ [-DLAUNCHER=ccache]
#         -P install_test.cmake
# WORK is wiped first and removed when everything passed (left for a look when not).
foreach(v BUILD WORK SOURCE GENERATOR CXX)
  if(NOT ${v})
    message(FATAL_ERROR "install_test.cmake: -D${v}= is required")
  endif()
endforeach()

include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)

file(REMOVE_RECURSE ${WORK})
set(prefix ${WORK}/prefix)
run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})

# What a consumer looks for, by name (GNUInstallDirs' libdir is lib when configured for a prefix other than /usr).
file(GLOB config_files ${prefix}/lib*/cmake/scanfill/scanfill-config.cmake)
file(GLOB pc_files ${prefix}/lib*/pkgconfig/scanfill.pc)
foreach(f ${prefix}/bin/scanfill ${prefix}/include/scanfill/engine/pipeline.h
          ${prefix}/include/scanfill/nodes/io/read_point_set.h "${config_files}" "${pc_files}")
  if(NOT EXISTS "${f}")
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
file(GLOB_RECURSE sources RELATIVE ${prefix} ${prefix}/include/*.cpp)
if(sources)
  message(FATAL_ERROR "sources installed with the headers: ${sources}")
endif()

run("installed scanfill --version" ${prefix}/bin/scanfill --version)
message(STATUS "installed CLI: ${output}")

# The consumer: configure against the prefix only, build, run a small completion of the vase, check the score.
set(launcher "")
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
run("consumer configure" ${CMAKE_COMMAND} -S ${SOURCE}/consumer -B ${WORK}/consumer -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix} ${launcher})
run("consumer build" ${CMAKE_COMMAND} --build ${WORK}/consumer)
file(WRITE ${WORK}/vase.yaml "mode: completion
inputs:
  scan: procedural:vase
  template: procedural:vase_template
output:
  dir: ${WORK}/out
virtual_scan:
  eye: [0, -3, 0.6]
  target: [0, 0, 0.5]
  width: 240
  height: 240
  fov_deg: 30
sample:
  count: 4000
")
run("consumer run" ${WORK}/consumer/consumer ${WORK}/vase.yaml vase)
if(NOT output MATCHES "consumer: ([0-9]+) points, fscore ([0-9.]+)")
  message(FATAL_ERROR "consumer printed no score:\n${output}")
endif()
set(points ${CMAKE_MATCH_1})
set(fscore ${CMAKE_MATCH_2})
# The completed vase has more points than the one-sided scan alone and scores well against the complete vase.
if(points LESS 10000 OR fscore LESS 0.8)
  message(FATAL_ERROR "consumer's completion is poor: ${points} points, fscore ${fscore}")
endif()
message(STATUS "consumer: ${points} points, fscore ${fscore}")

# pkg-config: the flags alone compile and link a program; the prefix comes from the .pc file's own location.
get_filename_component(pc_dir "${pc_files}" DIRECTORY)
run("pkg-config" ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${pc_dir} pkg-config --cflags --libs scanfill)
string(STRIP "${output}" pc_flags)
message(STATUS "pkg-config --cflags --libs scanfill: ${pc_flags}")
if(NOT pc_flags MATCHES "-I[^ ]*/include/scanfill" OR NOT pc_flags MATCHES "-lscanfill" OR NOT pc_flags MATCHES "eigen3")
  message(FATAL_ERROR "pkg-config flags lack scanfill's include folder, -lscanfill or Eigen: ${pc_flags}")
endif()
separate_arguments(pc_args UNIX_COMMAND "${pc_flags}")
run("pkg-config build" ${CXX} -std=c++20 ${SOURCE}/pkgconfig_main.cpp -o ${WORK}/pkgconfig_consumer ${pc_args})
get_filename_component(lib_dir "${pc_dir}" DIRECTORY)
run("pkg-config program" ${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${lib_dir} ${WORK}/pkgconfig_consumer)
message(STATUS "${output}")

file(REMOVE_RECURSE ${WORK})

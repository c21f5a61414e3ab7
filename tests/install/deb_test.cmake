# cpack -G DEB in the build folder (issue 14): the package holds the program, the library, the headers and the CMake
# and pkg-config files under /usr, and depends on the Debian packages of the libraries it links (dpkg-shlibdeps),
# none of them a -dev package.
# It ships scanfill's LICENSE and the third-party notices, and its Maintainer is SCANFILL_MAINTAINER.
#   cmake -DBUILD=DIR -DWORK=DIR -DCPACK=cpack -DMAINTAINER="Name <email>" -P deb_test.cmake
foreach(v BUILD WORK CPACK MAINTAINER)
  if(NOT ${v})
    message(FATAL_ERROR "deb_test.cmake: -D${v}= is required")
  endif()
endforeach()

include(${CMAKE_CURRENT_LIST_DIR}/run_step.cmake)

file(REMOVE_RECURSE ${WORK})
run("cpack" ${CPACK} -G DEB -B ${WORK} --config ${BUILD}/CPackConfig.cmake)
file(GLOB debs ${WORK}/scanfill_*.deb)
list(LENGTH debs n)
if(NOT n EQUAL 1)
  message(FATAL_ERROR "expected one scanfill_*.deb in ${WORK}, found: ${debs}")
endif()

run("dpkg -c" dpkg -c ${debs})
set(contents "${output}")
foreach(path usr/bin/scanfill usr/lib[a-z0-9_/-]*/libscanfill\\.so\\.[0-9.]+ usr/include/scanfill/engine/pipeline\\.h
             usr/include/scanfill/nodes/core/point_set\\.h usr/lib[a-z0-9_/-]*/cmake/scanfill/scanfill-config\\.cmake
             usr/lib[a-z0-9_/-]*/cmake/scanfill/scanfill-targets\\.cmake usr/lib[a-z0-9_/-]*/pkgconfig/scanfill\\.pc
             usr/share/doc/scanfill/LICENSE usr/share/doc/scanfill/third_party_notices\\.txt)
  if(NOT contents MATCHES " \\./${path}\n")
    message(FATAL_ERROR "the package lacks ${path}:\n${contents}")
  endif()
endforeach()

# The notices name every statically linked or compiled-in project.
run("dpkg-deb -x" dpkg-deb -x ${debs} ${WORK}/root)
file(READ ${WORK}/root/usr/share/doc/scanfill/third_party_notices.txt output)
foreach(project "Ceres Solver|Google Inc" "nanoflann|Marius Muja" "FLANN|Andreas M" "Eigen" "LEMON" "Niels Lohmann"
                "CLI11|University of Cincinnati" "BSD-3-[Cc]lause" "BSD-2-Clause")
  if(NOT output MATCHES "${project}")
    message(FATAL_ERROR "third_party_notices.txt lacks ${project}")
  endif()
endforeach()

run("dpkg -I" dpkg-deb --field ${debs} Package Version Depends Maintainer)
string(FIND "${output}" "Maintainer: ${MAINTAINER}\n" at)
if(at LESS 0)
  message(FATAL_ERROR "the package's Maintainer is not '${MAINTAINER}' (SCANFILL_MAINTAINER):\n${output}")
endif()
set(fields "${output}")
if(NOT fields MATCHES "Depends: ([^\n]*)")
  message(FATAL_ERROR "the package has no Depends:\n${fields}")
endif()
set(depends "${CMAKE_MATCH_1}")
# Not libceres: Debian's Ceres CMake config names libceres.a, so Ceres is linked in and its own libraries (glog,
# SuiteSparse, LAPACK) are what the package needs.
foreach(lib libtbb libyaml-cpp libspdlog libfmt libgoogle-glog libstdc\\+\\+)
  if(NOT depends MATCHES "(^|, )${lib}[0-9.a-z-]*( |,|$)")
    message(FATAL_ERROR "Depends lacks ${lib}: ${depends}")
  endif()
endforeach()
if(depends MATCHES "-dev")
  message(FATAL_ERROR "Depends names a -dev package: ${depends}")
endif()
message(STATUS "${debs}\n${fields}")
file(REMOVE_RECURSE ${WORK})

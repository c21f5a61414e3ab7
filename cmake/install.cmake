# cmake --install and CPack (issue 14): what is installed, where, and the Debian package made of it.
#
#   bin/scanfill                                   the command line (it links the archives: no libscanfill needed)
#   lib/libscanfill.so.0.1.0 (+ .so.0.1, .so)      nodes and engine; its dependencies are linked into it (see
#                                                  CMakeLists.txt), so a consumer needs only Eigen's headers
#   include/scanfill/{nodes,engine}/**.h           every header of nodes/ and engine/, included as in this tree
#                                                  ("engine/pipeline.h"); scanfill::scanfill puts include/scanfill
#                                                  on the include path. The API: engine/config.h, engine/pipeline.h,
#                                                  nodes/io/*.h, nodes/eval/evaluate.h, nodes/procedural/shapes.h
#   lib/cmake/scanfill/scanfill-{config,config-version,targets*}.cmake    find_package(scanfill) -> scanfill::scanfill
#   lib/pkgconfig/scanfill.pc                      pkg-config scanfill (relocatable: paths from the .pc's own folder)
#   share/doc/scanfill/{LICENSE,README.md}         scanfill's licence and manual
#   share/doc/scanfill/third_party_notices.txt     the licences of the code compiled or linked statically into the
#                                                  binaries (Ceres, nanoflann, FLANN, Eigen, LEMON, nlohmann/json,
#                                                  CLI11, PCL's templates): cmake/third_party_notices.txt
# lib is GNUInstallDirs' CMAKE_INSTALL_LIBDIR (lib, or lib/<multiarch> when configured with the prefix /usr).
include(CMakePackageConfigHelpers)

set(SCANFILL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/scanfill)

install(TARGETS scanfill RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS scanfill_lib EXPORT scanfill-targets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/nodes ${PROJECT_SOURCE_DIR}/engine
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/scanfill FILES_MATCHING PATTERN "*.h")
install(EXPORT scanfill-targets NAMESPACE scanfill:: DESTINATION ${SCANFILL_CMAKE_DIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/scanfill-config.cmake.in
                              ${PROJECT_BINARY_DIR}/scanfill-config.cmake INSTALL_DESTINATION ${SCANFILL_CMAKE_DIR})
# 0.x: a minor version may break the API, so 0.1 accepts only 0.1.*.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/scanfill-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/scanfill-config.cmake ${PROJECT_BINARY_DIR}/scanfill-config-version.cmake
        DESTINATION ${SCANFILL_CMAKE_DIR})

# The prefix is the .pc file's own folder walked back up, so the file is right wherever the tree is installed
# (cmake --install --prefix, DESTDIR, the .deb's /usr) without being written at install time.
file(RELATIVE_PATH SCANFILL_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" SCANFILL_PC_TO_PREFIX "${SCANFILL_PC_TO_PREFIX}")
configure_file(${CMAKE_CURRENT_LIST_DIR}/scanfill.pc.in ${PROJECT_BINARY_DIR}/scanfill.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/scanfill.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/README.md ${CMAKE_CURRENT_LIST_DIR}/third_party_notices.txt
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

# ---------------------------------------------------------------------------------------------------------------------
# cpack -G DEB (in the build folder): one package, scanfill_VERSION_ARCH.deb, with the program, the library, the
# headers and the CMake and pkg-config files, installed under /usr. Its Depends are computed by dpkg-shlibdeps (from
# dpkg-dev) from what the binary and the library actually link, so they follow the build machine's packages
# (Debian 12: libtbb12, libyaml-cpp0.7, libspdlog1.10-fmt9, libfmt9, liblz4-1, and for Ceres libgoogle-glog0v6,
# libcholmod3, libcxsparse3, liblapack3: Debian's Ceres CMake config names libceres.a, so Ceres itself is linked in
# and libceres3 is not needed). Eigen is headers only: building against the package needs libeigen3-dev, which is
# therefore recommended, not required.
set(CPACK_PACKAGE_NAME scanfill)
set(CPACK_PACKAGE_VENDOR "The scanfill authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Completes partial 3D scans and transfers style by shape analogies")
set(CPACK_PACKAGE_DESCRIPTION
    "scanfill completes partial 3D scans from a structural template, and transfers geometric style between 3D shapes, by shape analogies (Ma et al., Analogy-Driven 3D Style Transfer, Eurographics 2014). The package holds the scanfill command, the libscanfill library, its headers and its CMake and pkg-config files.")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
# The Debian Maintainer field: whoever builds and distributes the package (Debian policy 5.6.2: a name and an email
# address). The default is the copyright holder of LICENSE with the one address the project has on record (its
# commits'); a distributor puts their own with -DSCANFILL_MAINTAINER="Name <address>" (checked for that form).
set(SCANFILL_MAINTAINER "The scanfill authors <maintainers@users.noreply.h-seed-3de0c76f.example>"
    CACHE STRING "the .deb's Maintainer field: Name <email>")
if(NOT SCANFILL_MAINTAINER MATCHES "^[^<>]+ <[^<>@ ]+@[^<>@ ]+>$")
  message(FATAL_ERROR "SCANFILL_MAINTAINER: expected 'Name <email>', got '${SCANFILL_MAINTAINER}'")
endif()
set(CPACK_PACKAGE_CONTACT "${SCANFILL_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${SCANFILL_MAINTAINER}")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# shlibs and the ldconfig trigger, for the shared library installed in /usr/lib.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libeigen3-dev (>= 3.4)")
include(CPack)

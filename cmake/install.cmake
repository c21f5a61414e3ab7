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
#   share/doc/scanfill/{LICENSE,README.md}
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

install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})

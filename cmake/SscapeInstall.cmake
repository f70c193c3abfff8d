# What `cmake --install` puts where (GNUInstallDirs):
#   lib/libsscape.so.0.1.0 (+ .so.0, .so)      the runtime, exporting only ssc_*
#   lib/libsscape_offline.so.0.1.0 (+ ...)     the runtime and the offline tools (scan folders,
#                                              registration of files, bootstrapping; with training)
#   include/sscape/sscape.h                    the C API: its reference documentation
#   include/sscape/sscape_offline.h            the offline tools' C API (with training)
#   bin/sscape                                 the command line (when SSCAPE_BUILD_CLI)
#   share/sscape/models/sscape-default.sscape  the default model (also built into the library)
#   lib/cmake/sscape/                          find_package(sscape) -> sscape::sscape (and sscape::sscape_offline),
#                                              with a version file
#   lib/pkgconfig/sscape.pc                    pkg-config --cflags --libs sscape (sscape_offline.pc: the other)
#   share/doc/sscape/                          LICENSE (code: Apache-2.0), LICENSE-MODELS (models: CC0-1.0), README
include(CMakePackageConfigHelpers)

set(SSCAPE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/sscape)

install(TARGETS sscape EXPORT sscapeTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_SOURCE_DIR}/include/sscape/sscape.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sscape)
if(TARGET sscape_offline)
  install(TARGETS sscape_offline EXPORT sscapeTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} NAMELINK_COMPONENT Development
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(FILES ${PROJECT_SOURCE_DIR}/include/sscape/sscape_offline.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sscape)
endif()
install(FILES ${PROJECT_SOURCE_DIR}/model_format/models/sscape-default.sscape DESTINATION ${CMAKE_INSTALL_DATADIR}/sscape/models)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/LICENSE-MODELS ${PROJECT_SOURCE_DIR}/README.md
  DESTINATION ${CMAKE_INSTALL_DOCDIR})
if(TARGET sscape_cli)
  install(TARGETS sscape_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

install(EXPORT sscapeTargets NAMESPACE sscape:: DESTINATION ${SSCAPE_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/sscapeConfig.cmake.in
  ${PROJECT_BINARY_DIR}/sscapeConfig.cmake INSTALL_DESTINATION ${SSCAPE_CMAKE_DIR} PATH_VARS CMAKE_INSTALL_DATADIR)
# The ABI is the soname's major version: any 0.x library serves a 0.y consumer asking for 0.y or older.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sscapeConfigVersion.cmake COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/sscapeConfig.cmake ${PROJECT_BINARY_DIR}/sscapeConfigVersion.cmake
  DESTINATION ${SSCAPE_CMAKE_DIR})

# Relocatable: the prefix is found from the .pc file's own folder, so `cmake --install --prefix` anywhere works.
file(RELATIVE_PATH SSCAPE_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" SSCAPE_PC_TO_PREFIX "${SSCAPE_PC_TO_PREFIX}")
set(SSCAPE_PC_NAME sscape)
set(SSCAPE_PC_DESCRIPTION "Statistical 3D human body models (S-SCAPE) behind a stable C ABI")
configure_file(${PROJECT_SOURCE_DIR}/cmake/sscape.pc.in ${PROJECT_BINARY_DIR}/sscape.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/sscape.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(TARGET sscape_offline)
  set(SSCAPE_PC_NAME sscape_offline)
  set(SSCAPE_PC_DESCRIPTION "sscape's runtime and offline tools (scan folders, registration, bootstrapping) behind its C ABI")
  configure_file(${PROJECT_SOURCE_DIR}/cmake/sscape.pc.in ${PROJECT_BINARY_DIR}/sscape_offline.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/sscape_offline.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()

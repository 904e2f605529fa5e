include(CMakePackageConfigHelpers)
set(ICRKIT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/icrkit)
install(EXPORT icrkitTargets NAMESPACE icrkit:: FILE icrkitTargets.cmake
        DESTINATION ${ICRKIT_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/icrkitConfig.cmake.in
  ${PROJECT_BINARY_DIR}/icrkitConfig.cmake INSTALL_DESTINATION ${ICRKIT_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/icrkitConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/icrkitConfig.cmake ${PROJECT_BINARY_DIR}/icrkitConfigVersion.cmake
        DESTINATION ${ICRKIT_CMAKE_DIR})

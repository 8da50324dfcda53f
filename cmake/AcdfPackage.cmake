# The installed CMake package (cmake --install, make install): find_package(acdf) gives the
# targets acdf::sampling, acdf::brdf, acdf::envmap, acdf::integrator and acdf::experiments
# (cmake/acdfConfig.cmake.in).
include(CMakePackageConfigHelpers)

set(ACDF_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/acdf)
if(BUILD_SHARED_LIBS)
  set(ACDF_SHARED_LIBRARIES TRUE)
else()
  set(ACDF_SHARED_LIBRARIES FALSE)
endif()

install(EXPORT acdfTargets NAMESPACE acdf:: FILE acdfTargets.cmake DESTINATION ${ACDF_INSTALL_CMAKEDIR})
configure_package_config_file(cmake/acdfConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/acdfConfig.cmake
  INSTALL_DESTINATION ${ACDF_INSTALL_CMAKEDIR})
# 0.x: a minor version may break the API, so only the same major.minor is compatible.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/acdfConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/acdfConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/acdfConfigVersion.cmake
  DESTINATION ${ACDF_INSTALL_CMAKEDIR})

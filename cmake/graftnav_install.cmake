# `cmake --install` and CPack: the module libraries (graftnav::nav, ::imu, ::estimation, ::io,
# ::sim, ::eval, ::calibration, ::sg, ::mismatch, ::filters, ::graph and ::core), their headers,
# the `graftnav` command, the plot scripts it runs (share/graftnav/scripts, installed by
# scripts/runtime/CMakeLists.txt) and a CMake package, so that another project can write
#   find_package(graftnav REQUIRED)
#   target_link_libraries(app PRIVATE graftnav::io graftnav::filters)
# (examples/consumer). `cpack` in the build folder makes a .deb (Debian dependencies declared
# below and, for the command, found by dpkg-shlibdeps).
include(CMakePackageConfigHelpers)

set_target_properties(graftnav_core PROPERTIES EXPORT_NAME core)
install(TARGETS graftnav_core EXPORT graftnavTargets)
install(TARGETS graftnav RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_SOURCE_DIR}/docs/cli.md ${PROJECT_SOURCE_DIR}/docs/outputs.md
  DESTINATION ${CMAKE_INSTALL_DOCDIR})

set(GRAFTNAV_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/graftnav)
install(EXPORT graftnavTargets NAMESPACE graftnav:: DESTINATION ${GRAFTNAV_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/graftnavConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/graftnavConfig.cmake INSTALL_DESTINATION ${GRAFTNAV_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/graftnavConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/graftnavConfig.cmake
  ${CMAKE_CURRENT_BINARY_DIR}/graftnavConfigVersion.cmake DESTINATION ${GRAFTNAV_CMAKE_DIR})

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME graftnav)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "IMU evaluation by signal grafting: libraries, headers, CMake package and CLI")
set(CPACK_PACKAGE_CONTACT "graftnav maintainers <graftnav@localhost>")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The headers and the CMake package need the dependencies' headers and CMake files.
set(CPACK_DEBIAN_PACKAGE_DEPENDS
  "libeigen3-dev, libceres-dev, libgeographiclib-dev, libyaml-cpp-dev, libfmt-dev, nlohmann-json3-dev")
# The commands write their plots with the installed scripts through python3 and matplotlib;
# without them every number is still written and each command warns that it made no plot.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3, python3-matplotlib, python3-numpy")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
include(CPack)

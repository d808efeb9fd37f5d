# Installs Canopy as a CMake package: find_package(Canopy) + Canopy::adaptor
# (the in-situ driver, with Canopy::forest, the forest API and grid builder).
include(CMakePackageConfigHelpers)

set(CANOPY_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/Canopy")
install(EXPORT CanopyTargets NAMESPACE Canopy:: DESTINATION "${CANOPY_CMAKE_DIR}")
set(CANOPY_PIPELINES_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/canopy/pipelines")
configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/CanopyConfig.cmake.in"
  "${CMAKE_CURRENT_BINARY_DIR}/CanopyConfig.cmake"
  INSTALL_DESTINATION "${CANOPY_CMAKE_DIR}")
write_basic_package_version_file(
  "${CMAKE_CURRENT_BINARY_DIR}/CanopyConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${CMAKE_CURRENT_BINARY_DIR}/CanopyConfig.cmake"
  "${CMAKE_CURRENT_BINARY_DIR}/CanopyConfigVersion.cmake"
  "${CMAKE_CURRENT_LIST_DIR}/CanopyDependencies.cmake"
  "${CMAKE_CURRENT_LIST_DIR}/FindP4est.cmake"
  DESTINATION "${CANOPY_CMAKE_DIR}")

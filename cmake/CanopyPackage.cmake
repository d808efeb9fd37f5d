# Canopy as a CMake package: find_package(Canopy) + Canopy::adaptor (the in-situ
# driver, with Canopy::forest, the forest API and grid builder), from an install
# or straight from this build tree (Canopy_DIR=<build dir>). One template,
# CanopyConfig.cmake.in, is configured twice with the paths of each.
include(CMakePackageConfigHelpers)

set(CANOPY_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/Canopy")
set(CANOPY_PIPELINES_INSTALL_DIR "${CMAKE_INSTALL_DATADIR}/canopy/pipelines")
write_basic_package_version_file(
  "${PROJECT_BINARY_DIR}/CanopyConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)

# Install tree: paths relative to the prefix.
install(EXPORT CanopyTargets NAMESPACE Canopy:: DESTINATION "${CANOPY_CMAKE_DIR}")
set(CANOPY_CONFIG_DEPENDENCIES "${CANOPY_CMAKE_DIR}/CanopyDependencies.cmake")
set(CANOPY_CONFIG_TARGETS "${CANOPY_CMAKE_DIR}/CanopyTargets.cmake")
set(CANOPY_CONFIG_PIPELINES "${CANOPY_PIPELINES_INSTALL_DIR}")
set(CANOPY_CONFIG_MODULES "${CANOPY_CMAKE_DIR}")
configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/CanopyConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/CMakeFiles/CanopyInstall/CanopyConfig.cmake"
  INSTALL_DESTINATION "${CANOPY_CMAKE_DIR}"
  PATH_VARS CANOPY_CONFIG_DEPENDENCIES CANOPY_CONFIG_TARGETS CANOPY_CONFIG_PIPELINES
    CANOPY_CONFIG_MODULES)
install(FILES
  "${PROJECT_BINARY_DIR}/CMakeFiles/CanopyInstall/CanopyConfig.cmake"
  "${PROJECT_BINARY_DIR}/CanopyConfigVersion.cmake"
  "${CMAKE_CURRENT_LIST_DIR}/CanopyDependencies.cmake"
  "${CMAKE_CURRENT_LIST_DIR}/FindP4est.cmake"
  DESTINATION "${CANOPY_CMAKE_DIR}")

# Build tree: the same export set (the libraries and, added by vtk_module_build,
# the filter module) imported from where they are built; the dependency
# discovery and the pipeline scripts from the source tree. The driver finds the
# plugin next to the built library, as it does in an install.
export(EXPORT CanopyTargets NAMESPACE Canopy:: FILE "${PROJECT_BINARY_DIR}/CanopyTargets.cmake")
set(CANOPY_CONFIG_DEPENDENCIES "${CMAKE_CURRENT_LIST_DIR}/CanopyDependencies.cmake")
set(CANOPY_CONFIG_TARGETS "${PROJECT_BINARY_DIR}/CanopyTargets.cmake")
set(CANOPY_CONFIG_PIPELINES "${PROJECT_SOURCE_DIR}/pipelines")
set(CANOPY_CONFIG_MODULES "${CMAKE_CURRENT_LIST_DIR}")
configure_package_config_file(
  "${CMAKE_CURRENT_LIST_DIR}/CanopyConfig.cmake.in"
  "${PROJECT_BINARY_DIR}/CanopyConfig.cmake"
  INSTALL_DESTINATION "${PROJECT_BINARY_DIR}"
  INSTALL_PREFIX "${PROJECT_BINARY_DIR}"
  PATH_VARS CANOPY_CONFIG_DEPENDENCIES CANOPY_CONFIG_TARGETS CANOPY_CONFIG_PIPELINES
    CANOPY_CONFIG_MODULES)
unset(CANOPY_CONFIG_DEPENDENCIES)
unset(CANOPY_CONFIG_TARGETS)
unset(CANOPY_CONFIG_PIPELINES)
unset(CANOPY_CONFIG_MODULES)

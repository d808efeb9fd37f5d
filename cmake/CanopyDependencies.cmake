# Dependency discovery for Canopy, shared by the project build and by the
# installed CanopyConfig.cmake so both find the same ParaView 5.11 VTK.
#
# Why this file exists: Debian's ParaView 5.11 CMake package references
# imported targets (Freetype::Freetype, X11::X11, GLEW::GLEW, ...) that its own
# config does not create. They must be found before find_package(ParaView).
# Never find Debian's standalone VTK 9.1: two VTKs in one process crash.
#
# Not include-guarded on purpose: imported targets are directory-scoped, so a
# consumer calling find_package(Canopy) in two directories needs both runs.

# In a package config, a missing dependency makes find_package(Canopy) fail
# gracefully (Canopy_FOUND false); in the project build it is an error.
macro(_canopy_find_dependency)
  if(CANOPY_FINDING_PACKAGE)
    find_dependency(${ARGV})
  else()
    find_package(${ARGV} REQUIRED)
  endif()
endmacro()
if(CANOPY_FINDING_PACKAGE)
  include(CMakeFindDependencyMacro)
endif()

# FindMPI's and FindHDF5's C parts compile C test programs: a consumer project
# that enabled only CXX gets C enabled here (file scope: find_package's caller).
if(CANOPY_FINDING_PACKAGE)
  get_property(_canopy_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
  if(NOT "C" IN_LIST _canopy_languages)
    enable_language(C)
  endif()
  unset(_canopy_languages)
endif()

# ParaView ships Find modules (FindNetCDF, ...) next to its VTK config; use
# them for this discovery only, then restore the caller's module path.
set(_canopy_saved_module_path "${CMAKE_MODULE_PATH}")
find_path(_canopy_pv_find_modules FindNetCDF.cmake
  PATHS
    "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/paraview-5.11/vtk"
    "/usr/lib/cmake/paraview-5.11/vtk"
    "/usr/local/lib/cmake/paraview-5.11/vtk"
  NO_DEFAULT_PATH)
if(_canopy_pv_find_modules)
  list(PREPEND CMAKE_MODULE_PATH "${_canopy_pv_find_modules}")
endif()

_canopy_find_dependency(Freetype)
_canopy_find_dependency(X11)
_canopy_find_dependency(GLEW)
_canopy_find_dependency(LibXml2)
_canopy_find_dependency(Boost)
# The MPI-IO build of HDF5 (Debian: libhdf5-openmpi-dev), the one ParaView's VTK
# links; Canopy::IO writes VTKHDF files through it from every rank.
set(HDF5_PREFER_PARALLEL TRUE)
# A build directory configured before Canopy wrote HDF5 caches the serial build
# (h5cc); forget it so that the MPI-IO one is found.
if(HDF5_C_LIBRARY_hdf5 MATCHES "/serial/")
  get_cmake_property(_canopy_cache_variables CACHE_VARIABLES)
  foreach(_canopy_variable IN LISTS _canopy_cache_variables)
    if(_canopy_variable MATCHES "^HDF5_")
      unset(${_canopy_variable} CACHE)
    endif()
  endforeach()
endif()
_canopy_find_dependency(HDF5 COMPONENTS C HL)
_canopy_find_dependency(NetCDF)
_canopy_find_dependency(MPI COMPONENTS C CXX)
# Ask for explicit components: a bare find_package(ParaView) requires Qt5.
# Catalyst is what the in-situ driver links; the filters need only VTK.
_canopy_find_dependency(ParaView 5.11
  COMPONENTS Catalyst PythonCatalyst RemotingCore RemotingLive RemotingServerManager)
# ParaView's Python wrapping libraries leave libpython to the executable; the
# in-situ driver embeds Python, so Canopy links it itself.
_canopy_find_dependency(Python3 3.11 EXACT COMPONENTS Development.Embed)

set(CMAKE_MODULE_PATH "${_canopy_saved_module_path}")
unset(_canopy_saved_module_path)

if(NOT CANOPY_FINDING_PACKAGE AND NOT HDF5_IS_PARALLEL)
  message(FATAL_ERROR "Canopy needs HDF5 built with MPI-IO (found ${HDF5_C_LIBRARIES}); "
                      "install libhdf5-openmpi-dev")
endif()
if(NOT CANOPY_FINDING_PACKAGE AND NOT TARGET VTK::CommonDataModel)
  message(FATAL_ERROR "ParaView was found but VTK::CommonDataModel is missing; "
                      "is paraview-dev installed?")
endif()

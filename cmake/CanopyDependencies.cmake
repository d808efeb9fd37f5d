# Dependency discovery for Canopy, shared by the project build and by the
# installed CanopyConfig.cmake so both find the same ParaView 5.11 VTK.
#
# Why this file exists: Debian's ParaView 5.11 CMake package references
# imported targets (Freetype::Freetype, X11::X11, GLEW::GLEW, ...) that its own
# config does not create. They must be found before find_package(ParaView).
# Never find Debian's standalone VTK 9.1: two VTKs in one process crash.

include_guard(GLOBAL)

set(_canopy_pv_vtk_modules "/usr/lib/x86_64-linux-gnu/cmake/paraview-5.11/vtk")
if(EXISTS "${_canopy_pv_vtk_modules}")
  list(PREPEND CMAKE_MODULE_PATH "${_canopy_pv_vtk_modules}")
endif()

find_package(Freetype REQUIRED)
find_package(X11 REQUIRED)
find_package(GLEW REQUIRED)
find_package(LibXml2 REQUIRED)
find_package(Boost REQUIRED)
find_package(HDF5 REQUIRED COMPONENTS C HL)
find_package(NetCDF REQUIRED)
find_package(MPI REQUIRED COMPONENTS C CXX)

# Ask for explicit components: a bare find_package(ParaView) requires Qt5.
find_package(ParaView 5.11 REQUIRED
  COMPONENTS Catalyst PythonCatalyst RemotingCore RemotingServerManager)

if(NOT TARGET VTK::CommonDataModel)
  message(FATAL_ERROR "ParaView was found but VTK::CommonDataModel is missing; "
                      "is paraview-dev installed?")
endif()

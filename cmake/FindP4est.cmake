# Finds p4est (2D p4est_* and 3D p8est_*) and libsc, which Debian's libp4est-dev
# ships without a CMake package file. Defines P4est_FOUND and the imported
# targets P4est::p4est (with P4est::sc). p4est is built with MPI on Debian:
# a consumer links MPI as well.
find_path(P4est_INCLUDE_DIR p4est.h PATH_SUFFIXES p4est)
find_path(P4est_SC_INCLUDE_DIR sc.h PATH_SUFFIXES sc p4est)
find_library(P4est_LIBRARY NAMES p4est)
find_library(P4est_SC_LIBRARY NAMES sc)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(P4est
  REQUIRED_VARS P4est_LIBRARY P4est_SC_LIBRARY P4est_INCLUDE_DIR P4est_SC_INCLUDE_DIR)

if(P4est_FOUND AND NOT TARGET P4est::sc)
  add_library(P4est::sc UNKNOWN IMPORTED)
  set_target_properties(P4est::sc PROPERTIES
    IMPORTED_LOCATION "${P4est_SC_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${P4est_SC_INCLUDE_DIR}")
  add_library(P4est::p4est UNKNOWN IMPORTED)
  set_target_properties(P4est::p4est PROPERTIES
    IMPORTED_LOCATION "${P4est_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${P4est_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES P4est::sc)
endif()
mark_as_advanced(P4est_INCLUDE_DIR P4est_SC_INCLUDE_DIR P4est_LIBRARY P4est_SC_LIBRARY)

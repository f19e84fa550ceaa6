# Finds Embree 3 (Debian: libembree-dev). Defines the imported target Embree3::embree.
# The package's own CMake config works, but a plain header/library search keeps us independent of
# its layout across Debian revisions.
find_path(EMBREE3_INCLUDE_DIR embree3/rtcore.h)
find_library(EMBREE3_LIBRARY NAMES embree3)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Embree3 REQUIRED_VARS EMBREE3_LIBRARY EMBREE3_INCLUDE_DIR)
if(Embree3_FOUND AND NOT TARGET Embree3::embree)
  add_library(Embree3::embree UNKNOWN IMPORTED)
  set_target_properties(Embree3::embree PROPERTIES
    IMPORTED_LOCATION "${EMBREE3_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${EMBREE3_INCLUDE_DIR}")
endif()
mark_as_advanced(EMBREE3_INCLUDE_DIR EMBREE3_LIBRARY)

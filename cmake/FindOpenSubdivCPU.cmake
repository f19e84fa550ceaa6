# Finds OpenSubdiv's CPU library (Debian: libosd-dev). Defines OpenSubdiv::osdCPU.
# Debian's OpenSubdivConfig.cmake names a static library that the package does not ship, so we
# search for libosdCPU and opensubdiv/version.h directly.
find_path(OPENSUBDIV_INCLUDE_DIR opensubdiv/version.h)
find_library(OPENSUBDIV_CPU_LIBRARY NAMES osdCPU)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenSubdivCPU REQUIRED_VARS OPENSUBDIV_CPU_LIBRARY OPENSUBDIV_INCLUDE_DIR)
if(OpenSubdivCPU_FOUND AND NOT TARGET OpenSubdiv::osdCPU)
  add_library(OpenSubdiv::osdCPU UNKNOWN IMPORTED)
  set_target_properties(OpenSubdiv::osdCPU PROPERTIES
    IMPORTED_LOCATION "${OPENSUBDIV_CPU_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OPENSUBDIV_INCLUDE_DIR}")
endif()
mark_as_advanced(OPENSUBDIV_INCLUDE_DIR OPENSUBDIV_CPU_LIBRARY)

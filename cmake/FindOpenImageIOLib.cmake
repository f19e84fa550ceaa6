# Finds OpenImageIO 2.4 (Debian: libopenimageio-dev). Defines OpenImageIO::lib.
# Debian's exported OpenImageIO::OpenImageIO target lists an OpenCV include directory that is not
# installed, which makes CMake fail at generate time; we search the headers and libraries directly.
find_path(OIIO_INCLUDE_DIR OpenImageIO/imageio.h)
find_library(OIIO_LIBRARY NAMES OpenImageIO)
find_library(OIIO_UTIL_LIBRARY NAMES OpenImageIO_Util)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenImageIOLib
  REQUIRED_VARS OIIO_LIBRARY OIIO_UTIL_LIBRARY OIIO_INCLUDE_DIR)
if(OpenImageIOLib_FOUND AND NOT TARGET OpenImageIO::lib)
  add_library(OpenImageIO::lib UNKNOWN IMPORTED)
  set_target_properties(OpenImageIO::lib PROPERTIES
    IMPORTED_LOCATION "${OIIO_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OIIO_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${OIIO_UTIL_LIBRARY}")
endif()
mark_as_advanced(OIIO_INCLUDE_DIR OIIO_LIBRARY OIIO_UTIL_LIBRARY)

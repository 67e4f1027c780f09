# Finds Debian's GeographicLib (libgeographiclib-dev) and defines the imported target
# GeographicLib::GeographicLib. Debian ships only a find module outside CMake's default path.
find_path(GeographicLib_INCLUDE_DIR GeographicLib/Geocentric.hpp)
find_library(GeographicLib_LIBRARY NAMES GeographicLib)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(GeographicLibGeovor DEFAULT_MSG GeographicLib_LIBRARY GeographicLib_INCLUDE_DIR)
if(GeographicLibGeovor_FOUND AND NOT TARGET GeographicLib::GeographicLib)
  add_library(GeographicLib::GeographicLib UNKNOWN IMPORTED)
  set_target_properties(GeographicLib::GeographicLib PROPERTIES
    IMPORTED_LOCATION "${GeographicLib_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${GeographicLib_INCLUDE_DIR}")
endif()

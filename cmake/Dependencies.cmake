# All dependencies come from Debian 12 packages (scripts/setup.sh installs them).
# Three Debian packaging bugs are worked around here; see docs/building.md.

find_package(embree 3.13 REQUIRED)       # target: embree; calls find_package(TBB) itself
find_package(TBB REQUIRED)               # TBB::tbb
find_package(OpenImageIO 2.4 REQUIRED)   # needs openimageio-tools installed (Debian bug 1)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED) # nlohmann_json::nlohmann_json (snell lsp)
# cpp-httplib (libcpp-httplib-dev): snell watch's page. Debian builds it as a library
# (its header's -D flags must match that build) with a pkg-config file, no CMake config.
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET GLOBAL cpp-httplib>=0.11)

# Debian bug 2: the OIIO target lists /usr/include/opencv4, which does not exist
# unless libopencv-dev is installed.
foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
  get_target_property(_dirs OpenImageIO::OpenImageIO ${_prop})
  if(_dirs)
    list(FILTER _dirs EXCLUDE REGEX "opencv4")
    set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${_prop} "${_dirs}")
  endif()
endforeach()

# Debian bug 3: OCIO's CMake config lives in /usr/share/cmake and points at /include.
find_package(OpenColorIO 2.1 CONFIG QUIET)
if(NOT OpenColorIO_FOUND)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(OCIO REQUIRED IMPORTED_TARGET GLOBAL OpenColorIO>=2.1)
  add_library(OpenColorIO::OpenColorIO ALIAS PkgConfig::OCIO)
endif()

if(SNELL_BUILD_TESTS)
  find_package(Catch2 2.13 REQUIRED)     # puts Catch.cmake on CMAKE_MODULE_PATH
endif()

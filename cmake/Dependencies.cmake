# Every dependency comes from Debian 12's packages (scripts/setup.sh installs them).

find_package(embree 3.13 REQUIRED)
find_package(TBB REQUIRED)
find_package(Imath REQUIRED)
# OpenEXR, libpng and libjpeg-turbo read and write the images every render touches;
# OpenImageIO, with its ~260 shared libraries, only in a module loaded on first use
# (renderer/image/oiio_module.h, docs/images.md).
find_package(OpenEXR REQUIRED CONFIG)
find_package(PNG REQUIRED)
find_package(OpenImageIO REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(Threads REQUIRED)
# Debian's libdraco-dev ships a working CMake config (draco::draco, the shared library).
find_package(draco REQUIRED CONFIG)

# Debian's OpenImageIO target lists /usr/include/opencv4 as an include directory even
# though nothing of OpenCV is needed to use it; CMake rejects the missing path.
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
list(FILTER _oiio_includes EXCLUDE REGEX "opencv")
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_includes}")

# Debian's OpenColorIO CMake config is broken; its pkg-config file is not.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OCIO REQUIRED IMPORTED_TARGET OpenColorIO)
pkg_check_modules(TURBOJPEG REQUIRED IMPORTED_TARGET libturbojpeg)

if(PRISM_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(PRISM_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()

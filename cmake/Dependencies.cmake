# Third-party packages acdf builds against. All come from Debian packages installed by
# scripts/install-deps; every one ships a CMake config file, so config mode is used throughout.
#
# Imported targets made available here:
#   TBB::tbb                      oneTBB
#   fmt::fmt                      {fmt}
#   CLI11::CLI11                  CLI11 (header-only)
#   nlohmann_json::nlohmann_json  JSON for Modern C++ (header-only)
#   OpenEXR::OpenEXR, Imath::Imath  OpenEXR (reading and writing .exr files)
#   ZLIB::ZLIB                    zlib (writing .png previews)
#   OpenImageIO::OpenImageIO      OpenImageIO (reading other image formats), OpenImageIO::OpenImageIO_Util;
#                                 with ACDF_WITH_OPENIMAGEIO or BUILD_TESTING
#   Eigen3::Eigen                 Eigen 3.4 (header-only): rotations and transforms
#   GTest::gtest, GTest::gtest_main, GTest::gmock   only when BUILD_TESTING is ON
#   benchmark::benchmark, benchmark::benchmark_main

find_package(TBB CONFIG REQUIRED)
# fmt before OpenImageIO: OIIO's targets link fmt::fmt only "if it exists".
find_package(fmt CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(Eigen3 3.4 CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(Imath CONFIG REQUIRED)
find_package(OpenEXR CONFIG REQUIRED)
find_package(ZLIB REQUIRED)
# ACDF_WITH_OPENIMAGEIO: OpenImageIO reads the image formats other than OpenEXR (HDR, PNG, TIFF...), from a
# module acdf loads on the first such image (envmap/src/openimageio_module.h), so that only programs that read
# one load the about 250 shared libraries OpenImageIO links. Off, acdf reads OpenEXR files only: the portable
# wheel's build (pyproject.toml).
option(ACDF_WITH_OPENIMAGEIO "Read image formats other than OpenEXR through OpenImageIO" ON)
# The tests write their images of every format with it, whatever acdf reads.
if(ACDF_WITH_OPENIMAGEIO OR BUILD_TESTING)
  find_package(OpenImageIO CONFIG REQUIRED)
endif()
find_package(benchmark CONFIG REQUIRED)
if(BUILD_TESTING)
  find_package(GTest REQUIRED)
endif()

# Debian's OpenImageIO targets list include directories of optional dependencies that need not be
# installed (/usr/include/opencv4 unless OpenCV is). CMake refuses to generate a project that uses
# an imported target with a non-existent include directory, so drop the missing ones.
function(acdf_drop_missing_include_dirs target)
  if(NOT TARGET ${target})
    return()
  endif()
  get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT dirs)
    return()
  endif()
  set(kept "")
  foreach(dir IN LISTS dirs)
    # Keep generator expressions untouched: they cannot be checked at configure time.
    if(dir MATCHES "\\$<" OR EXISTS "${dir}")
      list(APPEND kept "${dir}")
    else()
      message(STATUS "acdf: dropping missing include directory ${dir} from ${target}")
    endif()
  endforeach()
  set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${kept}")
endfunction()

acdf_drop_missing_include_dirs(OpenImageIO::OpenImageIO)
acdf_drop_missing_include_dirs(OpenImageIO::OpenImageIO_Util)

# acdf_library(<component> <source>...): the library acdf_<component>, called acdf::<component>
# both in this tree and in the installed package (acdfConfig.cmake). Its public headers are
# include/acdf/<component>/ beside the calling CMakeLists.txt and install to <prefix>/include;
# the library installs to <prefix>/lib with the project version as its shared-library version.
# Header-only private dependencies (Eigen, nlohmann json) are linked as $<BUILD_INTERFACE:…>, so
# they leave no trace in the installed package.
include(GNUInstallDirs)

function(acdf_library component)
  set(target acdf_${component})
  add_library(${target} ${ARGN})
  add_library(acdf::${component} ALIAS ${target})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_20)
  # 0.x: every minor version may break the ABI, so the SONAME carries major.minor.
  set_target_properties(${target} PROPERTIES
    EXPORT_NAME ${component}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    # A shared acdf library finds the ones it links beside itself (RUNPATH is not inherited).
    INSTALL_RPATH "$ORIGIN")
  if(ACDF_PYTHON)
    # Linked into the Python extension module, a shared object. Without semantic interposition
    # -fPIC still lets GCC inline the library's own functions into each other, as in a non-PIC build.
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-fno-semantic-interposition>)
  endif()
  install(TARGETS ${target} EXPORT acdfTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

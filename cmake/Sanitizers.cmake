# ACDF_SANITIZE: a comma-separated list for -fsanitize= (e.g. "address,undefined", or "thread"),
# applied to every target's compile and link lines. Empty (the default) builds without sanitizers.
# Meant for a separate build directory: `make test-asan` uses build-asan/, `make test-tsan`
# build-tsan/.
#
# ACDF_FUZZ: build the libFuzzer targets in fuzz/ (clang only). Every library gets coverage
# instrumentation (-fsanitize=fuzzer-no-link) plus ASan and UBSan; the fuzz programs link
# libFuzzer's main. Meant for its own build directory: `make fuzz` uses build-fuzz/.

set(ACDF_SANITIZE "" CACHE STRING "Sanitizers for -fsanitize= (empty, or e.g. address,undefined)")
set_property(CACHE ACDF_SANITIZE PROPERTY STRINGS "" "address,undefined" "thread")
option(ACDF_FUZZ "Build the libFuzzer targets in fuzz/ (clang only)" OFF)

if(ACDF_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "ACDF_FUZZ needs clang (libFuzzer), e.g. -DCMAKE_CXX_COMPILER=clang++")
  endif()
  if(ACDF_SANITIZE AND NOT ACDF_SANITIZE STREQUAL "address,undefined")
    message(FATAL_ERROR "ACDF_FUZZ builds with address,undefined; leave ACDF_SANITIZE empty")
  endif()
  set(ACDF_SANITIZE "address,undefined")
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

if(ACDF_SANITIZE)
  # Any UBSan finding aborts the program, so ctest sees it as a failure instead of a log line.
  set(_acdf_sanitize_flags -fsanitize=${ACDF_SANITIZE} -fno-omit-frame-pointer)
  if(ACDF_SANITIZE MATCHES "undefined")
    list(APPEND _acdf_sanitize_flags -fno-sanitize-recover=undefined)
  endif()
  add_compile_options(${_acdf_sanitize_flags})
  if(ACDF_SANITIZE MATCHES "thread")
    # The renderer runs its tiles on std::threads instead of TBB (integrator/src/renderer.cpp).
    add_compile_definitions(ACDF_THREAD_SANITIZER)
  endif()
  add_link_options(${_acdf_sanitize_flags})
  message(STATUS "acdf: sanitizers enabled: ${ACDF_SANITIZE}")
  unset(_acdf_sanitize_flags)
endif()

# Option parsing, gtest macros and JSON are most of a sanitizer build's compile time, and at -O1
# they compile in two-thirds of the time -O2 takes. apps/ and tests/ call this; the libraries,
# where the tests spend their time, keep the build type's optimisation.
macro(acdf_optimize_less_when_sanitized)
  if(ACDF_SANITIZE)
    add_compile_options(-O1)
  endif()
endmacro()

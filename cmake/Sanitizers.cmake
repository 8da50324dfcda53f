# ACDF_SANITIZE: a comma-separated list for -fsanitize= (e.g. "address,undefined"), applied to
# every target's compile and link lines. Empty (the default) builds without sanitizers.
# Meant for a separate build directory: `make test-asan` uses build-asan/.

set(ACDF_SANITIZE "" CACHE STRING "Sanitizers for -fsanitize= (empty, or e.g. address,undefined)")
set_property(CACHE ACDF_SANITIZE PROPERTY STRINGS "" "address,undefined")

if(ACDF_SANITIZE)
  # Any UBSan finding aborts the program, so ctest sees it as a failure instead of a log line.
  set(_acdf_sanitize_flags
    -fsanitize=${ACDF_SANITIZE}
    -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined)
  add_compile_options(${_acdf_sanitize_flags})
  add_link_options(${_acdf_sanitize_flags})
  message(STATUS "acdf: sanitizers enabled: ${ACDF_SANITIZE}")
  unset(_acdf_sanitize_flags)
endif()

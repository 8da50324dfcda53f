# ctest helper: runs PROGRAM and passes only if it exits non-zero and its output contains every
# string of the ;-separated list EXPECTED, so a test can check that a wrong program fails loudly.
#   cmake -DPROGRAM=<path> "-DEXPECTED=<a>;<b>" -P expect_failure.cmake
execute_process(COMMAND ${PROGRAM} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(output "${out}${err}")
if(status EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} exited 0; it should have failed:\n${output}")
endif()
foreach(text IN LISTS EXPECTED)
  string(FIND "${output}" "${text}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${PROGRAM} failed without saying '${text}':\n${output}")
  endif()
endforeach()
message(STATUS "${PROGRAM} failed as expected (exit ${status})")

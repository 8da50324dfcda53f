# cmake -DBUILD_DIR=… -DEXAMPLES_DIR=… -DWORK_DIR=… -DGENERATOR=… -DACDF=… -DMAP=…
#       [-DPYTHON=… -DPYTHON_SITE_DIR=…] -P this file
#
# Installs BUILD_DIR into WORK_DIR/prefix, builds EXAMPLES_DIR against it (find_package(acdf) must
# resolve to the staging prefix), runs both examples and checks that each one's two estimators
# (the adaptive table, cosine sampling) agree within 5 standard errors. With PYTHON, the same for
# examples/python/quickstart.py run on the module installed in the prefix's site-packages.

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    list(JOIN ARGN " " command)
    message(FATAL_ERROR "failed (${status}): ${command}\n${out}\n${err}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

# The two "name  mean +- stderr" lines an example prints must agree within 5 combined errors.
function(expect_agreement output first second)
  foreach(name IN ITEMS first second)
    string(REGEX MATCH "${${name}} +([-+.eE0-9]+) \\+- ([-+.eE0-9]+)" line "${output}")
    if(NOT line)
      message(FATAL_ERROR "no '${${name}}' estimate in:\n${output}")
    endif()
    set(${name}_mean ${CMAKE_MATCH_1})
    set(${name}_error ${CMAKE_MATCH_2})
  endforeach()
  set(a ${first_mean})
  set(b ${second_mean})
  set(ea ${first_error})
  set(eb ${second_error})
  # CMake has no floating point; awk does: |a − b| <= 5 √(ea² + eb²), squared, and a > 0.
  execute_process(COMMAND awk "BEGIN { d = ${a} - (${b}); exit !(d * d <= 25 * (${ea} * ${ea} + ${eb} * ${eb}) && ${a} > 0) }"
                  RESULT_VARIABLE disagree)
  if(NOT disagree EQUAL 0)
    message(FATAL_ERROR "estimates disagree: ${first} ${a} +- ${ea}, ${second} ${b} +- ${eb}")
  endif()
  message(STATUS "agree: ${first} ${a} +- ${ea}, ${second} ${b} +- ${eb}")
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(installed IN ITEMS include/acdf/sampling/cascade.h include/acdf/envmap/environment_light.h
                           include/acdf/brdf/merl.h include/acdf/integrator/renderer.h
                           lib/cmake/acdf/acdfConfig.cmake lib/cmake/acdf/acdfConfigVersion.cmake)
  if(NOT EXISTS ${prefix}/${installed})
    message(FATAL_ERROR "not installed: ${installed}")
  endif()
endforeach()

run(${CMAKE_COMMAND} -S ${EXAMPLES_DIR} -B ${WORK_DIR}/build -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS ${WORK_DIR}/build/CMakeCache.txt found REGEX "^acdf_DIR:")
if(NOT found STREQUAL "acdf_DIR:PATH=${prefix}/lib/cmake/acdf")
  message(FATAL_ERROR "find_package(acdf) did not use the staging prefix: ${found}")
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)

run(${WORK_DIR}/build/sample_environment ${MAP} 200000)
message(STATUS "${output}")
expect_agreement("${output}" "light table" "cosine hemisphere")

run(${ACDF} merl-gen --preset gold -o ${WORK_DIR}/gold.binary)
run(${WORK_DIR}/build/sample_merl ${WORK_DIR}/gold.binary 45 200000)
message(STATUS "${output}")
expect_agreement("${output}" "adaptive table" "cosine hemisphere")

if(PYTHON)
  set(site ${prefix}/${PYTHON_SITE_DIR})
  file(GLOB module ${site}/acdf/_acdf*.so)
  if(NOT module)
    message(FATAL_ERROR "the Python module is not installed in ${site}")
  endif()
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c "print(__import__('acdf').__file__)")
  if(NOT output MATCHES "^${site}/")
    message(FATAL_ERROR "Python imported acdf from ${output}, not from ${site}")
  endif()
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} ${EXAMPLES_DIR}/python/quickstart.py ${MAP} 200000)
  message(STATUS "${output}")
  expect_agreement("${output}" "light table" "cosine hemisphere")
endif()

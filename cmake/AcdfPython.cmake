# ACDF_PYTHON: the Python module `acdf` (python/, docs/python.md), built with Debian's pybind11 for
# ACDF_PYTHON_EXECUTABLE (/usr/bin/python3, the interpreter Debian's python3-numpy belongs to).
# On by default, except in sanitizer and fuzz builds (an instrumented module would need the
# sanitizer runtime preloaded into the interpreter). Without pybind11 or the interpreter's headers
# the module is left out with a warning; install-deps installs both.
set(_acdf_python_default ON)
if(ACDF_SANITIZE OR ACDF_FUZZ)
  set(_acdf_python_default OFF)
endif()
option(ACDF_PYTHON "Build the Python module acdf (pybind11)" ${_acdf_python_default})
# A wheel (pyproject.toml, scikit-build-core) is tagged for the interpreter that builds it.
if(SKBUILD)
  set(_acdf_python_executable ${PYTHON_EXECUTABLE})
else()
  set(_acdf_python_executable /usr/bin/python3)
endif()
set(ACDF_PYTHON_EXECUTABLE ${_acdf_python_executable} CACHE FILEPATH "The Python interpreter the module is built for")

if(ACDF_PYTHON)
  # pybind11's own Python lookup (FindPythonLibsNew) takes the interpreter from PYTHON_EXECUTABLE.
  set(PYTHON_EXECUTABLE ${ACDF_PYTHON_EXECUTABLE} CACHE FILEPATH "" FORCE)
  find_package(pybind11 CONFIG QUIET)
  if(NOT pybind11_FOUND AND SKBUILD)
    message(FATAL_ERROR "acdf: pybind11 not found (Debian: pybind11-dev python3-dev); a wheel needs it")
  elseif(NOT pybind11_FOUND)
    message(WARNING "acdf: pybind11 not found (Debian: pybind11-dev python3-dev); the Python module is not built")
    set(ACDF_PYTHON OFF)
  endif()
endif()

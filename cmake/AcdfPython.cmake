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
set(ACDF_PYTHON_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python interpreter the module is built for")

if(ACDF_PYTHON)
  # pybind11's own Python lookup (FindPythonLibsNew) takes the interpreter from PYTHON_EXECUTABLE.
  set(PYTHON_EXECUTABLE ${ACDF_PYTHON_EXECUTABLE} CACHE FILEPATH "" FORCE)
  find_package(pybind11 CONFIG QUIET)
  if(NOT pybind11_FOUND)
    message(WARNING "acdf: pybind11 not found (Debian: pybind11-dev python3-dev); the Python module is not built")
    set(ACDF_PYTHON OFF)
  endif()
endif()

# ACDF_PYTHON: the Python module `acdf` (python/, docs/python.md), built for ACDF_PYTHON_EXECUTABLE
# (/usr/bin/python3, the interpreter Debian's python3-numpy belongs to) with PyPI's pybind11 at
# pyproject.toml's pin: in .venv (scripts/install-deps) for this tree, in the build environment for
# a wheel. Debian 12's pybind11 2.10 is refused: before 2.12 it misreads NumPy 2's arrays (every
# row of a batch came back as row 0's). On by default, except in sanitizer and fuzz builds (an
# instrumented module would need the sanitizer runtime preloaded into the interpreter). Without
# pybind11 or the interpreter's headers the module is left out with a warning.
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
  # pybind11's Python lookup takes the interpreter from PYTHON_EXECUTABLE (FindPythonLibsNew) or
  # Python_EXECUTABLE (FindPython, pybind11 3's default).
  set(PYTHON_EXECUTABLE ${ACDF_PYTHON_EXECUTABLE} CACHE FILEPATH "" FORCE)
  set(Python_EXECUTABLE ${ACDF_PYTHON_EXECUTABLE} CACHE FILEPATH "" FORCE)
  set(_pybind11_provider ${PROJECT_SOURCE_DIR}/.venv/bin/python)
  if(SKBUILD)
    set(_pybind11_provider ${PYTHON_EXECUTABLE})
  endif()
  execute_process(COMMAND ${_pybind11_provider} -m pybind11 --cmakedir
                  OUTPUT_VARIABLE _pybind11_cmakedir OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  find_package(pybind11 2.12 CONFIG QUIET HINTS ${_pybind11_cmakedir} NO_SYSTEM_ENVIRONMENT_PATH)
  set(_pybind11_missing "pybind11 >= 2.12 not found (scripts/install-deps puts PyPI's in .venv)")
  if(NOT pybind11_FOUND AND SKBUILD)
    message(FATAL_ERROR "acdf: ${_pybind11_missing}; a wheel needs it")
  elseif(NOT pybind11_FOUND)
    message(WARNING "acdf: ${_pybind11_missing}; the Python module is not built")
    set(ACDF_PYTHON OFF)
  endif()
endif()

// The compiled extension acdf._acdf behind the package acdf (python/acdf/__init__.py re-exports it):
// numpy in, numpy out, batched (docs/python.md).
#include <pybind11/pybind11.h>

#include "acdf/sampling/file_error.h"
#include "bindings.h"

namespace py = pybind11;

PYBIND11_MODULE(_acdf, m) {
  // Classes, the exception and the signatures in docstrings take their module from __name__ when
  // they are made: they should name the package users import (acdf.Cascade, acdf.FileError), not
  // the private extension. The import system expects its own name back once the module is built.
  const py::object extensionName = m.attr("__name__");
  m.attr("__name__") = "acdf";
  m.attr("__version__") = ACDF_VERSION;
  m.doc() = R"(acdf: adaptive cascaded numerical CDFs for importance sampling (Lawrence et al. 2005).

Every call is batched: variates, points and directions are numpy arrays with one row per sample,
and the loop over rows runs in C++ (without the GIL and on oneTBB's threads from 8192 rows on).

Conventions
  Variates u are float32 in [0, 1) (values outside are clamped into it). Table coordinates are
  float32; directions are float64 unit vectors, shape (n, 3). Densities of tables are per unit of
  the table's domain (the product measure of its axes); densities of directions are per steradian.
  Environment maps are lat-long in OpenEXR's layout: +Y up, row 0 at the top (theta = 0), column
  0 at phi = 0; see EnvironmentLight. BRDF directions are in the local shading frame, z = normal.

Errors
  Bad arguments and bad values raise ValueError naming the argument or option; an unreadable,
  missing or malformed file raises acdf.FileError (an OSError) whose message is "file: problem".)";

  // FileError carries the file and the problem in what(); OSError is what Python code catches for
  // a file it could not use.
  py::register_exception<acdf::FileError>(m, "FileError", PyExc_OSError);

  acdf::python::bindSampling(m);
  acdf::python::bindEnvmap(m);
  acdf::python::bindBrdf(m);
  acdf::python::bindProductSampling(m);
  acdf::python::bindOpenings(m);
  m.attr("__name__") = extensionName;
}

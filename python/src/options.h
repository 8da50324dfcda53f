#pragma once
// The simplification options every table binding takes: an acdf.SimplifyOptions, with an
// `epsilon` keyword that overrides its tolerance (the option users change most).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>

#include "acdf/sampling/simplify.h"

namespace acdf::python {

// `base` when nothing is given; the result is validated (OptionError, a ValueError in Python).
inline SimplifyOptions simplifyOptions(SimplifyOptions base, const std::optional<SimplifyOptions>& simplify,
                                       std::optional<double> epsilon) {
  SimplifyOptions o = simplify.value_or(base);
  if (epsilon) o.epsilon = *epsilon;
  validate(o);
  return o;
}

}  // namespace acdf::python

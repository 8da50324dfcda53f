#pragma once
// The parts of the module, one per library (module.cpp calls them in this order: the BRDF and
// environment classes use the sampling ones, product sampling both).
#include <pybind11/pybind11.h>

namespace acdf::python {

void bindSampling(pybind11::module_& m);
void bindEnvmap(pybind11::module_& m);
void bindBrdf(pybind11::module_& m);
void bindProductSampling(pybind11::module_& m);

}  // namespace acdf::python

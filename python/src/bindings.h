#pragma once
// The parts of the module, one per library (module.cpp calls them in this order: the BRDF and
// environment classes use the sampling ones, product sampling both).
#include <pybind11/pybind11.h>

namespace acdf {
class Cascade;
}

namespace acdf::python {

// The 1D CDFs of each sampled axis of a cascade, for sampling it in other arithmetic
// (Cascade.arrays, EnvironmentLight.cascade_arrays): one dict per sampled axis with "start" (CDF k's
// breakpoints are [start[k], start[k + 1])), "vertex" (each breakpoint's grid vertex) and "value"
// (the CDF there), the CDFs laid end to end in Cascade::breakpoints' order.
pybind11::list cascadeArrays(const Cascade& cascade);

void bindSampling(pybind11::module_& m);
void bindEnvmap(pybind11::module_& m);
void bindBrdf(pybind11::module_& m);
void bindProductSampling(pybind11::module_& m);

}  // namespace acdf::python

#pragma once
// The parts of the module, one per library (module.cpp calls them in this order: the BRDF and
// environment classes use the sampling ones, product sampling both; the openings none).
#include <pybind11/pybind11.h>

#include <span>

namespace acdf {
class Cascade;
}

namespace acdf::python {

// The 1D CDFs of each sampled axis of a cascade, for sampling it in other arithmetic
// (Cascade.arrays, EnvironmentLight.cascade_arrays): one dict per sampled axis with "start" (CDF k's
// breakpoints are [start[k], start[k + 1])), "vertex" (each breakpoint's grid vertex) and "value"
// (the CDF there), the CDFs laid end to end in Cascade::breakpoints' order.
pybind11::list cascadeArrays(const Cascade& cascade);
// The same for cascades of one shape laid end to end (each axis' CDFs of the first, then of the
// second, ...): the first axis' CDFs of the i-th come after those of the ones before it, and below
// interval j of an axis' CDFs, counted across all the cascades in order, still lies CDF j of the
// next axis.
pybind11::list cascadeArrays(std::span<const Cascade* const> cascades);

void bindSampling(pybind11::module_& m);
void bindEnvmap(pybind11::module_& m);
void bindBrdf(pybind11::module_& m);
void bindProductSampling(pybind11::module_& m);
void bindOpenings(pybind11::module_& m);

}  // namespace acdf::python

#include "acdf/sampling/piecewise_constant_1d.h"

#include "acdf/sampling/grid_check.h"
#include "breakpoint_cdf.h"

namespace acdf {

PiecewiseConstant1D::PiecewiseConstant1D(std::span<const float> function, float lo, float hi)
    : axis_(static_cast<uint32_t>(function.size()), lo, hi) {
  checkNonNegativeFinite(function);
  cdf_.reserve(function.size() + 1);
  integral_ = detail::appendCdf(function, cdf_) * axis_.cellWidth();
}

namespace {
// The stored CDF keeps its end points (cdf() reports them); the view skips them.
detail::BreakpointCdf view(std::span<const float> cdf) {
  return {cdf.data() + 1, cdf.size(), static_cast<uint32_t>(cdf.size() - 1)};
}
}  // namespace

Sample1D PiecewiseConstant1D::sample(float u) const { return sample(cdf_, axis_, u); }

Sample1D PiecewiseConstant1D::sample(std::span<const float> cdf, const GridAxis& axis, float u) {
  const detail::Draw d = detail::draw(view(cdf), axis, clampUnit(u));
  return {d.placed.x, clampDensity(d.density)};
}

float PiecewiseConstant1D::pdf(float x) const {
  if (!axis_.contains(x)) return 0.0f;
  return clampDensity(detail::lookup(view(cdf_), axis_, x).density);
}

float PiecewiseConstant1D::invert(float x) const { return detail::invert(view(cdf_), axis_, x); }

}  // namespace acdf

#include "acdf/sampling/adaptive_cdf_1d.h"

#include "acdf/sampling/grid_check.h"
#include "breakpoint_cdf.h"

namespace acdf {

AdaptiveCdf1D::AdaptiveCdf1D(std::span<const float> function, float lo, float hi, const SimplifyOptions& options)
    : axis_(static_cast<uint32_t>(function.size()), lo, hi), vertices_(axis_.cells()) {
  checkNonNegativeFinite(function);
  validate(options);
  std::vector<float> uniform;
  uniform.reserve(function.size() + 1);
  integral_ = detail::appendCdf(function, uniform) * axis_.cellWidth();
  const std::vector<uint32_t> kept = simplifyCdf(uniform, options);
  cdf_.reserve(kept.size());
  vertices_.reserve(kept.size());
  for (uint32_t v : kept) {
    cdf_.push_back(uniform[v]);
    vertices_.push_back(v);
  }
}

namespace {
// The stored CDF keeps its end points (cdfAt() reports them); the view skips them.
detail::BreakpointCdf view(const std::vector<float>& cdf, const VertexIndices& vertices, uint32_t cells) {
  return {cdf.data() + 1, cdf.size(), cells, &vertices, 1};
}
}  // namespace

Sample1D AdaptiveCdf1D::sample(float u) const {
  const detail::Draw d = detail::draw(view(cdf_, vertices_, axis_.cells()), axis_, clampUnit(u));
  return {d.placed.x, clampDensity(d.density)};
}

float AdaptiveCdf1D::pdf(float x) const {
  if (!axis_.contains(x)) return 0.0f;
  return clampDensity(detail::lookup(view(cdf_, vertices_, axis_.cells()), axis_, x).density);
}

float AdaptiveCdf1D::invert(float x) const { return detail::invert(view(cdf_, vertices_, axis_.cells()), axis_, x); }

}  // namespace acdf

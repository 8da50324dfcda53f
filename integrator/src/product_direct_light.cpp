#include "acdf/integrator/product_direct_light.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "acdf/sampling/option_error.h"

namespace acdf {

namespace {

// Rgb::luminance's weights, in double: positive for any non-black, non-negative RGB.
double luminance(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

bool isFinite(const Rgb& c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }

}  // namespace

void validate(const ProductSamplingOptions& options) {
  if (options.candidates < 1 || options.candidates > 1024)
    throw OptionError("product sampling", "candidates", "must be an integer in [1, 1024]");
  if (!(options.bsdfFraction >= 0 && options.bsdfFraction <= 1))
    throw OptionError("product sampling", "bsdf_fraction",
                      "must be in [0, 1], got " + OptionError::number(options.bsdfFraction));
}

ProductDirectLight::ProductDirectLight(const EnvironmentLight& light, const LightSampleContext& context,
                                       const BrdfSampler& material, const Frame& frame, const Vec3d& wo,
                                       const ProductSamplingOptions& options)
    : ProductDirectLight(light, context, material.vertex(wo), frame, options) {}

ProductDirectLight::ProductDirectLight(const EnvironmentLight& light, const LightSampleContext& context,
                                       const BrdfVertex& material, const Frame& frame,
                                       const ProductSamplingOptions& options)
    : light_(light), context_(context), material_(material), frame_(frame), options_(options) {}

std::optional<ProductLightSample> ProductDirectLight::sample(CandidateValues& values) const {
  // Weighted reservoir sampling: candidate i replaces the kept one with probability
  // p_i = w_i / Σ_{k≤i} w_k, so candidate j is kept with probability w_j / Σ w, in one pass
  // without storing the candidates. One uniform u decides every step: u < p_i replaces, and u is
  // rescaled to the part of [0, 1) it fell in, which leaves it uniform and independent of the
  // decisions so far; a stratified u keeps the choice stratified over the pixel's samples.
  constexpr double kBelowOne = 0x1.fffffffffffffp-1;
  double u = values.resamplingValue(), weightSum = 0;
  Candidate chosen;
  for (uint32_t i = 0; i < options_.candidates; ++i) {
    const Candidate c = candidate(values.point(i));
    if (!(c.weight > 0)) continue;
    weightSum += c.weight;
    const double p = c.weight / weightSum;
    if (u < p) {
      chosen = c;
      u = std::min(u / p, kBelowOne);
    } else {
      u = std::min((u - p) / (1 - p), kBelowOne);
    }
  }
  if (!(weightSum > 0)) return std::nullopt;
  const Rgb estimate = chosen.integrand * static_cast<float>(weightSum / (options_.candidates * chosen.target));
  if (!isFinite(estimate)) return std::nullopt;
  return ProductLightSample{chosen.direction, estimate, chosen.mixturePdf};
}

double ProductDirectLight::mixturePdf(const Vec3d& w) const {
  const double b = options_.bsdfFraction;
  const double lightPdf = b < 1 ? light_.pdf(context_, w) : 0.0;
  const double bsdfPdf = b > 0 ? material_.pdf(frame_.toLocal(w)) : 0.0;
  return (1 - b) * lightPdf + b * bsdfPdf;
}

ProductDirectLight::Candidate ProductDirectLight::candidate(const std::array<float, 2>& u) const {
  // The strategy from u[0], which is then stretched back over [0, 1) (the samplers clamp a
  // rounded 1 into it), so that stratified points stay stratified within each strategy. A
  // direction below the horizon has weight 0 and is never chosen: nothing else of it is found.
  const double b = options_.bsdfFraction;
  if (u[0] < b) {
    // The direction alone: weighed() evaluates f there.
    const SampledDirection s = material_.sampleDirection(static_cast<float>(u[0] / b), u[1]);
    if (!(s.wi.z > 0)) return {};
    const Vec3d direction = normalize(frame_.toWorld(s.wi));
    if (b == 1) return weighed(direction, s.wi, light_.eval(direction), 0.0, s.pdf);
    const RadianceAndPdf L = light_.evalWithPdf(context_, direction);
    return weighed(direction, s.wi, L.radiance, L.pdf, s.pdf);
  }
  const LightSample l = light_.sample(context_, static_cast<float>((u[0] - b) / (1 - b)), u[1]);
  if (!(l.pdf > 0)) return {};  // a light that emits nothing
  const Vec3d wi = frame_.toLocal(l.direction);
  if (!(wi.z > 0)) return {};
  return weighed(l.direction, wi, l.radiance, l.pdf, b > 0 ? material_.pdf(wi) : 0.0);
}

ProductDirectLight::Candidate ProductDirectLight::weighed(const Vec3d& direction, const Vec3d& wi, const Rgb& radiance,
                                                          double lightPdf, double bsdfPdf) const {
  const double b = options_.bsdfFraction;
  Candidate c;
  c.direction = direction;
  c.mixturePdf = (1 - b) * lightPdf + b * bsdfPdf;
  if (radiance.isBlack() || !(c.mixturePdf > 0)) return c;
  c.integrand = material_.eval(wi) * radiance * static_cast<float>(wi.z);
  if (!isFinite(c.integrand)) return c;
  c.target = luminance(c.integrand);
  const double weight = c.target / c.mixturePdf;
  if (std::isfinite(weight)) c.weight = weight;
  return c;
}

}  // namespace acdf

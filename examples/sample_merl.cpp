// A MERL material sampled with acdf's adaptive table, given the outgoing direction ωo: the
// directional albedo a(ωo) = ∫ f(ωo, ωi) cosθi dωi, estimated in your own loop with the same
// sample count by the table and by cosine-weighted hemisphere sampling. Each sample's weight is
// f·cosθi/pdf, what a path tracer multiplies its throughput by.
//
//   sample_merl MATERIAL.binary [THETA_O_DEGREES] [SAMPLES]
//
// Directions are in the surface's local frame: the normal is +z.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <numbers>
#include <random>

#include "acdf/brdf/merl.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "running_estimate.h"

namespace {

// Mean albedo (luminance) and its standard error with `sampler` at ωo.
RunningEstimate albedo(const acdf::BrdfSampler& sampler, const acdf::Vec3d& wo, long samples) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  RunningEstimate e;
  for (long i = 0; i < samples; ++i) {
    const acdf::BrdfSample s = sampler.sample(wo, uniform(rng), uniform(rng));
    e.add(s.weight.luminance());  // 0 below the horizon
  }
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MATERIAL.binary [THETA_O_DEGREES] [SAMPLES]\n", argv[0]);
    return 2;
  }
  const double thetaO = (argc > 2 ? std::atof(argv[2]) : 45.0) * std::numbers::pi / 180.0;
  const long samples = argc > 3 ? std::atol(argv[3]) : 100000;
  try {
    const auto material = std::make_shared<const acdf::MerlBrdf>(acdf::MerlBrdf::load(argv[1]));
    // An isotropic table (θo, and the half vector relative to ωo): MERL materials are isotropic.
    acdf::TabulatedBrdfOptions options;
    options.layout = acdf::TabulatedBrdfOptions::Layout::Isotropic;
    const acdf::TabulatedBrdfSampler table(material, options);
    const acdf::CosineBrdfSampler cosine(material);

    const acdf::Vec3d wo{std::sin(thetaO), 0.0, std::cos(thetaO)};
    const RunningEstimate a = albedo(table, wo, samples), b = albedo(cosine, wo, samples);
    std::printf("%s: %s table of %zu bytes\n", argv[1], table.name().c_str(), table.bytes());
    std::printf("albedo at theta_o = %g degrees, %ld samples each:\n", thetaO * 180.0 / std::numbers::pi, samples);
    std::printf("  adaptive table    %.6g +- %.2g\n", a.mean(), a.standardError());
    std::printf("  cosine hemisphere %.6g +- %.2g\n", b.mean(), b.standardError());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}

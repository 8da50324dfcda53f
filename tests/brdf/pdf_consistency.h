#pragma once
// The contract of BrdfSampler::sample() (brdf_sampler.h) measured: the pdf a sample reports,
// computed along the sampling path, against pdf(ωo, ωi) at the sampled ωi, over random ωo
// (cosine-distributed above the horizon) and variates. They differ by the round trip's float
// rounding only.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/sampling/rng.h"

namespace acdf::test {

struct PdfConsistency {
  uint64_t samples = 0;
  uint64_t mismatches = 0;  // relative difference above the tolerance
  double worst = 0;         // the largest relative difference of the others
};

inline PdfConsistency measurePdfConsistency(const BrdfSampler& sampler, uint64_t samples, double tolerance,
                                            uint64_t seed = 5) {
  Pcg32 rng(seed);
  PdfConsistency c;
  c.samples = samples;
  for (uint64_t n = 0; n < samples; ++n) {
    const Vec3d wo = sampleCosineHemisphere(rng.nextFloat(), rng.nextFloat());
    const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
    const BrdfSample s = sampler.sample(wo, u0, u1);
    const double relative = std::fabs(sampler.pdf(wo, s.wi) - s.pdf) / s.pdf;
    if (relative > tolerance)
      ++c.mismatches;
    else
      c.worst = std::max(c.worst, relative);
  }
  return c;
}

}  // namespace acdf::test

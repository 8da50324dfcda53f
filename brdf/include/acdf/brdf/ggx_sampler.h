#pragma once
// Sampling of an AnalyticBrdf by its GGX distribution: the half vector ωh ∝ D(ωh) cosθh (the
// projected microfacet area, which integrates to 1 over the hemisphere), then ωi = reflect(ωo, ωh),
// so p(ωi) = D(ωh) cosθh / (4 |ωo·ωh|) (half_vector.h). Inverting D cosθh's CDF in θh:
// tan²θh = α² u / (1 − u), φh = 2π u'.
//
// Exact in shape for the conductor's specular lobe; for the coated diffuse model it samples the
// coat's lobe (pdf > 0 wherever f·cosθi > 0, so estimators stay unbiased, at more variance for
// the diffuse base). No table: bytes() is 0.

#include <memory>
#include <string>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/brdf_sampler.h"

namespace acdf {

class GgxBrdfSampler final : public BrdfSampler {
 public:
  explicit GgxBrdfSampler(std::shared_ptr<const AnalyticBrdf> model);

  double pdf(const Vec3d& wo, const Vec3d& wi) const override;
  // D(ωh) cosθh per steradian of ωh; 0 below the horizon.
  double halfVectorPdf(const Vec3d& wh) const;
  // All of it reflected; the smooth density on 256 × 32 cells in (√θh, φh) follows the peak.
  HalfVectorDensity halfVectorDensity(const Vec3d& wo) const override;

  std::size_t bytes() const override { return 0; }
  std::string name() const override { return "ggx"; }

 protected:
  SampledDirection sampleDirection(const Vec3d& wo, float u0, float u1) const override;

 private:
  double alpha_;
};

}  // namespace acdf

#pragma once
// Sampling of an AnalyticBrdf by the GGX distribution of the normals ωo sees (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals"), as pbrt-v4 and Mitsuba 3 sample GGX: the
// half vector ωh with the visible-normal density
//
//   D_ωo(ωh) = G1(ωo) max(0, ωo·ωh) D(ωh) / cosθo,
//
// then ωi = reflect(ωo, ωh), so p(ωi) = D_ωo(ωh) / (4 ωo·ωh) = G1(ωo) D(ωh) / (4 cosθo)
// (half_vector.h), and a conductor's weight f cosθi / p is F G1(ωi) <= 1. Sampling D(ωh) cosθh
// instead (Walter et al. 2007) weighs F G1(ωi) G1(ωo) (ωo·ωh) / (cosθo cosθh), which near grazing
// ωo exceeds 1 many times over. The visible normals are drawn as Dupuy & Benyoub 2023 do
// ("Sampling Visible GGX Normals with Spherical Caps"): in the configuration where the
// microsurface is the unit hemisphere (x and y divided by α), the visible normals are uniform on a
// spherical cap around ωo.
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
  // D_ωo(ωh) per steradian of ωh, for ωo above the horizon; 0 where ωo·ωh <= 0 or ωh is below it.
  double visibleNormalPdf(const Vec3d& wo, const Vec3d& wh) const;
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

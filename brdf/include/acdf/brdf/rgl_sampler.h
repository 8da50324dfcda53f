#pragma once
// The RGL format's own importance sampler (Dupuy & Jakob 2018, §5; pbrt-v4's
// MeasuredBxDF::Sample_f, Mitsuba 3's `measured`): the two warps stored in the file, conditioned
// on ωo's angles (rgl.h):
//   1. the luminance warp maps the variates u to a point s of the sample domain;
//   2. the visible-NDF warp maps s to the half vector's unit coordinates um = (v(φm − φo), u(θm));
//   3. ωi = reflect(ωo, ωm).
// Both warps are Bilinear2D, so the density of um is the product of their densities,
// p(um) = p_lum(s) · p_vndf(um) (the second warp's Jacobian is 1 / p_vndf), and with
// θ = u²·π/2, φ = 2π v − π, dωm = 2π² u sinθm du dv:
//   p(ωm) = p_lum(s) p_vndf(um) / (2π² u sinθm),   p(ωi) = p(ωm) / (4 |ωo·ωm|).
// pdf() inverts the visible-NDF warp to find s (Bilinear2D::invert). With jacobian = 1 and
// luminance = Y(ρ) on the vertices this follows f·cosθi up to the tables' interpolation.
//
// No defensive mixture: this is the published sampler as renderers use it. Its density is > 0
// wherever both warps are, which the file's slices guarantee (none is zero everywhere) only where
// the visible NDF has mass. bytes() is the two warps' tables.

#include <memory>
#include <string>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/rgl.h"

namespace acdf {

class RglBrdfSampler final : public BrdfSampler {
 public:
  explicit RglBrdfSampler(std::shared_ptr<const RglBrdf> model);

  double pdf(const Vec3d& wo, const Vec3d& wi) const override;
  // p(ωm) per steradian of the half vector (upper hemisphere), given ωo above the horizon.
  double halfVectorPdf(const Vec3d& wo, const Vec3d& wm) const;
  // All of it reflected, on 64 × 32 cells in the warps' own (√θm, φm − φo + π), sub-cells uniform
  // in those coordinates (the density per steradian has a 1/θm spike at the pole); coarser than
  // GGX's since each evaluation inverts a warp.
  HalfVectorDensity halfVectorDensity(const Vec3d& wo) const override;

  std::size_t bytes() const override { return rgl_.warpBytes(); }
  std::string name() const override { return "rgl"; }

 protected:
  SampledDirection sampleDirection(const Vec3d& wo, float u0, float u1) const override;

 private:
  const RglBrdf& rgl_;
};

}  // namespace acdf

#pragma once
// Half-vector sampling: a sampler draws a half vector ωh in the upper hemisphere and reflects the
// outgoing direction about it, ωi = 2(ωo·ωh)ωh − ωo (sphere.h's reflect()). The reflection's
// Jacobian turns the half vector's density into the incident direction's (Walter et al. 2007,
// eq. 14):
//
//   p(ωi) = p(ωh) / (4 |ωo·ωh|),   ωh = ±normalize(ωi + ωo).
//
// The one place this is written: the half-vector samplers' sample() and pdf() and the chi-square
// test's binning use it.

#include <cmath>
#include <optional>

#include "acdf/sampling/sphere.h"

namespace acdf {

struct HalfVector {
  Vec3d direction;    // unit, z >= 0
  double cosOut = 0;  // |ωo·ωh| > 0

  // The density of ωi of a half-vector density p(ωh) at this half vector, both per steradian.
  double incidentPdf(double halfVectorPdf) const { return halfVectorPdf / (4.0 * cosOut); }

  // Whether ωi's density can be found again from ωi alone: as ωh turns perpendicular to ωo, ωi
  // nears −ωo and normalize(ωi + ωo) recovers ωh, and with it 1/(4|ωo·ωh|), only to about
  // 1e-16 / (ωo·ωh)² relative. Below |ωo·ωh| = 1e-3 a sampler reports pdf(ωo, ωi) itself (where
  // positive), so that its samples' densities and pdf() agree on every sample.
  bool roundTripExact() const { return cosOut >= 1e-3; }
};

// A half vector ωh (unit, z >= 0) a sampler drew to reflect ωo about: its density converts to
// ωi's along the sampling path, without finding ωh again from ωi.
inline HalfVector sampledHalfVector(const Vec3d& wo, const Vec3d& wh) { return {wh, std::fabs(dot(wo, wh))}; }

// The half vector reflecting ωo into ωi, taken in the upper hemisphere: ωh and −ωh reflect ωo
// alike, and half-vector samplers draw z >= 0 only, so exactly one of them can have been sampled.
// nullopt where no half vector gives ωi a finite density (ωi = −ωo).
inline std::optional<HalfVector> halfVectorOf(const Vec3d& wo, const Vec3d& wi) {
  const Vec3d sum = wi + wo;
  const double len = length(sum);
  if (!(len > 0.0)) return std::nullopt;
  Vec3d h = sum * (1.0 / len);
  if (h.z < 0.0) h = -h;
  const double cosOut = std::fabs(dot(wo, h));
  if (!(cosOut > 0.0)) return std::nullopt;
  return HalfVector{h, cosOut};
}

}  // namespace acdf

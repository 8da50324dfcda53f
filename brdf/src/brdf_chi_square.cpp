#include "acdf/brdf/brdf_chi_square.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/sampling/rng.h"

namespace acdf {

namespace {

constexpr double kPi = std::numbers::pi;

// 1 − cosθh at s = √(θh / (π/2)).
double capArea(double s) {
  const double h = std::sin(0.25 * kPi * s * s);
  return 2.0 * h * h;
}

Vec3d capDirection(double cap, double phi) {
  const double sinTheta = std::sqrt(cap * (2.0 - cap));
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), 1.0 - cap};
}

}  // namespace

std::vector<double> brdfBinProbabilities(const BrdfSampler& sampler, const Vec3d& wo, const SphereChiSquareOptions& o) {
  const auto* table = dynamic_cast<const TabulatedBrdfSampler*>(&sampler);
  if (!table && !dynamic_cast<const CosineBrdfSampler*>(&sampler))
    throw std::invalid_argument("brdf chi-square: unknown sampler " + sampler.name());
  if (!o.equalAreaRows || o.thetaBins % 2 != 0 || o.subPoints == 0)
    throw std::invalid_argument("brdf chi-square: needs equal-area rows, an even row count and subPoints > 0");
  std::vector<double> p(std::size_t{o.thetaBins} * o.phiBins, 0.0);
  const bool cosineOnly = !table || !(wo.z > 0.0);
  const double w = cosineOnly ? 1.0 : table->options().cosineWeight;
  // ∫ cosθ/π dω over an equal-area row z in [zb, za] above the horizon, φ in a bin of width
  // 2π/phiBins: (za² − zb²)/phiBins.
  for (uint32_t row = 0; row < o.thetaBins / 2; ++row) {
    const double za = 1.0 - 2.0 * row / o.thetaBins, zb = 1.0 - 2.0 * (row + 1) / o.thetaBins;
    for (uint32_t col = 0; col < o.phiBins; ++col)
      p[std::size_t{row} * o.phiBins + col] += w * (za * za - zb * zb) / o.phiBins;
  }
  if (cosineOnly || w == 1.0) return p;

  const TabulatedBrdfOptions& t = table->options();
  const double phiOrigin = t.layout == TabulatedBrdfOptions::Layout::Isotropic ? azimuth(wo) : 0.0;
  const double cellPhi = 2.0 * kPi / t.phiHalfCells;
  // Per row of s-cells in parallel, each with its own histogram and jitter stream, summed in order.
  std::vector<std::vector<double>> rows(t.thetaHalfCells);
  tbb::parallel_for(uint32_t{0}, t.thetaHalfCells, [&](uint32_t k) {
    std::vector<double>& row = rows[k];
    row.assign(p.size(), 0.0);
    Pcg32 jitter(o.seed, k);
    const double c0 = capArea(static_cast<double>(k) / t.thetaHalfCells);
    const double c1 = capArea(static_cast<double>(k + 1) / t.thetaHalfCells);
    for (uint32_t j = 0; j < t.phiHalfCells; ++j) {
      const Vec3d centre = capDirection(0.5 * (c0 + c1), phiOrigin + (j + 0.5) * cellPhi);
      const double mass = (1.0 - w) * table->halfVectorPdf(wo, centre) * (c1 - c0) * cellPhi;
      if (mass == 0.0) continue;
      // The reflection stretches solid angle by 1/(4 ωo·ωh): subdivide more where it is large.
      const double stretch = 0.25 / std::max(std::fabs(dot(wo, centre)), 1e-3);
      const uint32_t sub = o.subPoints * static_cast<uint32_t>(std::clamp(std::ceil(stretch), 1.0, 2.0));
      const double share = mass / (static_cast<double>(sub) * sub);
      for (uint32_t a = 0; a < sub; ++a)
        for (uint32_t b = 0; b < sub; ++b) {
          const double ta = (a + jitter.nextDouble()) / sub, tb = (b + jitter.nextDouble()) / sub;
          const Vec3d h = capDirection(c0 + ta * (c1 - c0), phiOrigin + (j + tb) * cellPhi);
          row[sphereBinOf(reflect(wo, h), o)] += share;
        }
    }
  });
  for (const auto& row : rows)
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += row[i];
  return p;
}

SphereChiSquareReport brdfChiSquareTest(const BrdfSampler& sampler, const Vec3d& wo, SphereChiSquareOptions options) {
  options.equalAreaRows = true;
  return sphereChiSquareTest(
      [&](float u0, float u1) {
        const BrdfSample s = sampler.sample(wo, u0, u1);
        return DirectionSample{s.wi, s.pdf};
      },
      [&](const Vec3d& wi) { return sampler.pdf(wo, wi); }, brdfBinProbabilities(sampler, wo, options), options);
}

}  // namespace acdf

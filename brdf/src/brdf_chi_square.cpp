#include "acdf/brdf/brdf_chi_square.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "acdf/brdf/half_vector.h"
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

// Adds `scale` × the grid's mass, sub-cell by sub-cell, to the bins of the reflected directions.
// Sub-cells are uniform in solid angle, each reflected at a jittered point.
void addReflectedMass(const HalfVectorDensity& grid, const Vec3d& wo, double scale, const SphereChiSquareOptions& o,
                      std::vector<double>& p) {
  const double cellPhi = 2.0 * kPi / grid.phiCells;
  // Per row of s-cells in parallel, each with its own histogram and jitter stream, summed in order.
  std::vector<std::vector<double>> rows(grid.sCells);
  tbb::parallel_for(uint32_t{0}, grid.sCells, [&](uint32_t k) {
    std::vector<double>& row = rows[k];
    row.assign(p.size(), 0.0);
    Pcg32 jitter(o.seed, k);
    const double c0 = capArea(static_cast<double>(k) / grid.sCells);
    const double c1 = capArea(static_cast<double>(k + 1) / grid.sCells);
    for (uint32_t j = 0; j < grid.phiCells; ++j) {
      const Vec3d centre = capDirection(0.5 * (c0 + c1), grid.phiOrigin + (j + 0.5) * cellPhi);
      const double cellMass = grid.constantPerCell ? scale * grid.density(centre) * (c1 - c0) * cellPhi : 1.0;
      if (cellMass == 0.0) continue;
      // The reflection squeezes solid angle by 4 |ωo·ωh| (half_vector.h): subdivide more where
      // the incident density it gives is large.
      const double stretch = HalfVector{centre, std::max(std::fabs(dot(wo, centre)), 1e-3)}.incidentPdf(1.0);
      const uint32_t sub = o.subPoints * static_cast<uint32_t>(std::clamp(std::ceil(stretch), 1.0, 2.0));
      const double subCells = static_cast<double>(sub) * sub;
      for (uint32_t a = 0; a < sub; ++a)
        for (uint32_t b = 0; b < sub; ++b) {
          const double ta = (a + jitter.nextDouble()) / sub, tb = (b + jitter.nextDouble()) / sub;
          if (grid.uniformInS) {
            const double s = (k + ta) / grid.sCells, thetaH = 0.5 * kPi * s * s,
                         phi = grid.phiOrigin + (j + tb) * cellPhi;
            const Vec3d h = sphericalDirection(thetaH, phi);
            const double perArea = grid.density(h) * std::sin(thetaH) * kPi * s;
            row[sphereBinOf(reflect(wo, h), o)] +=
                scale * perArea * cellPhi / (static_cast<double>(grid.sCells) * subCells);
            continue;
          }
          const Vec3d h = capDirection(c0 + ta * (c1 - c0), grid.phiOrigin + (j + tb) * cellPhi);
          const double share =
              grid.constantPerCell ? cellMass / subCells : scale * grid.density(h) * (c1 - c0) * cellPhi / subCells;
          row[sphereBinOf(reflect(wo, h), o)] += share;
        }
    }
  });
  for (const auto& row : rows)
    for (std::size_t i = 0; i < p.size(); ++i) p[i] += row[i];
}

}  // namespace

std::vector<double> brdfBinProbabilities(const BrdfSampler& sampler, const Vec3d& wo, const SphereChiSquareOptions& o) {
  if (!o.equalAreaRows || o.thetaBins % 2 != 0 || o.subPoints == 0)
    throw std::invalid_argument("brdf chi-square: needs equal-area rows, an even row count and subPoints > 0");
  std::vector<double> p(std::size_t{o.thetaBins} * o.phiBins, 0.0);
  // At or below the horizon every sampler falls back to cosine-weighted sampling.
  const HalfVectorDensity density = wo.z > 0.0 ? sampler.halfVectorDensity(wo) : HalfVectorDensity{};
  const double w = density.cosineShare;
  if (w < 1.0 && !density.density)
    throw std::invalid_argument("brdf chi-square: sampler " + sampler.name() + " describes no half-vector density");
  // ∫ cosθ/π dω over an equal-area row z in [zb, za] above the horizon, φ in a bin of width
  // 2π/phiBins: (za² − zb²)/phiBins.
  for (uint32_t row = 0; row < o.thetaBins / 2; ++row) {
    const double za = 1.0 - 2.0 * row / o.thetaBins, zb = 1.0 - 2.0 * (row + 1) / o.thetaBins;
    for (uint32_t col = 0; col < o.phiBins; ++col)
      p[std::size_t{row} * o.phiBins + col] += w * (za * za - zb * zb) / o.phiBins;
  }
  if (w < 1.0) addReflectedMass(density, wo, 1.0 - w, o, p);
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

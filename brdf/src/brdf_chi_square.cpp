#include "acdf/brdf/brdf_chi_square.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "acdf/brdf/ggx_sampler.h"
#include "acdf/brdf/half_vector.h"
#include "acdf/brdf/rgl_sampler.h"
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

// A half-vector density over the upper hemisphere, integrated on a grid of cells in
// (s, φh − phiOrigin): sCells × phiCells over [0, 1) × [0, 2π).
struct HalfVectorGrid {
  uint32_t sCells, phiCells;
  double phiOrigin;
  // Constant per cell (a table's), so one evaluation at the centre gives the cell's mass;
  // otherwise (a smooth density) each sub-cell is weighted by the density at its jittered point.
  bool constantPerCell;
  std::function<double(const Vec3d& wh)> density;
  // Smooth densities only: sub-cells uniform in (s, φh) instead of solid angle, each weighted by
  // the density per unit (s, φh) area, p(ωh) sinθh dθh/ds = p(ωh) sinθh π s — bounded where
  // p(ωh) per steradian is not (the RGL warps' p ~ 1/s² at the pole).
  bool uniformInS = false;
};

// Adds `scale` × the grid's mass, sub-cell by sub-cell, to the bins of the reflected directions.
// Sub-cells are uniform in solid angle, each reflected at a jittered point.
void addReflectedMass(const HalfVectorGrid& grid, const Vec3d& wo, double scale, const SphereChiSquareOptions& o,
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

// GGX's density is smooth: a grid as fine as a default table's, in s to follow the peak.
constexpr uint32_t kGgxSCells = 256, kGgxPhiCells = 32;
// The RGL warps' density is bilinear in (s, v) patches of the visible-NDF table, with the
// luminance warp on top: smooth enough for a coarser grid, which matters since each of its
// evaluations inverts a warp.
constexpr uint32_t kRglSCells = 64, kRglPhiCells = 32;

}  // namespace

std::vector<double> brdfBinProbabilities(const BrdfSampler& sampler, const Vec3d& wo, const SphereChiSquareOptions& o) {
  const auto* table = dynamic_cast<const TabulatedBrdfSampler*>(&sampler);
  const auto* ggx = dynamic_cast<const GgxBrdfSampler*>(&sampler);
  const auto* rgl = dynamic_cast<const RglBrdfSampler*>(&sampler);
  if (!table && !ggx && !rgl && !dynamic_cast<const CosineBrdfSampler*>(&sampler))
    throw std::invalid_argument("brdf chi-square: unknown sampler " + sampler.name());
  if (!o.equalAreaRows || o.thetaBins % 2 != 0 || o.subPoints == 0)
    throw std::invalid_argument("brdf chi-square: needs equal-area rows, an even row count and subPoints > 0");
  std::vector<double> p(std::size_t{o.thetaBins} * o.phiBins, 0.0);
  // The cosine-weighted share: all of it for the cosine sampler and below the horizon, the
  // defensive mixture's for a table, none for GGX and the RGL warps.
  double w = 1.0;
  if (wo.z > 0.0 && table) w = table->options().cosineWeight;
  if (wo.z > 0.0 && (ggx || rgl)) w = 0.0;
  // ∫ cosθ/π dω over an equal-area row z in [zb, za] above the horizon, φ in a bin of width
  // 2π/phiBins: (za² − zb²)/phiBins.
  for (uint32_t row = 0; row < o.thetaBins / 2; ++row) {
    const double za = 1.0 - 2.0 * row / o.thetaBins, zb = 1.0 - 2.0 * (row + 1) / o.thetaBins;
    for (uint32_t col = 0; col < o.phiBins; ++col)
      p[std::size_t{row} * o.phiBins + col] += w * (za * za - zb * zb) / o.phiBins;
  }
  if (w == 1.0) return p;

  if (table) {
    const TabulatedBrdfOptions& t = table->options();
    const double phiOrigin = t.layout == TabulatedBrdfOptions::Layout::Isotropic ? azimuth(wo) : 0.0;
    addReflectedMass({t.thetaHalfCells, t.phiHalfCells, phiOrigin, true,
                      [&](const Vec3d& wh) { return table->halfVectorPdf(wo, wh); }},
                     wo, 1.0 - w, o, p);
  } else if (rgl) {
    // The warps' v = 0 is φm = φo − π.
    addReflectedMass({kRglSCells, kRglPhiCells, azimuth(wo) - kPi, false,
                      [&](const Vec3d& wh) { return rgl->halfVectorPdf(wo, wh); }, true},
                     wo, 1.0, o, p);
  } else {
    addReflectedMass({kGgxSCells, kGgxPhiCells, 0.0, false, [&](const Vec3d& wh) { return ggx->halfVectorPdf(wh); }},
                     wo, 1.0 - w, o, p);
  }
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

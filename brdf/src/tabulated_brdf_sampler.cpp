#include "acdf/brdf/tabulated_brdf_sampler.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "acdf/brdf/coordinates.h"
#include "acdf/sampling/sample.h"

namespace acdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = 0.5 * kPi;
constexpr double kTwoPi = 2.0 * kPi;

using Layout = TabulatedBrdfOptions::Layout;
using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

bool mirrored(const TabulatedBrdfOptions& o) { return o.layout == Layout::Isotropic && o.mirror; }

// The azimuth axis of the half vector: φh (Full4D) or Δφ (Isotropic), in radians.
uint32_t phiCells(const TabulatedBrdfOptions& o) { return mirrored(o) ? o.phiHalfCells / 2 : o.phiHalfCells; }
double phiRange(const TabulatedBrdfOptions& o) { return mirrored(o) ? kPi : kTwoPi; }

const TabulatedBrdfOptions& validated(const TabulatedBrdfOptions& o) {
  if (o.thetaOutCells == 0 || o.thetaHalfCells == 0 || o.phiHalfCells == 0 ||
      (o.layout == Layout::Full4D && o.phiOutCells == 0))
    throw std::invalid_argument("BRDF table: every axis needs at least one cell");
  if (mirrored(o) && o.phiHalfCells % 2 != 0)
    throw std::invalid_argument("BRDF table: a mirrored isotropic table needs an even number of phi cells");
  if (o.supersampling == 0) throw std::invalid_argument("BRDF table: supersampling must be >= 1");
  if (!(o.cosineWeight >= 0.0 && o.cosineWeight <= 1.0))
    throw std::invalid_argument("BRDF table: the cosine mixture weight must be in [0, 1]");
  validate(o.simplify);
  return o;
}

std::vector<GridAxis> tableAxes(const TabulatedBrdfOptions& o) {
  std::vector<GridAxis> axes{GridAxis(o.thetaOutCells, 0.0f, static_cast<float>(kHalfPi))};
  if (o.layout == Layout::Full4D) axes.emplace_back(o.phiOutCells, 0.0f, static_cast<float>(kTwoPi));
  axes.emplace_back(o.thetaHalfCells, 0.0f, 1.0f);
  axes.emplace_back(phiCells(o), 0.0f, static_cast<float>(phiRange(o)));
  return axes;
}

// x as a coordinate of the axis: rounded to float and kept inside [lo, hi), since a double just
// below hi (2π, say) may round up to it.
float onAxis(const GridAxis& axis, double x) {
  const float f = static_cast<float>(x);
  if (f >= axis.hi()) return std::nextafter(axis.hi(), axis.lo());
  return f < axis.lo() ? axis.lo() : f;
}

// 1 − cos θ without cancellation near θ = 0: the solid angle of a polar cap over 2π.
double oneMinusCos(double theta) {
  const double h = std::sin(0.5 * theta);
  return 2.0 * h * h;
}

// Stratified positions: the centres of `per` equal sub-cells of each of `cells` cells of [0, range).
std::vector<double> subPoints(uint32_t cells, uint32_t per, double range) {
  std::vector<double> points(std::size_t{cells} * per);
  for (std::size_t k = 0; k < points.size(); ++k) points[k] = (static_cast<double>(k) + 0.5) / points.size() * range;
  return points;
}

// A half-vector sub-point of the grid: its direction, frame and Jacobian π s sinθh.
struct HalfVectorPoint {
  Vec3d direction;
  HalfVectorFrame frame;
  double jacobian;
};

// f·cosθi · 4(ωo·ωh) · π s sinθh averaged over each cell's sub-points: the target density in
// (s, φh), row-major over (θo[, φo], s, φh). Slices in parallel; each cell's sum in double in a
// fixed order.
std::vector<float> tabulate(const MerlBrdf& brdf, MerlBrdf::Interpolation interpolation,
                            const TabulatedBrdfOptions& o) {
  const uint32_t per = o.supersampling;
  const uint32_t sCells = o.thetaHalfCells, pCells = phiCells(o);
  const std::vector<double> sValues = subPoints(sCells, per, 1.0);
  const std::vector<double> phiValues = subPoints(pCells, per, phiRange(o));
  std::vector<HalfVectorPoint> halfPoints;
  halfPoints.reserve(sValues.size() * phiValues.size());
  for (double s : sValues) {
    const double thetaHalf = s * s * kHalfPi;
    for (double phi : phiValues)
      halfPoints.push_back({sphericalDirection(thetaHalf, phi), HalfVectorFrame(thetaHalf, phi),
                            kPi * s * std::sin(thetaHalf)});
  }

  const std::vector<double> thetaOut = subPoints(o.thetaOutCells, per, kHalfPi);
  // Isotropic tables put ωo at φo = 0; Δφ is then the half vector's own azimuth.
  const bool full = o.layout == Layout::Full4D;
  const std::vector<double> phiOut = full ? subPoints(o.phiOutCells, per, kTwoPi) : std::vector<double>{0.0};
  const uint32_t phiOutCells = full ? o.phiOutCells : 1;
  const uint32_t phiOutPer = full ? per : 1;

  const std::size_t sliceCells = std::size_t{sCells} * pCells;
  const std::size_t slices = std::size_t{o.thetaOutCells} * phiOutCells;
  std::vector<float> values(slices * sliceCells);
  const double subPointsPerCell = std::pow(static_cast<double>(per), full ? 4 : 3);

  tbb::parallel_for(std::size_t{0}, slices, [&](std::size_t slice) {
    const std::size_t thetaCell = slice / phiOutCells, phiCell = slice % phiOutCells;
    std::vector<double> sums(sliceCells, 0.0);
    for (uint32_t a = 0; a < per; ++a)
      for (uint32_t b = 0; b < phiOutPer; ++b) {
        const Vec3d wo = sphericalDirection(thetaOut[thetaCell * per + a], phiOut[phiCell * phiOutPer + b]);
        for (std::size_t k = 0; k < halfPoints.size(); ++k) {
          const HalfVectorPoint& h = halfPoints[k];
          const double cosOutHalf = dot(wo, h.direction);
          if (!(cosOutHalf > 0.0)) continue;  // ωi would be below the horizon
          const Vec3d wi = reflect(wo, h.direction);
          if (!(wi.z > 0.0)) continue;
          double thetaDiff, phiDiff;
          h.frame.diffAngles(wi, thetaDiff, phiDiff);
          const double f = brdf.evalHalfDiff(h.frame.thetaHalf(), thetaDiff, phiDiff, interpolation).luminance();
          // Sub-point k lies in cell (k / (phi sub-points) / per, k % (phi sub-points) / per).
          const std::size_t sCell = k / phiValues.size() / per, pCell = k % phiValues.size() / per;
          sums[sCell * pCells + pCell] += f * wi.z * 4.0 * cosOutHalf * h.jacobian;
        }
      }
    float* out = values.data() + slice * sliceCells;
    for (std::size_t c = 0; c < sliceCells; ++c) out[c] = static_cast<float>(sums[c] / subPointsPerCell);
  });
  return values;
}

// Bump when tabulate() changes its values: cached tables of the old ones must not be used.
constexpr int kTabulationVersion = 1;

CascadeOptions cascadeOptions(const TabulatedBrdfOptions& o) {
  CascadeOptions cascade;
  cascade.conditioningDims = o.layout == Layout::Full4D ? 2 : 1;
  cascade.methods = {o.method, o.method};
  cascade.simplify = o.simplify;
  cascade.tolerance = o.tolerance;
  return cascade;
}

Cascade buildTable(const MerlBrdf& brdf, MerlBrdf::Interpolation interpolation, const TabulatedBrdfOptions& o,
                   double& tabulationMs, double& buildMs) {
  Clock::time_point start = Clock::now();
  const std::vector<float> values = tabulate(brdf, interpolation, o);
  tabulationMs = millisecondsSince(start);
  start = Clock::now();
  Cascade table(values, tableAxes(o), cascadeOptions(o));
  buildMs = millisecondsSince(start);
  return table;
}

// A cached table, checked to have the grid and options a build with `o` would have.
Cascade checkedTable(Cascade table, const TabulatedBrdfOptions& o) {
  if (table.axes() != tableAxes(o) || !(table.options() == cascadeOptions(o)))
    throw SerializationError("BRDF table: the saved table has another grid or other options than " + o.name());
  return table;
}

std::vector<double> capAreasOf(const TabulatedBrdfOptions& o) {
  std::vector<double> areas(o.thetaHalfCells + 1);
  for (uint32_t k = 0; k <= o.thetaHalfCells; ++k) {
    const double s = static_cast<double>(k) / o.thetaHalfCells;
    areas[k] = oneMinusCos(s * s * kHalfPi);
  }
  return areas;
}

}  // namespace

std::string TabulatedBrdfOptions::name() const {
  return std::string(method == DimensionMethod::Adaptive ? "adaptive" : "uniform") +
         (layout == Layout::Full4D ? "-4d" : "-iso");
}

TabulatedBrdfSampler::TabulatedBrdfSampler(const MerlBrdf& brdf, MerlBrdf::Interpolation interpolation,
                                           const TabulatedBrdfOptions& options)
    : BrdfSampler(brdf, interpolation),
      options_(validated(options)),
      table_(buildTable(brdf, interpolation, options_, tabulationMs_, buildMs_)),
      capAreas_(capAreasOf(options_)) {}

TabulatedBrdfSampler::TabulatedBrdfSampler(const MerlBrdf& brdf, MerlBrdf::Interpolation interpolation,
                                           const TabulatedBrdfOptions& options, Cascade table)
    : BrdfSampler(brdf, interpolation),
      options_(validated(options)),
      table_(checkedTable(std::move(table), options_)),
      capAreas_(capAreasOf(options_)) {}

Cascade TabulatedBrdfSampler::buildCascade(const MerlBrdf& brdf, MerlBrdf::Interpolation interpolation,
                                           const TabulatedBrdfOptions& options) {
  double tabulationMs, buildMs;
  return buildTable(brdf, interpolation, validated(options), tabulationMs, buildMs);
}

CacheKey TabulatedBrdfSampler::tableKey(const MerlBrdf& brdf, MerlBrdf::Interpolation interpolation,
                                        const TabulatedBrdfOptions& o) {
  ContentHash content;
  for (int c = 0; c < 3; ++c) content.values(brdf.channel(c));
  const std::string parameters =
      "brdf-half-vector-table tabulation=" + std::to_string(kTabulationVersion) +
      " interpolation=" + (interpolation == MerlBrdf::Interpolation::Nearest ? "nearest" : "trilinear") +
      " layout=" + (o.layout == Layout::Full4D ? "full-4d" : "isotropic") +
      " cells=" + std::to_string(o.thetaOutCells) + "x" + std::to_string(o.phiOutCells) + "x" +
      std::to_string(o.thetaHalfCells) + "x" + std::to_string(o.phiHalfCells) +
      " mirror=" + std::to_string(o.mirror) + " supersampling=" + std::to_string(o.supersampling) + " " +
      describe(cascadeOptions(o));
  return cacheKey(content, parameters);
}

std::array<float, 2> TabulatedBrdfSampler::condition(const Vec3d& wo) const {
  const auto& axes = table_.axes();
  std::array<float, 2> c{onAxis(axes[0], polarAngle(wo)), 0.0f};
  if (options_.layout == Layout::Full4D) c[1] = onAxis(axes[1], azimuth(wo));
  return c;
}

Vec3d TabulatedBrdfSampler::sampleDirection(const Vec3d& wo, float u0, float u1) const {
  const double w = options_.cosineWeight;
  if (!(wo.z > 0.0)) return sampleCosineHemisphere(u0, u1);
  if (u0 < w) return sampleCosineHemisphere(u0 / w, u1);
  // The rest of u0's range, stretched back to [0, 1), drives the table; for a mirrored table
  // u1's halves choose the sign of Δφ (exact in float: 2·u1 and 2·u1 − 1).
  const bool negative = mirrored(options_) && u1 >= 0.5f;
  const std::array<float, 2> u{clampUnit(static_cast<float>((u0 - w) / (1.0 - w))),
                               negative ? 2.0f * u1 - 1.0f : mirrored(options_) ? 2.0f * u1 : u1};
  const std::array<float, 2> c = condition(wo);
  const std::size_t k = table_.conditioningDims();
  const SampleND x = table_.sample(std::span<const float>(c.data(), k), u);
  // x[0] is uniform in s within its cell; move it to the same fraction of the cell's solid angle.
  const GridAxis& sAxis = table_.axes()[k];
  const uint32_t cell = sAxis.cellOf(x.x[0]);
  const double t = std::clamp(sAxis.gridCoordinate(x.x[0]) - cell, 0.0, 1.0);
  const double cap = capAreas_[cell] + t * (capAreas_[cell + 1] - capAreas_[cell]);  // 1 − cosθh
  const double sinTheta = std::sqrt(cap * (2.0 - cap));
  double phi = x.x[1];
  if (options_.layout == Layout::Isotropic) phi = azimuth(wo) + (negative ? -phi : phi);
  const Vec3d wh{sinTheta * std::cos(phi), sinTheta * std::sin(phi), 1.0 - cap};
  return reflect(wo, wh);
}

double TabulatedBrdfSampler::halfVectorPdf(const Vec3d& wo, const Vec3d& wh) const {
  if (!(wh.z > 0.0)) return 0.0;
  const std::size_t k = table_.conditioningDims();
  const GridAxis& sAxis = table_.axes()[k];
  const double s = std::sqrt(polarAngle(wh) / kHalfPi);
  const auto cell = static_cast<uint32_t>(std::min<double>(s * sAxis.cells(), sAxis.cells() - 1));
  double phi = azimuth(wh);
  if (options_.layout == Layout::Isotropic) {
    phi -= azimuth(wo);
    if (phi < 0.0) phi += kTwoPi;
    if (mirrored(options_) && phi > kPi) phi = kTwoPi - phi;
  }
  // The cascade's density is constant in s over the cell: ask at its centre, so a θh that
  // rounds across a cell boundary in float still reads the cell the solid-angle mapping used.
  const std::array<float, 2> x{sAxis.place(cell, cell + 1, 0.5), onAxis(table_.axes()[k + 1], phi)};
  const std::array<float, 2> c = condition(wo);
  const double density = table_.pdf(std::span<const float>(c.data(), k), x);
  // P(cell) / Ω(cell) per unit φ: density · Δs / Δ(1 − cosθh).
  const double perSteradian = density * sAxis.cellWidth() / (capAreas_[cell + 1] - capAreas_[cell]);
  return mirrored(options_) ? 0.5 * perSteradian : perSteradian;
}

double TabulatedBrdfSampler::pdf(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0.0)) return cosineHemispherePdf(wi.z);
  const double w = options_.cosineWeight;
  double p = w * cosineHemispherePdf(wi.z);
  const Vec3d sum = wi + wo;
  const double len = length(sum);
  if (w < 1.0 && len > 0.0) {
    // Reflecting ωo about h or −h gives the same ωi; the table covers the upper hemisphere only,
    // so exactly one of the two can have been sampled.
    Vec3d h = sum * (1.0 / len);
    if (h.z < 0.0) h = -h;
    const double cosOutHalf = std::fabs(dot(wo, h));
    if (cosOutHalf > 0.0) p += (1.0 - w) * halfVectorPdf(wo, h) / (4.0 * cosOutHalf);
  }
  return p;
}

}  // namespace acdf

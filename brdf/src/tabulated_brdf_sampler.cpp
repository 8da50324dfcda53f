#include "acdf/brdf/tabulated_brdf_sampler.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/half_vector.h"
#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/sample.h"
#include "acdf/sampling/timing.h"

namespace acdf {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = 0.5 * kPi;
constexpr double kTwoPi = 2.0 * kPi;

using Layout = TabulatedBrdfOptions::Layout;
using Clock = std::chrono::steady_clock;

// How far inside its θh cell a sample stays, as a fraction of the cell in s. pdf() finds the cell
// again from ωi = reflect(ωo, ωh), a round trip that moves θh by a few double ulps (more as
// ωo·ωh → 0), so a sample on a boundary (fraction 0, which float coordinates often give) would
// land in the neighbour. 1e-6 of a cell is 5e-11 rad at the first boundary of a 256-cell axis,
// far above that rounding; it shifts the density at cell edges by 1e-6 of a cell, as the
// environment light's pixel margin does.
constexpr double kCellMargin = 1e-6;

bool mirrored(const TabulatedBrdfOptions& o) { return o.layout == Layout::Isotropic && o.mirror; }

// The azimuth axis of the half vector: φh (Full4D) or Δφ (Isotropic), in radians.
uint32_t phiCells(const TabulatedBrdfOptions& o) { return mirrored(o) ? o.phiHalfCells / 2 : o.phiHalfCells; }
double phiRange(const TabulatedBrdfOptions& o) { return mirrored(o) ? kPi : kTwoPi; }

const TabulatedBrdfOptions& validated(const BrdfModel& model, const TabulatedBrdfOptions& o) {
  validate(o);
  if (o.layout == Layout::Isotropic && !model.isotropic())
    throw std::invalid_argument("BRDF table: the isotropic layout needs an isotropic BRDF model");
  return o;
}

std::vector<GridAxis> tableAxes(const TabulatedBrdfOptions& o) {
  std::vector<GridAxis> axes{GridAxis(o.thetaOutCells, 0.0f, static_cast<float>(kHalfPi))};
  if (o.layout == Layout::Full4D) axes.emplace_back(o.phiOutCells, 0.0f, static_cast<float>(kTwoPi));
  axes.emplace_back(o.thetaHalfCells, 0.0f, 1.0f);
  axes.emplace_back(phiCells(o), 0.0f, static_cast<float>(phiRange(o)));
  return axes;
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

// The azimuths of the half-vector sub-points relative to the outgoing direction's, on which the
// BRDF is evaluated. A MERL BRDF is isotropic: turning ωo and ωh together about the normal changes
// nothing, so the target at (θo, φo, ωh) is the target at (θo, 0) with ωh turned by −φo; only
// Δφ = φh − φo matters. With n sub-points per cell, P cells of φh and Q of φo over 2π, L = lcm(P, Q),
// a = L/P, b = L/Q and δ = 2π/(2Ln), the sub-points are φh_k = (2k + 1)a·δ and φo_j = (2j + 1)b·δ,
// so every Δφ = (2ka − 2jb + a − b)·δ lies on one lattice of Ln points, offset by half a step when
// a − b is odd. The BRDF is evaluated once per (θo, θh, lattice point) instead of once per 4D
// sub-point: for the default table, 2M evaluations instead of 67M. An isotropic table has φo = 0
// and its lattice is the Δφ sub-points themselves.
struct AzimuthLattice {
  uint32_t points;
  double spacing, offset;  // point t is at (t + offset) · spacing
  int64_t stepPerHalf, stepPerOut, shift;

  AzimuthLattice(const TabulatedBrdfOptions& o) {
    const uint32_t per = o.supersampling;
    if (o.layout == Layout::Isotropic) {
      points = phiCells(o) * per;
      spacing = phiRange(o) / points;
      offset = 0.5;
      stepPerHalf = 1, stepPerOut = 0, shift = 0;
      return;
    }
    const int64_t lcm = std::lcm<int64_t>(o.phiHalfCells, o.phiOutCells);
    const int64_t a = lcm / o.phiHalfCells, b = lcm / o.phiOutCells, parity = (a - b) & 1;
    points = static_cast<uint32_t>(lcm * per);
    spacing = kTwoPi / points;
    offset = 0.5 * static_cast<double>(parity);
    stepPerHalf = a, stepPerOut = b, shift = (a - b - parity) / 2;
  }
  // The lattice point of φh sub-point k seen from φo sub-point j.
  uint32_t index(uint32_t k, uint32_t j) const {
    const int64_t t = (k * stepPerHalf - j * stepPerOut + shift) % points;
    return static_cast<uint32_t>(t < 0 ? t + points : t);
  }
};

// The target density's integrand at one (ωo, ωh): f·cosθi · 4(ωo·ωh) · `jacobian` (π s sinθh),
// with `luminance(ωi)` the model's; 0 where ωi = reflect(ωo, ωh) is at or below the horizon.
template <class Luminance>
double targetIntegrand(const Vec3d& wo, const Vec3d& wh, double jacobian, const Luminance& luminance) {
  const double cosOutHalf = dot(wo, wh);
  if (!(cosOutHalf > 0.0)) return 0.0;
  const Vec3d wi = reflect(wo, wh);
  if (!(wi.z > 0.0)) return 0.0;
  const double f = luminance(wi);
  return f * wi.z * 4.0 * cosOutHalf * jacobian;
}

// Where f·cosθi > 0 in only a sliver of a cell, every stratified point of the cell can miss it: near
// the horizon a half vector reflects one ωo of a θo cell above it and another ωo below. For a model
// whose f·cosθi does not vanish there (RGL's ρD / (4σ) at the horizon), such a zero cell leaves the
// region to the cosine mixture alone, and the variance grows as 1 / cosineWeight. The cell's
// corners find that support. With φo = 0 and Δφ = φh − φo,
//     ωi.z = 2(ωo·ωh) cosθh − cosθo = sinθo sin2θh cosΔφ + cosθo cos2θh,
// a sinusoid in θo (period 2π) and in θh (period π), whose cells are far shorter than half a
// period, so where it is positive somewhere on a cell's range it is positive at one of its ends;
// and over the cell's Δφ range [φh_a − φo_b, φh_b − φo_a], a + b cosΔφ (b >= 0) is largest at
// an end or at Δφ = 0 when that lies inside. Moving along each axis in turn to where ωi.z is
// largest keeps it positive, so wherever ωi.z > 0 in a cell it is > 0 at one of the points
//     θo ∈ {θo_a, θo_b} × s ∈ {s_a, s_b} × (φo, φh) ∈ {(φo_b, φh_a), (φo_a, φh_b)} [∪ {(t, t)}],
// t a common azimuth of both cells when Δφ = 0 lies inside; and ωi.z > 0 implies ωo·ωh > 0
// (ωo.z, ωh.z >= 0). Azimuths count steps of the lattice of both cells' boundaries: 2π / lcm(P, Q)
// for a 4D table, the Δφ cells' for an isotropic one (φo = 0).
struct CornerLattice {
  uint32_t thetaOutCells, sCells, halfCells;  // halfCells: φh (or Δφ) cells
  uint32_t steps;                             // lattice steps over the azimuth range
  int64_t stepPerHalf, stepPerOut;            // lattice steps per φh cell, per φo cell (0: isotropic)
  double phiStep;

  explicit CornerLattice(const TabulatedBrdfOptions& o)
      : thetaOutCells(o.thetaOutCells), sCells(o.thetaHalfCells), halfCells(phiCells(o)) {
    const bool full = o.layout == Layout::Full4D;
    steps = full ? std::lcm(halfCells, o.phiOutCells) : halfCells;
    stepPerHalf = steps / halfCells;
    stepPerOut = full ? steps / o.phiOutCells : 0;
    phiStep = phiRange(o) / steps;
  }
  // The mean of integrand(θo corner, s corner, φo step, φh step), f·cosθi · 4(ωo·ωh) without the
  // Jacobian, over the cell's corner points, times the Jacobian π s sinθh at the cell's centre.
  template <class Integrand>
  double mean(uint32_t thetaCell, uint32_t outCell, uint32_t sCell, uint32_t halfCell, const Integrand& integrand) const {
    const int64_t outA = outCell * stepPerOut, outB = (outCell + 1) * stepPerOut;
    const int64_t halfA = halfCell * stepPerHalf, halfB = (halfCell + 1) * stepPerHalf;
    double sum = 0.0;
    int count = 0;
    for (uint32_t k = thetaCell; k <= thetaCell + 1; ++k)
      for (uint32_t b = sCell; b <= sCell + 1; ++b) {
        sum += integrand(k, b, outB, halfA) + integrand(k, b, outA, halfB);
        count += 2;
        if (halfA < outB && outA < halfB) {
          const int64_t common = std::max(outA, halfA);
          sum += integrand(k, b, common, common);
          ++count;
        }
      }
    const double s = (sCell + 0.5) / sCells;
    return sum / count * kPi * s * std::sin(s * s * kHalfPi);
  }
  // A cell's table value: the mean of its `subPoints` stratified points (their sum `sum`), or
  // where they all gave 0, the mean over its corners. `cell` counts (s, φh) cells of one slice.
  template <class Integrand>
  float cellValue(double sum, double subPoints, uint32_t thetaCell, uint32_t outCell, std::size_t cell,
                  const Integrand& integrand) const {
    if (sum > 0.0) return static_cast<float>(sum / subPoints);
    return static_cast<float>(mean(thetaCell, outCell, static_cast<uint32_t>(cell / halfCells),
                                   static_cast<uint32_t>(cell % halfCells), integrand));
  }
  // θo at corner k; the last is the largest θo a table is conditioned on (onAxis: the float below
  // π/2), where f·cosθi of a model like GGX is still finite to rounding, not 0/0 as at the horizon.
  double thetaOut(uint32_t k) const {
    return k < thetaOutCells ? k * kHalfPi / thetaOutCells : std::nextafter(static_cast<float>(kHalfPi), 0.0f);
  }
  double thetaHalf(uint32_t b) const {
    const double s = static_cast<double>(b) / sCells;
    return s * s * kHalfPi;
  }
};

// The luminance of an isotropic model's f at ωi, for the half vector of `frame`.
double luminanceAt(const BrdfModel& model, const HalfVectorFrame& frame, const Vec3d& wi) {
  double thetaDiff, phiDiff;
  frame.diffAngles(wi, thetaDiff, phiDiff);
  return model.evalHalfDiff(frame.thetaHalf(), thetaDiff, phiDiff).luminance();
}

// f·cosθi · 4(ωo·ωh) · π s sinθh averaged over each cell's sub-points: the target density in
// (s, φh), row-major over (θo[, φo], s, φh). θo cells in parallel; each cell's sum in double in a
// fixed order. An isotropic model, on the azimuth lattice. A cell whose sub-points all give 0 but
// whose corners (CornerLattice) do not gets the mean of f·cosθi · 4(ωo·ωh) over its corners times
// the Jacobian at its centre, so the table covers f·cosθi wherever a corner sees it.
std::vector<float> tabulateOnLattice(const BrdfModel& model, const TabulatedBrdfOptions& o) {
  const uint32_t per = o.supersampling;
  const uint32_t sCells = o.thetaHalfCells, pCells = phiCells(o);
  const bool full = o.layout == Layout::Full4D;
  const uint32_t phiOutCells = full ? o.phiOutCells : 1, phiOutPer = full ? per : 1;
  const AzimuthLattice lattice(o);
  const CornerLattice corners(o);

  // The half vectors of the lattice: direction, frame and Jacobian π s sinθh.
  const std::vector<double> sValues = subPoints(sCells, per, 1.0);
  struct HalfVectorPoint {
    Vec3d direction;
    HalfVectorFrame frame;
    double jacobian;
  };
  std::vector<HalfVectorPoint> halfVectors;
  halfVectors.reserve(sValues.size() * lattice.points);
  for (double s : sValues) {
    const double thetaHalf = s * s * kHalfPi;
    for (uint32_t t = 0; t < lattice.points; ++t) {
      const double phi = (t + lattice.offset) * lattice.spacing;
      halfVectors.push_back(
          {sphericalDirection(thetaHalf, phi), HalfVectorFrame(thetaHalf, phi), kPi * s * std::sin(thetaHalf)});
    }
  }

  // The integrand without its Jacobian at every corner point, row-major over (θo, s, Δφ): φo = 0,
  // Δφ = φh − φo in lattice steps, from 0 to the whole range (negative ones wrap around).
  const uint32_t deltas = corners.steps + 1;
  const std::size_t cornerRow = std::size_t{sCells + 1} * deltas;
  std::vector<double> cornerValues((o.thetaOutCells + 1) * cornerRow);
  tbb::parallel_for(uint32_t{0}, o.thetaOutCells + 1, [&](uint32_t k) {
    const Vec3d wo = sphericalDirection(corners.thetaOut(k), 0.0);
    for (uint32_t b = 0; b <= sCells; ++b)
      for (uint32_t d = 0; d < deltas; ++d) {
        const HalfVectorFrame frame(corners.thetaHalf(b), d * corners.phiStep);
        cornerValues[k * cornerRow + b * deltas + d] =
            targetIntegrand(wo, sphericalDirection(corners.thetaHalf(b), d * corners.phiStep), 1.0,
                            [&](const Vec3d& wi) { return luminanceAt(model, frame, wi); });
      }
  });
  const auto cornerIntegrand = [&](uint32_t k, uint32_t b, int64_t phiOut, int64_t phiHalf) {
    const int64_t delta = phiHalf - phiOut;
    return cornerValues[k * cornerRow + b * deltas + (delta < 0 ? delta + corners.steps : delta)];
  };

  const std::vector<double> thetaOut = subPoints(o.thetaOutCells, per, kHalfPi);
  const std::size_t sliceCells = std::size_t{sCells} * pCells;
  const uint32_t phiSubPoints = pCells * per;
  std::vector<float> values(std::size_t{o.thetaOutCells} * phiOutCells * sliceCells);
  const double subPointsPerCell = std::pow(static_cast<double>(per), full ? 4 : 3);

  tbb::parallel_for(uint32_t{0}, o.thetaOutCells, [&](uint32_t thetaCell) {
    // The target at this cell's θo sub-points (φo = 0) over the lattice.
    std::vector<double> target(std::size_t{per} * halfVectors.size(), 0.0);
    for (uint32_t a = 0; a < per; ++a) {
      const Vec3d wo = sphericalDirection(thetaOut[thetaCell * per + a], 0.0);
      double* row = target.data() + std::size_t{a} * halfVectors.size();
      for (std::size_t k = 0; k < halfVectors.size(); ++k) {
        const HalfVectorPoint& h = halfVectors[k];
        row[k] = targetIntegrand(wo, h.direction, h.jacobian,
                                 [&](const Vec3d& wi) { return luminanceAt(model, h.frame, wi); });
      }
    }
    std::vector<double> sums(sliceCells);
    std::vector<uint32_t> latticeOf(phiSubPoints);
    for (uint32_t phiCell = 0; phiCell < phiOutCells; ++phiCell) {
      std::fill(sums.begin(), sums.end(), 0.0);
      for (uint32_t a = 0; a < per; ++a)
        for (uint32_t j = phiCell * phiOutPer; j < (phiCell + 1) * phiOutPer; ++j) {
          for (uint32_t k = 0; k < phiSubPoints; ++k) latticeOf[k] = lattice.index(k, j);
          for (std::size_t i = 0; i < sValues.size(); ++i) {
            const double* row = target.data() + (a * sValues.size() + i) * lattice.points;
            double* cells = sums.data() + i / per * pCells;
            for (uint32_t k = 0; k < phiSubPoints; ++k) cells[k / per] += row[latticeOf[k]];
          }
        }
      float* out = values.data() + (std::size_t{thetaCell} * phiOutCells + phiCell) * sliceCells;
      for (std::size_t c = 0; c < sliceCells; ++c)
        out[c] = corners.cellValue(sums[c], subPointsPerCell, thetaCell, phiCell, c, cornerIntegrand);
    }
  });
  return values;
}

// The same for a model that is not isotropic (a Full4D table): f at every 4D sub-point, and a zero
// cell's corners at their own azimuths.
std::vector<float> tabulateEveryPoint(const BrdfModel& model, const TabulatedBrdfOptions& o) {
  const uint32_t per = o.supersampling;
  const uint32_t sCells = o.thetaHalfCells, pCells = o.phiHalfCells;
  const std::vector<double> sValues = subPoints(sCells, per, 1.0);
  const std::vector<double> phiHalf = subPoints(pCells, per, kTwoPi);
  struct HalfVectorPoint {
    Vec3d direction;
    double jacobian;  // π s sinθh
  };
  std::vector<HalfVectorPoint> halfVectors;
  halfVectors.reserve(sValues.size() * phiHalf.size());
  for (double s : sValues) {
    const double thetaHalf = s * s * kHalfPi;
    for (double phi : phiHalf)
      halfVectors.push_back({sphericalDirection(thetaHalf, phi), kPi * s * std::sin(thetaHalf)});
  }
  const std::vector<double> thetaOut = subPoints(o.thetaOutCells, per, kHalfPi);
  const std::vector<double> phiOut = subPoints(o.phiOutCells, per, kTwoPi);
  const std::size_t sliceCells = std::size_t{sCells} * pCells;
  std::vector<float> values(std::size_t{o.thetaOutCells} * o.phiOutCells * sliceCells);
  const double subPointsPerCell = std::pow(static_cast<double>(per), 4);
  const CornerLattice corners(o);
  const auto cornerIntegrand = [&](uint32_t k, uint32_t b, int64_t phiOut, int64_t phiHalf) {
    const Vec3d wo = sphericalDirection(corners.thetaOut(k), phiOut * corners.phiStep);
    const Vec3d wh = sphericalDirection(corners.thetaHalf(b), phiHalf * corners.phiStep);
    return targetIntegrand(wo, wh, 1.0, [&](const Vec3d& wi) { return model.luminance(wo, wi); });
  };

  tbb::parallel_for(uint32_t{0}, o.thetaOutCells, [&](uint32_t thetaCell) {
    std::vector<double> sums(sliceCells);
    for (uint32_t phiCell = 0; phiCell < o.phiOutCells; ++phiCell) {
      std::fill(sums.begin(), sums.end(), 0.0);
      for (uint32_t a = 0; a < per; ++a)
        for (uint32_t b = 0; b < per; ++b) {
          const Vec3d wo = sphericalDirection(thetaOut[thetaCell * per + a], phiOut[phiCell * per + b]);
          for (std::size_t k = 0; k < halfVectors.size(); ++k) {
            const HalfVectorPoint& h = halfVectors[k];
            sums[k / phiHalf.size() / per * pCells + k % phiHalf.size() / per] +=
                targetIntegrand(wo, h.direction, h.jacobian, [&](const Vec3d& wi) { return model.luminance(wo, wi); });
          }
        }
      float* out = values.data() + (std::size_t{thetaCell} * o.phiOutCells + phiCell) * sliceCells;
      for (std::size_t c = 0; c < sliceCells; ++c)
        out[c] = corners.cellValue(sums[c], subPointsPerCell, thetaCell, phiCell, c, cornerIntegrand);
    }
  });
  return values;
}

std::vector<float> tabulate(const BrdfModel& model, const TabulatedBrdfOptions& o) {
  return model.isotropic() ? tabulateOnLattice(model, o) : tabulateEveryPoint(model, o);
}

// Bump when tabulate() changes its values: cached tables of the old ones must not be used.
constexpr int kTabulationVersion = 3;  // 3: zero cells take their corners' support

CascadeOptions cascadeOptions(const TabulatedBrdfOptions& o) {
  CascadeOptions cascade;
  cascade.conditioningDims = o.layout == Layout::Full4D ? 2 : 1;
  cascade.methods = {o.method, o.method};
  cascade.simplify = o.simplify;
  cascade.tolerance = o.tolerance;
  cascade.sliceGroupingTolerance = o.sliceGrouping;
  return cascade;
}

Cascade buildTable(const BrdfModel& model, const TabulatedBrdfOptions& o, double& tabulationMs, double& buildMs) {
  Clock::time_point start = Clock::now();
  const std::vector<float> values = tabulate(model, o);
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

void validate(const TabulatedBrdfOptions& o) {
  const auto fail = [](const char* option, const std::string& problem) {
    throw OptionError("BRDF table", option, problem);
  };
  if (o.thetaOutCells == 0) fail("theta_out", "must be at least 1");
  if (o.layout == Layout::Full4D && o.phiOutCells == 0) fail("phi_out", "must be at least 1");
  if (o.thetaHalfCells == 0) fail("theta_half", "must be at least 1");
  if (o.phiHalfCells == 0) fail("phi_half", "must be at least 1");
  if (mirrored(o) && o.phiHalfCells % 2 != 0)
    fail("phi_half", "must be even for a mirrored isotropic table, got " + std::to_string(o.phiHalfCells));
  if (o.supersampling == 0) fail("supersampling", "must be at least 1");
  if (!(o.cosineWeight >= 0.0 && o.cosineWeight <= 1.0))
    fail("cosine_weight", "must be in [0, 1], got " + OptionError::number(o.cosineWeight));
  if (!(o.sliceGrouping >= 0.0 && std::isfinite(o.sliceGrouping)))
    fail("slice_grouping", "must be finite and >= 0, got " + OptionError::number(o.sliceGrouping));
  try {
    validate(o.simplify);
  } catch (const OptionError& e) {
    // A table's ε is a χ²-divergence, which users set as chi2_epsilon (table_options.h).
    throw OptionError("BRDF table", e.option() == "epsilon" ? "chi2_epsilon" : e.option(), e.problem());
  }
}

namespace {
constexpr EnumName<Layout> kLayoutNames[] = {{Layout::Full4D, "4d"}, {Layout::Isotropic, "isotropic"}};
}  // namespace

std::string_view toString(TabulatedBrdfOptions::Layout layout) { return nameOf(kLayoutNames, layout); }

TabulatedBrdfOptions::Layout parseTableLayout(std::string_view name) {
  return valueNamed(kLayoutNames, name, "BRDF table layout");
}

std::string TabulatedBrdfOptions::name() const {
  return std::string(toString(method)) + (layout == Layout::Full4D ? "-4d" : "-iso");
}

TabulatedBrdfSampler::TabulatedBrdfSampler(std::shared_ptr<const BrdfModel> model, const TabulatedBrdfOptions& options)
    : BrdfSampler(std::move(model)),
      options_(validated(this->model(), options)),
      table_(buildTable(this->model(), options_, tabulationMs_, buildMs_)),
      capAreas_(capAreasOf(options_)),
      outgoingCells_(outgoingCellsOf(table_)),
      halfVectorCells_(halfVectorCellsOf(table_, options_)) {}

TabulatedBrdfSampler::TabulatedBrdfSampler(std::shared_ptr<const BrdfModel> model, const TabulatedBrdfOptions& options,
                                           Cascade table)
    : BrdfSampler(std::move(model)),
      options_(validated(this->model(), options)),
      table_(checkedTable(std::move(table), options_)),
      capAreas_(capAreasOf(options_)),
      outgoingCells_(outgoingCellsOf(table_)),
      halfVectorCells_(halfVectorCellsOf(table_, options_)) {}

Cascade TabulatedBrdfSampler::buildCascade(const BrdfModel& model, const TabulatedBrdfOptions& options) {
  double tabulationMs, buildMs;
  return buildTable(model, validated(model, options), tabulationMs, buildMs);
}

CacheKey TabulatedBrdfSampler::tableKey(const BrdfModel& model, const TabulatedBrdfOptions& o) {
  ContentHash content;
  const std::string modelParameters = model.addToKey(content);
  const std::string parameters =
      "brdf-half-vector-table tabulation=" + std::to_string(kTabulationVersion) + " " + modelParameters +
      (model.isotropic() ? "" : " every-point") + " layout=" + std::string(toString(o.layout)) +
      " cells=" + std::to_string(o.thetaOutCells) + "x" + std::to_string(o.phiOutCells) + "x" +
      std::to_string(o.thetaHalfCells) + "x" + std::to_string(o.phiHalfCells) + " mirror=" + std::to_string(o.mirror) +
      " supersampling=" + std::to_string(o.supersampling) + " " + describe(cascadeOptions(o));
  return cacheKey(content, parameters);
}

OutgoingCells TabulatedBrdfSampler::outgoingCellsOf(const Cascade& table) {
  const auto& axes = table.axes();
  return OutgoingCells(axes[0], table.conditioningDims() == 2 ? std::optional<GridAxis>(axes[1]) : std::nullopt);
}

HalfVectorCells TabulatedBrdfSampler::halfVectorCellsOf(const Cascade& table, const TabulatedBrdfOptions& options) {
  const std::size_t k = table.conditioningDims();
  const HalfAzimuth azimuth = options.layout == Layout::Full4D ? HalfAzimuth::Absolute
                              : mirrored(options)              ? HalfAzimuth::Folded
                                                               : HalfAzimuth::Relative;
  return HalfVectorCells(table.axes()[k], table.axes()[k + 1], azimuth);
}

BrdfVertex TabulatedBrdfSampler::vertex(const Vec3d& wo) const {
  return vertexWithSlice(wo, outgoingCells_.sliceOf(wo));
}

SampledDirection TabulatedBrdfSampler::sampleDirectionAt(const BrdfVertex& v, float u0, float u1) const {
  const Vec3d& wo = v.wo();
  const double w = options_.cosineWeight;
  if (!(wo.z > 0.0)) return sampleCosineDirection(u0, u1);
  if (u0 < w) {
    // The table's term at this ωi is not known along this path: pdf() finds it.
    const Vec3d wi = sampleCosineHemisphere(u0 / w, u1);
    return {wi, pdfAt(v, wi)};
  }
  // The rest of u0's range, stretched back to [0, 1), drives the table; for a mirrored table
  // u1's halves choose the sign of Δφ (exact in float: 2·u1 and 2·u1 − 1).
  const bool negative = mirrored(options_) && u1 >= 0.5f;
  const std::array<float, 2> u{clampUnit(static_cast<float>((u0 - w) / (1.0 - w))), negative ? 2.0f * u1 - 1.0f
                                                                                    : mirrored(options_) ? 2.0f * u1
                                                                                                         : u1};
  const CellSample x = table_.sampleCellsInSlice(v.slice(), u);
  // The sample is uniform in s within its cell; move it to the same fraction of the cell's solid
  // angle, kept a margin inside the cell, so that pdf() finds this cell again from ωi despite
  // the rounding of the reflection and of θh. φ is found through its float coordinate (onAxis),
  // as the table placed it.
  const uint32_t cell = x.cells[0];
  const double t = std::clamp(x.fractions[0], kCellMargin, 1.0 - kCellMargin);
  const double cap = capAreas_[cell] + t * (capAreas_[cell + 1] - capAreas_[cell]);  // 1 − cosθh
  const double sinTheta = std::sqrt(cap * (2.0 - cap));
  double phi = x.x[1];
  if (options_.layout == Layout::Isotropic) phi = azimuth(wo) + (negative ? -phi : phi);
  const Vec3d wh{sinTheta * std::cos(phi), sinTheta * std::sin(phi), 1.0 - cap};
  const Vec3d wi = reflect(wo, wh);
  const HalfVector h = sampledHalfVector(wo, wh);
  // The table's density at the sampled cell, and the cosine term at ωi: the two ways to reach ωi.
  const double table = h.incidentPdf(perSteradian(x.pdf, cell));
  return reflected(v, wi, h, w * cosineHemispherePdf(wi.z) + (1.0 - w) * table);
}

// P(cell) / Ω(cell) per unit φ: density · Δs / Δ(1 − cosθh); half of it for each sign of a
// mirrored table's Δφ.
double TabulatedBrdfSampler::perSteradian(double density, uint32_t cell) const {
  const double perSteradian =
      density * table_.axes()[table_.conditioningDims()].cellWidth() / (capAreas_[cell + 1] - capAreas_[cell]);
  return mirrored(options_) ? 0.5 * perSteradian : perSteradian;
}

double TabulatedBrdfSampler::halfVectorPdfAt(const BrdfVertex& v, const Vec3d& wh) const {
  if (!(wh.z > 0.0)) return 0.0;
  // The cascade's density is constant over grid cells: asked by the cells themselves, it reads
  // the s cell of θh in double, the one the solid-angle mapping uses, where a θh rounded to a
  // float coordinate could fall across a cell boundary.
  const std::array<uint32_t, 2> cells = halfVectorCells_.cellsOf(v.wo(), wh);
  return perSteradian(table_.pdfOfCellsInSlice(v.slice(), cells), cells[0]);
}

double TabulatedBrdfSampler::pdfAt(const BrdfVertex& v, const Vec3d& wi) const {
  const Vec3d& wo = v.wo();
  if (!(wo.z > 0.0)) return cosineHemispherePdf(wi.z);
  const double w = options_.cosineWeight;
  double p = w * cosineHemispherePdf(wi.z);
  if (w < 1.0)
    if (const std::optional<HalfVector> h = halfVectorOf(wo, wi))
      p += h->incidentPdf((1.0 - w) * halfVectorPdfAt(v, h->direction));
  return p;
}

HalfVectorDensity TabulatedBrdfSampler::halfVectorDensity(const Vec3d& wo) const {
  return {.cosineShare = options_.cosineWeight,
          .sCells = options_.thetaHalfCells,
          .phiCells = options_.phiHalfCells,
          .phiOrigin = options_.layout == TabulatedBrdfOptions::Layout::Isotropic ? azimuth(wo) : 0.0,
          .constantPerCell = true,
          .density = [this, wo](const Vec3d& wh) { return halfVectorPdf(wo, wh); }};
}

}  // namespace acdf

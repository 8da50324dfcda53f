#include "acdf/envmap/environment_table.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/sample.h"

namespace acdf {

namespace {
constexpr EnumName<EnvironmentSampling> kEnvironmentSamplingNames[] = {
    {EnvironmentSampling::UniformSphere, "uniform-sphere"},
    {EnvironmentSampling::Uniform, "uniform"},
    {EnvironmentSampling::Alias, "alias"},
    {EnvironmentSampling::Adaptive, "adaptive"},
    {EnvironmentSampling::Compensated, "compensated"},
    {EnvironmentSampling::Hierarchical, "hierarchical"},
    {EnvironmentSampling::Local, "local"},
    {EnvironmentSampling::LocalCompensated, "local-compensated"},
};
}  // namespace

std::string_view toString(EnvironmentSampling strategy) { return nameOf(kEnvironmentSamplingNames, strategy); }

EnvironmentSampling parseEnvironmentSampling(std::string_view name) {
  return valueNamed(kEnvironmentSamplingNames, name, "environment sampling strategy");
}

std::string_view describe(EnvironmentSampling strategy) {
  switch (strategy) {
    case EnvironmentSampling::UniformSphere: return "directions uniform on the sphere, whatever the map (no table)";
    case EnvironmentSampling::Uniform: return "pixels by full-resolution CDFs (pbrt's and Mitsuba's table)";
    case EnvironmentSampling::Alias: return "pixels by alias tables over the rows, then the row's columns";
    case EnvironmentSampling::Adaptive: return "pixels by the paper's simplified CDFs";
    case EnvironmentSampling::Compensated:
      return "the adaptive table of the map minus its mean: the dim directions left to BSDF sampling (MIS only)";
    case EnvironmentSampling::Hierarchical: return "sample warping down a mip-map of the table (Mitsuba 3's)";
    case EnvironmentSampling::Local: return "the map times the shading normal's clamped cosine, per normal cell";
    case EnvironmentSampling::LocalCompensated: return "local, each normal cell's table compensated (MIS only)";
  }
  return "?";
}

std::string environmentSamplingNames(std::string_view separator) {
  std::string names;
  for (EnvironmentSampling s : kEnvironmentSamplings) {
    if (!names.empty()) names += separator;
    names += toString(s);
  }
  return names;
}

namespace {
struct TableOfSampling {
  EnvironmentTableStrategy table;
  EnvironmentSampling sampling;
};
constexpr TableOfSampling kTablesOfSamplings[] = {
    {EnvironmentTableStrategy::UniformSphere, EnvironmentSampling::UniformSphere},
    {EnvironmentTableStrategy::Uniform, EnvironmentSampling::Uniform},
    {EnvironmentTableStrategy::Alias, EnvironmentSampling::Alias},
    {EnvironmentTableStrategy::Adaptive, EnvironmentSampling::Adaptive},
    {EnvironmentTableStrategy::Compensated, EnvironmentSampling::Compensated},
    {EnvironmentTableStrategy::Hierarchical, EnvironmentSampling::Hierarchical},
};
}  // namespace

EnvironmentSampling samplingOf(EnvironmentTableStrategy strategy) {
  for (const TableOfSampling& t : kTablesOfSamplings)
    if (t.table == strategy) return t.sampling;
  throw std::invalid_argument("environment table: unknown strategy");
}

std::string_view toString(EnvironmentTableStrategy strategy) { return toString(samplingOf(strategy)); }

std::optional<EnvironmentTableStrategy> tableStrategyOf(EnvironmentSampling strategy) {
  for (const TableOfSampling& t : kTablesOfSamplings)
    if (t.sampling == strategy) return t.table;
  return std::nullopt;
}

namespace {

constexpr double kCompensationTolerance = 1e-6;

// max(0, L − L̄) × ΔΩ per pixel with L̄ the mean luminance over the sphere (per steradian): the
// uncompensated table is luminance × ΔΩ, so the compensated one subtracts L̄ × ΔΩ and clamps.
// An excess within rounding of the mean (relative 1e-6) counts as none, so that a constant map
// has nothing left and falls back, whatever the rounding of its sums.
std::vector<float> compensated(const EnvironmentMap& map, const std::vector<float>& power) {
  double integral = 0;
  for (float p : power) integral += p;
  const double mean = integral / (4.0 * std::numbers::pi);
  std::vector<float> out(power.size());
  for (uint32_t r = 0; r < map.height(); ++r) {
    const double solidAngle = map.mapping().pixelSolidAngle(r);
    for (uint32_t c = 0; c < map.width(); ++c) {
      const std::size_t i = std::size_t{r} * map.width() + c;
      const double excess = power[i] - mean * solidAngle;
      out[i] = excess > kCompensationTolerance * mean * solidAngle ? static_cast<float>(excess) : 0.0f;
    }
  }
  return out;
}

// The cascade of `values`: built, or read from `saved` and checked to have the grid and options
// a build would use.
Cascade cascadeOf(const std::vector<float>& values, const std::vector<GridAxis>& axes, const CascadeOptions& options,
                  const std::span<const std::byte>* saved) {
  if (!saved) return Cascade(values, axes, options);
  Cascade table = Cascade::deserialize(*saved);
  if (table.axes() != axes || !(table.options() == options))
    throw SerializationError("environment light: the saved table is for another map size or other options");
  return table;
}

// Bump when the tabulated function changes (EnvironmentMap::pixelPower, the compensation, the
// lat-long mapping): the saved tables of the old one must not be used. 2: OpenEXR's lat-long
// directions (the old mapping was mirrored).
constexpr int kTabulationVersion = 2;

// The strategies whose table is a cascade, the one table worth caching.
bool savesCascade(EnvironmentTableStrategy strategy) {
  return strategy == EnvironmentTableStrategy::Uniform || strategy == EnvironmentTableStrategy::Adaptive ||
         strategy == EnvironmentTableStrategy::Compensated;
}

bool allZero(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return v == 0.0f; });
}

}  // namespace

class PixelDistribution {
 public:
  struct Pick {
    PixelIndex pixel;
    double fractionDown = 0, fractionRight = 0;  // where in the pixel, uniform in [0, 1)
    double density = 0;                          // P(pixel) · W H
  };
  virtual ~PixelDistribution() = default;
  // u0, u1 in [0, 1).
  virtual Pick sample(float u0, float u1) const = 0;
  virtual double density(PixelIndex p) const = 0;
  virtual std::size_t bytes() const = 0;
  virtual std::vector<double> pixelProbabilities() const = 0;  // row-major, exact
  // What the table cache saves (empty: not worth saving, rebuilt in O(pixels)).
  virtual std::vector<std::byte> serialize() const { return {}; }
  virtual const Cascade* cascade() const { return nullptr; }
  virtual const PixelAlias* alias() const { return nullptr; }
  virtual const HierarchicalWarp2D* hierarchical() const { return nullptr; }
};

namespace {

// Uniform, Adaptive, Compensated: the cascade's grid cells are the pixels.
class CascadePixels final : public PixelDistribution {
 public:
  explicit CascadePixels(Cascade cascade) : cascade_(std::move(cascade)) {}
  Pick sample(float u0, float u1) const override {
    const float u[2] = {u0, u1};
    const CellSample s = cascade_.sampleCells(u);
    // Where the table put the sample inside its cell (uniformly): reused for the position in the
    // pixel, uniform in solid angle.
    return {{s.cells[0], s.cells[1]}, s.fractions[0], s.fractions[1], s.pdf};
  }
  double density(PixelIndex p) const override {
    const uint32_t cells[2] = {p.row, p.column};
    return cascade_.pdfOfCellsInSlice(0, cells);
  }
  std::size_t bytes() const override { return cascade_.bytes(); }
  std::vector<double> pixelProbabilities() const override { return cascade_.cellProbabilities(0); }
  std::vector<std::byte> serialize() const override { return cascade_.serialize(); }
  const Cascade* cascade() const override { return &cascade_; }

 private:
  Cascade cascade_;
};

// Alias and Hierarchical give a pixel's probability; the grid density is that × W H.
class AliasPixels final : public PixelDistribution {
 public:
  AliasPixels(const std::vector<float>& values, uint32_t width, uint32_t height)
      : alias_(values, width, height), pixels_(static_cast<double>(width) * height) {}
  Pick sample(float u0, float u1) const override {
    const PixelAlias::Pick pick = alias_.sample(u0, u1);
    return {pick.pixel, pick.fractionDown, pick.fractionRight, pick.probability * pixels_};
  }
  double density(PixelIndex p) const override { return alias_.probability(p) * pixels_; }
  std::size_t bytes() const override { return alias_.bytes(); }
  std::vector<double> pixelProbabilities() const override { return alias_.pixelProbabilities(); }
  const PixelAlias* alias() const override { return &alias_; }

 private:
  PixelAlias alias_;
  double pixels_;
};

class HierarchicalPixels final : public PixelDistribution {
 public:
  HierarchicalPixels(const std::vector<float>& values, const std::vector<GridAxis>& axes)
      : warp_(values, axes), pixels_(static_cast<double>(axes[0].cells()) * axes[1].cells()) {}
  Pick sample(float u0, float u1) const override {
    // Double fractions straight from the descent: no float coordinate in between.
    const HierarchicalWarp2D::CellSample pick = warp_.sampleCell(u0, u1);
    return {{pick.row, pick.column}, pick.fractionDown, pick.fractionRight, pick.probability * pixels_};
  }
  double density(PixelIndex p) const override { return warp_.probability(p.row, p.column) * pixels_; }
  std::size_t bytes() const override { return warp_.bytes(); }
  std::vector<double> pixelProbabilities() const override { return warp_.cellProbabilities(); }
  const HierarchicalWarp2D* hierarchical() const override { return &warp_; }

 private:
  HierarchicalWarp2D warp_;
  double pixels_;
};

}  // namespace

EnvironmentTable::EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentTableStrategy strategy,
                                   const SimplifyOptions& simplify)
    : EnvironmentTable(std::move(map), strategy, simplify, nullptr) {}

EnvironmentTable::EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentTableStrategy strategy,
                                   const SimplifyOptions& simplify, std::span<const std::byte> saved)
    : EnvironmentTable(std::move(map), strategy, simplify, &saved) {
  if (!saved.empty() && (!pixels_ || !savesCascade(strategy_)))
    throw SerializationError("environment light: a saved table for a strategy or map that has none");
}

EnvironmentTable::EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentTableStrategy strategy,
                                   const SimplifyOptions& simplify, const std::span<const std::byte>* saved)
    : map_(std::move(map)), strategy_(strategy) {
  if (!map_) throw std::invalid_argument("EnvironmentTable: no map");
  validate(simplify);
  if (map_->isBlack()) return;
  emitsNothing_ = false;
  if (strategy_ == EnvironmentTableStrategy::UniformSphere) return;

  const uint32_t width = map_->width(), height = map_->height();
  pdfScale_.resize(height);
  for (uint32_t r = 0; r < height; ++r)
    pdfScale_[r] = 1.0 / (static_cast<double>(width) * height * map_->mapping().pixelSolidAngle(r));

  tabulated_ = map_->pixelPower();
  if (strategy_ == EnvironmentTableStrategy::Compensated) {
    std::vector<float> values = compensated(*map_, tabulated_);
    compensationFellBack_ = allZero(values);
    if (!compensationFellBack_) tabulated_ = std::move(values);
  }
  // A map whose non-zero pixels all underflow in the table would get the engine's uniform
  // fallback, which no radiance matches: treat it as emitting nothing, like a black one.
  if (allZero(tabulated_)) {
    tabulated_.clear();
    pdfScale_.clear();
    emitsNothing_ = true;
    return;
  }

  // The tables' grid: v (rows, θ / π) then u (columns, φ / 2π), both over [0, 1).
  const std::vector<GridAxis> axes{GridAxis(height), GridAxis(width)};
  switch (strategy_) {
    case EnvironmentTableStrategy::UniformSphere: break;
    case EnvironmentTableStrategy::Uniform: {
      CascadeOptions uniform;
      uniform.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
      pixels_ = std::make_shared<CascadePixels>(cascadeOf(tabulated_, axes, uniform, saved));
      break;
    }
    case EnvironmentTableStrategy::Alias: pixels_ = std::make_shared<AliasPixels>(tabulated_, width, height); break;
    case EnvironmentTableStrategy::Hierarchical: pixels_ = std::make_shared<HierarchicalPixels>(tabulated_, axes); break;
    case EnvironmentTableStrategy::Adaptive:
    case EnvironmentTableStrategy::Compensated: {
      CascadeOptions adaptive;
      adaptive.simplify = simplify;
      pixels_ = std::make_shared<CascadePixels>(cascadeOf(tabulated_, axes, adaptive, saved));
      break;
    }
  }
}

EnvironmentTable::Sample EnvironmentTable::sample(float u0, float u1) const {
  if (emitsNothing_) return {};
  if (strategy_ == EnvironmentTableStrategy::UniformSphere) {
    const Vec3d w = sampleUniformSphere(u0, u1);
    return {w, map_->mapping().pixelOf(w), kUniformSpherePdf};
  }
  const PixelDistribution::Pick pick = pixels_->sample(clampUnit(u0), clampUnit(u1));
  map_->prefetchRadiance(pick.pixel);  // the light's next need, after the direction
  return {map_->mapping().directionInPixel(pick.pixel, pick.fractionDown, pick.fractionRight), pick.pixel,
          pick.density * pdfScale_[pick.pixel.row]};
}

double EnvironmentTable::pdf(const Vec3d& w) const { return pdf(map_->mapping().pixelOf(w)); }

double EnvironmentTable::pdf(PixelIndex p) const {
  if (emitsNothing_) return 0.0;
  if (strategy_ == EnvironmentTableStrategy::UniformSphere) return kUniformSpherePdf;
  return pixels_->density(p) * pdfScale_[p.row];
}

const Cascade* EnvironmentTable::cascade() const { return pixels_ ? pixels_->cascade() : nullptr; }

const PixelAlias* EnvironmentTable::alias() const { return pixels_ ? pixels_->alias() : nullptr; }

const HierarchicalWarp2D* EnvironmentTable::hierarchical() const { return pixels_ ? pixels_->hierarchical() : nullptr; }

std::size_t EnvironmentTable::bytes() const { return pixels_ ? pixels_->bytes() : 0; }

std::vector<double> EnvironmentTable::pixelProbabilities() const {
  return pixels_ ? pixels_->pixelProbabilities() : std::vector<double>{};
}

std::vector<std::byte> EnvironmentTable::serialize() const {
  return pixels_ ? pixels_->serialize() : std::vector<std::byte>{};
}

CacheKey EnvironmentTable::key(const EnvironmentMap& map, EnvironmentTableStrategy strategy,
                               const SimplifyOptions& simplify) {
  ContentHash content;
  content.number(map.width()).number(map.height()).values(std::span<const float>(map.rgb()));
  return cacheKey(content, "environment-light tabulation=" + std::to_string(kTabulationVersion) +
                               " strategy=" + std::string(toString(strategy)) + " " + describe(simplify) +
                               " cascade-format=" + std::to_string(Cascade::kSerialVersion));
}

Cached<EnvironmentTable> EnvironmentTable::cached(TableCache& cache, std::shared_ptr<const EnvironmentMap> map,
                                                  EnvironmentTableStrategy strategy, const SimplifyOptions& simplify,
                                                  std::string_view what) {
  if (!savesCascade(strategy) || map->isBlack()) return {EnvironmentTable(std::move(map), strategy, simplify), false};
  return cache.getOrBuild(
      key(*map, strategy, simplify), what, [&] { return EnvironmentTable(map, strategy, simplify); },
      [](const EnvironmentTable& table) { return table.serialize(); },
      [&](std::span<const std::byte> saved) { return EnvironmentTable(map, strategy, simplify, saved); });
}

}  // namespace acdf

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
};
}  // namespace

std::string_view toString(EnvironmentSampling strategy) { return nameOf(kEnvironmentSamplingNames, strategy); }

EnvironmentSampling parseEnvironmentSampling(std::string_view name) {
  return valueNamed(kEnvironmentSamplingNames, name, "environment sampling strategy");
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

bool allZero(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float v) { return v == 0.0f; });
}

}  // namespace

EnvironmentTable::EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentSampling strategy,
                                   const SimplifyOptions& simplify)
    : EnvironmentTable(std::move(map), strategy, simplify, nullptr) {}

EnvironmentTable::EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentSampling strategy,
                                   const SimplifyOptions& simplify, std::span<const std::byte> saved)
    : EnvironmentTable(std::move(map), strategy, simplify, &saved) {
  if (!cascade_ && !saved.empty())
    throw SerializationError("environment light: a saved table for a strategy or map that has none");
}

EnvironmentTable::EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentSampling strategy,
                                   const SimplifyOptions& simplify, const std::span<const std::byte>* saved)
    : map_(std::move(map)), strategy_(strategy) {
  if (!map_) throw std::invalid_argument("EnvironmentTable: no map");
  if (strategy_ == EnvironmentSampling::Local)
    throw std::invalid_argument("EnvironmentTable: local sampling is a LocalEnvironmentTable");
  validate(simplify);
  if (map_->isBlack()) return;
  emitsNothing_ = false;
  if (strategy_ == EnvironmentSampling::UniformSphere) return;

  const uint32_t width = map_->width(), height = map_->height();
  pixels_ = static_cast<double>(width) * height;
  pdfScale_.resize(height);
  for (uint32_t r = 0; r < height; ++r)
    pdfScale_[r] = 1.0 / (static_cast<double>(width) * height * map_->mapping().pixelSolidAngle(r));

  tabulated_ = map_->pixelPower();
  if (strategy_ == EnvironmentSampling::Compensated) {
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

  // The cascades' grid: v (rows, θ / π) then u (columns, φ / 2π), both over [0, 1).
  const std::vector<GridAxis> axes{GridAxis(height), GridAxis(width)};
  switch (strategy_) {
    case EnvironmentSampling::UniformSphere:
    case EnvironmentSampling::Local: break;
    case EnvironmentSampling::Uniform: {
      CascadeOptions uniform;
      uniform.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
      cascade_.emplace(cascadeOf(tabulated_, axes, uniform, saved));
      break;
    }
    case EnvironmentSampling::Alias: alias_.emplace(tabulated_, width, height); break;
    case EnvironmentSampling::Hierarchical: warp_.emplace(tabulated_, axes); break;
    case EnvironmentSampling::Adaptive:
    case EnvironmentSampling::Compensated: {
      CascadeOptions adaptive;
      adaptive.simplify = simplify;
      cascade_.emplace(cascadeOf(tabulated_, axes, adaptive, saved));
      break;
    }
  }
}

double EnvironmentTable::pixelPdf(PixelIndex p) const {
  if (alias_) return probabilityPdf(alias_->probability(p), p.row);
  if (warp_) return probabilityPdf(warp_->probability(p.row, p.column), p.row);
  // The cascade's grid cells are the pixels.
  const uint32_t cells[2] = {p.row, p.column};
  return cascade_->pdfOfCellsInSlice(0, cells) * pdfScale_[p.row];
}

EnvironmentTable::Sample EnvironmentTable::sample(float u0, float u1) const {
  if (emitsNothing_) return {};
  if (strategy_ == EnvironmentSampling::UniformSphere) {
    const Vec3d w = sampleUniformSphere(u0, u1);
    return {w, map_->mapping().pixelOf(w), kUniformSpherePdf};
  }
  PixelIndex p;
  double fractionDown, fractionRight, pdf;
  if (alias_) {
    const PixelAlias::Pick pick = alias_->sample(clampUnit(u0), clampUnit(u1));
    p = pick.pixel;
    fractionDown = pick.fractionDown;
    fractionRight = pick.fractionRight;
    pdf = probabilityPdf(pick.probability, p.row);
  } else if (warp_) {
    // Double fractions straight from the descent: no float coordinate in between.
    const HierarchicalWarp2D::CellSample pick = warp_->sampleCell(clampUnit(u0), clampUnit(u1));
    p = {pick.row, pick.column};
    fractionDown = pick.fractionDown;
    fractionRight = pick.fractionRight;
    pdf = probabilityPdf(pick.probability, p.row);
  } else {
    const float u[2] = {clampUnit(u0), clampUnit(u1)};
    const CellSample s = cascade_->sampleCells(u);
    p = {s.cells[0], s.cells[1]};
    // Where the table put the sample inside its cell (uniformly): reused for the position in
    // the pixel, uniform in solid angle.
    fractionDown = s.fractions[0];
    fractionRight = s.fractions[1];
    pdf = s.pdf * pdfScale_[p.row];
  }
  return {map_->mapping().directionInPixel(p, fractionDown, fractionRight), p, pdf};
}

double EnvironmentTable::pdf(const Vec3d& w) const { return pdf(map_->mapping().pixelOf(w)); }

double EnvironmentTable::pdf(PixelIndex p) const {
  if (emitsNothing_) return 0.0;
  if (strategy_ == EnvironmentSampling::UniformSphere) return kUniformSpherePdf;
  return pixelPdf(p);
}

std::size_t EnvironmentTable::bytes() const {
  if (cascade_) return cascade_->bytes();
  if (alias_) return alias_->bytes();
  if (warp_) return warp_->bytes();
  return 0;
}

std::vector<double> EnvironmentTable::pixelProbabilities() const {
  if (cascade_) return cascade_->cellProbabilities(0);
  if (alias_) return alias_->pixelProbabilities();
  if (warp_) return warp_->cellProbabilities();
  return {};
}

std::vector<std::byte> EnvironmentTable::serialize() const {
  return cascade_ ? cascade_->serialize() : std::vector<std::byte>{};
}

CacheKey EnvironmentTable::key(const EnvironmentMap& map, EnvironmentSampling strategy,
                               const SimplifyOptions& simplify) {
  ContentHash content;
  content.number(map.width()).number(map.height()).values(std::span<const float>(map.rgb()));
  return cacheKey(content, "environment-light tabulation=" + std::to_string(kTabulationVersion) +
                               " strategy=" + std::string(toString(strategy)) + " " + describe(simplify) +
                               " cascade-format=" + std::to_string(Cascade::kSerialVersion));
}

Cached<EnvironmentTable> EnvironmentTable::cached(TableCache& cache, std::shared_ptr<const EnvironmentMap> map,
                                                  EnvironmentSampling strategy, const SimplifyOptions& simplify,
                                                  std::string_view what) {
  const bool cascade = strategy == EnvironmentSampling::Uniform || strategy == EnvironmentSampling::Adaptive ||
                       strategy == EnvironmentSampling::Compensated;
  if (!cascade || map->isBlack()) return {EnvironmentTable(std::move(map), strategy, simplify), false};
  return cache.getOrBuild(
      key(*map, strategy, simplify), what, [&] { return EnvironmentTable(map, strategy, simplify); },
      [](const EnvironmentTable& table) { return table.serialize(); },
      [&](std::span<const std::byte> saved) { return EnvironmentTable(map, strategy, simplify, saved); });
}

}  // namespace acdf

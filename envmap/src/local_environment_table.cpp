#include "acdf/envmap/local_environment_table.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "acdf/sampling/option_error.h"
#include "acdf/sampling/sample.h"

namespace acdf {

namespace {

constexpr uint32_t kMaxGridCells = 4096;

// Rounding in the angles below is far under 1e-9 rad; widening the bound by that much keeps
// cosBound > 0 for directions a hair above the horizon of a cell's edge normal.
constexpr double kAngleMargin = 1e-9;

double angleBetween(const Vec3d& a, const Vec3d& b) {
  const Vec3d c{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  return std::atan2(std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z), a.x * b.x + a.y * b.y + a.z * b.z);
}

const LocalEnvironmentOptions& validated(const LocalEnvironmentOptions& options) {
  validate(options);
  return options;
}

}  // namespace

void validate(const LocalEnvironmentOptions& o) {
  auto check = [](uint32_t value, const char* name) {
    if (value < 1 || value > kMaxGridCells)
      throw OptionError("local environment", name,
                        "must be in [1, " + std::to_string(kMaxGridCells) + "], got " + std::to_string(value));
  };
  check(o.normalRows, "normal_rows");
  check(o.normalColumns, "normal_columns");
  check(o.blockSize, "block_size");
}

LocalEnvironmentTable::Cap LocalEnvironmentTable::capOf(double thetaA, double thetaB, double phiA, double phiB) {
  const double pi = std::numbers::pi;
  const double maxSin = thetaA <= pi / 2 && pi / 2 <= thetaB ? 1.0 : std::max(std::sin(thetaA), std::sin(thetaB));
  const double radius = std::min(pi, (thetaB - thetaA) / 2 + maxSin * (phiB - phiA) / 2);
  return {LatLongMapping::direction((thetaA + thetaB) / 2, (phiA + phiB) / 2), radius};
}

double LocalEnvironmentTable::cosBound(const Vec3d& cellCentre, double cellRadius, const Vec3d& blockCentre,
                                       double blockRadius) {
  // cos ∠ <= −s implies ∠ >= π/2 + s (as sin s <= s): with s the radii and the margin widened
  // past the rounding of both ways, the angle below is >= π/2 too. Most blocks of a cell lie this
  // far below its horizon; this skips their atan2.
  const double reach = cellRadius + blockRadius + kAngleMargin + 1e-12;
  if (dot(cellCentre, blockCentre) <= -reach) return 0.0;
  const double angle = std::max(0.0, angleBetween(cellCentre, blockCentre) - cellRadius - blockRadius - kAngleMargin);
  return angle >= std::numbers::pi / 2 ? 0.0 : std::cos(angle);
}

LocalEnvironmentTable::LocalEnvironmentTable(std::shared_ptr<const EnvironmentMap> map,
                                             const LocalEnvironmentOptions& options, const SimplifyOptions& simplify,
                                             bool compensated)
    : map_(std::move(map)),
      options_(validated(options)),
      normalCells_(options_.normalColumns, options_.normalRows),
      simplify_(simplify),
      compensated_(compensated) {
  if (!map_) throw std::invalid_argument("LocalEnvironmentTable: no map");
  validate(simplify_);
  slices_ = std::make_unique<Slice[]>(slices());
  if (map_->isBlack()) return;
  const std::vector<float> power = map_->pixelPower();
  if (std::all_of(power.begin(), power.end(), [](float v) { return v == 0.0f; })) return;
  emitsNothing_ = false;

  const uint32_t width = map_->width(), height = map_->height();
  blockHeight_ = std::min(options_.blockSize, height);
  blockWidth_ = std::min(options_.blockSize, width);
  blockRows_ = (height + blockHeight_ - 1) / blockHeight_;
  blockColumns_ = (width + blockWidth_ - 1) / blockWidth_;
  const std::size_t blocks = std::size_t{blockRows_} * blockColumns_;
  const std::size_t blockPixels = std::size_t{blockHeight_} * blockWidth_;

  // The pixel tables' grid, row-major (block row, block column, row in block, column in block);
  // the padding past the map's edge stays 0 and is never sampled.
  std::vector<float> values(blocks * blockPixels, 0.0f);
  blockMass_.assign(blocks, 0.0);
  blockCaps_.resize(blocks);
  const double pi = std::numbers::pi;
  for (uint32_t br = 0; br < blockRows_; ++br) {
    for (uint32_t bc = 0; bc < blockColumns_; ++bc) {
      const std::size_t b = std::size_t{br} * blockColumns_ + bc;
      const uint32_t rows = std::min(blockHeight_, height - br * blockHeight_);
      const uint32_t columns = std::min(blockWidth_, width - bc * blockWidth_);
      double mass = 0;
      for (uint32_t i = 0; i < rows; ++i)
        for (uint32_t j = 0; j < columns; ++j) {
          const PixelIndex p = pixelOf(br, bc, i, j);
          const float v = power[std::size_t{p.row} * width + p.column];
          values[b * blockPixels + std::size_t{i} * blockWidth_ + j] = v;
          mass += v;
        }
      blockMass_[b] = mass;
      if (mass == 0)  // no slice gives it mass, but an adaptive interval may reach it: uniform
        for (uint32_t i = 0; i < rows; ++i)
          for (uint32_t j = 0; j < columns; ++j) values[b * blockPixels + std::size_t{i} * blockWidth_ + j] = 1.0f;
      const uint32_t r0 = br * blockHeight_, c0 = bc * blockWidth_;
      blockCaps_[b] =
          capOf(pi * r0 / height, pi * (r0 + rows) / height, 2 * pi * c0 / width, 2 * pi * (c0 + columns) / width);
      if (compensated_) {
        double solidAngle = 0;
        for (uint32_t i = 0; i < rows; ++i) solidAngle += map_->mapping().pixelSolidAngle(r0 + i) * columns;
        blockSolidAngle_.push_back(solidAngle);
      }
    }
  }
  CascadeOptions exact;
  exact.conditioningDims = 2;
  exact.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
  pixels_.emplace(values,
                  std::vector<GridAxis>{GridAxis(blockRows_), GridAxis(blockColumns_), GridAxis(blockHeight_),
                                        GridAxis(blockWidth_)},
                  exact);

  pdfScale_.resize(height);
  for (uint32_t r = 0; r < height; ++r)
    pdfScale_[r] = 1.0 / (static_cast<double>(blocks) * blockPixels * map_->mapping().pixelSolidAngle(r));
}

std::size_t LocalEnvironmentTable::sliceOf(const Vec3d& normal) const {
  const PixelIndex cell = normalCells_.pixelOf(normal);
  return std::size_t{cell.row} * options_.normalColumns + cell.column;
}

const Cascade& LocalEnvironmentTable::slice(std::size_t index) const {
  Slice& s = slices_[index];
  // Built: one acquire load, not call_once's heavier path on every sample.
  if (s.ready.load(std::memory_order_acquire)) return *s.blocks;
  std::call_once(s.once, [&] {
    const double pi = std::numbers::pi;
    const uint32_t r = static_cast<uint32_t>(index / options_.normalColumns);
    const uint32_t c = static_cast<uint32_t>(index % options_.normalColumns);
    const Cap cell = capOf(pi * r / options_.normalRows, pi * (r + 1) / options_.normalRows,
                           2 * pi * c / options_.normalColumns, 2 * pi * (c + 1) / options_.normalColumns);
    std::vector<double> lit(blockMass_.size());
    for (std::size_t b = 0; b < lit.size(); ++b)
      lit[b] = blockMass_[b] * cosBound(cell.centre, cell.radius, blockCaps_[b].centre, blockCaps_[b].radius);
    if (compensated_) {
      double total = 0;
      for (double v : lit) total += v;
      const double mean = total / (4 * pi);  // per steradian, over the sphere
      std::vector<double> excess(lit.size());
      bool any = false;
      for (std::size_t b = 0; b < lit.size(); ++b) {
        excess[b] = std::max(0.0, lit[b] - mean * blockSolidAngle_[b]);
        any = any || excess[b] > 0;
      }
      if (any) lit = std::move(excess);
    }
    std::vector<float> values(lit.size());
    for (std::size_t b = 0; b < values.size(); ++b) {
      const double v = lit[b];
      // Clamped into the normal float range: a positive product must not round to 0.
      values[b] = v > 0 ? static_cast<float>(std::clamp(v, double{std::numeric_limits<float>::min()},
                                                        double{std::numeric_limits<float>::max()}))
                        : 0.0f;
    }
    CascadeOptions adaptive;
    adaptive.simplify = simplify_;
    // Isolated: while this thread holds the once flag, the cascade's parallel build must not
    // pick up an outer task (a render tile) that may ask for this very slice.
    tbb::this_task_arena::isolate([&] {
      s.blocks.emplace(values, std::vector<GridAxis>{GridAxis(blockRows_), GridAxis(blockColumns_)}, adaptive);
    });
    s.ready.store(true, std::memory_order_release);
    built_.fetch_add(1, std::memory_order_acq_rel);
  });
  return *s.blocks;
}

void LocalEnvironmentTable::buildAll() const {
  if (emitsNothing_) return;
  tbb::parallel_for(std::size_t{0}, slices(), [&](std::size_t i) { slice(i); });
}

LocalEnvironmentTable::Sample LocalEnvironmentTable::sample(const Vec3d& normal, float u0, float u1) const {
  return sampleInCell(sliceOf(normal), u0, u1);
}

LocalEnvironmentTable::Sample LocalEnvironmentTable::sampleInCell(std::size_t cell, float u0, float u1) const {
  if (emitsNothing_) return {};
  const Cascade& blocks = slice(cell);
  const float u[2] = {clampUnit(u0), clampUnit(u1)};
  const CellSample b = blocks.sampleCells(u);
  const uint32_t br = b.cells[0], bc = b.cells[1];
  // Where the block table put the sample inside its cell (uniformly): reused for the pixel.
  const float inBlock[2] = {clampUnit(static_cast<float>(b.fractions[0])),
                            clampUnit(static_cast<float>(b.fractions[1]))};
  const CellSample q = pixels_->sampleCellsInSlice(blockIndex(br, bc), inBlock);
  const PixelIndex p = pixelOf(br, bc, q.cells[0], q.cells[1]);
  map_->prefetchRadiance(p);  // the light's next need, after the direction
  const double pdf = static_cast<double>(b.pdf) * q.pdf * pdfScale_[p.row];
  return {map_->mapping().directionInPixel(p, q.fractions[0], q.fractions[1]), p, pdf};
}

double LocalEnvironmentTable::pdf(const Vec3d& normal, const Vec3d& w) const {
  return pdf(normal, map_->mapping().pixelOf(w));
}

double LocalEnvironmentTable::pdf(const Vec3d& normal, PixelIndex p) const { return pdfInCell(sliceOf(normal), p); }

double LocalEnvironmentTable::pdfInCell(std::size_t cell, PixelIndex p) const {
  if (emitsNothing_) return 0.0;
  const uint32_t br = p.row / blockHeight_, bc = p.column / blockWidth_;
  const uint32_t block[2] = {br, bc}, inBlock[2] = {p.row - br * blockHeight_, p.column - bc * blockWidth_};
  return static_cast<double>(slice(cell).pdfOfCellsInSlice(0, block)) *
         pixels_->pdfOfCellsInSlice(blockIndex(br, bc), inBlock) * pdfScale_[p.row];
}

std::size_t LocalEnvironmentTable::bytes() const {
  std::size_t total = pixels_ ? pixels_->bytes() : 0;
  for (std::size_t i = 0; i < slices(); ++i)
    if (slices_[i].ready.load(std::memory_order_acquire)) total += slices_[i].blocks->bytes();
  return total;
}

std::vector<double> LocalEnvironmentTable::pixelProbabilities(const Vec3d& normal) const {
  if (emitsNothing_) return {};
  const uint32_t width = map_->width(), height = map_->height();
  const std::vector<double> blocks = slice(sliceOf(normal)).cellProbabilities(0);
  std::vector<double> out(std::size_t{width} * height, 0.0);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const uint32_t br = static_cast<uint32_t>(b / blockColumns_), bc = static_cast<uint32_t>(b % blockColumns_);
    const std::vector<double> inBlock = pixels_->cellProbabilities(b);
    for (uint32_t i = 0; i < blockHeight_; ++i)
      for (uint32_t j = 0; j < blockWidth_; ++j) {
        const PixelIndex p = pixelOf(br, bc, i, j);
        if (p.row < height && p.column < width)
          out[std::size_t{p.row} * width + p.column] = blocks[b] * inBlock[std::size_t{i} * blockWidth_ + j];
      }
  }
  return out;
}

}  // namespace acdf

#pragma once
// Local environment sampling (Lawrence et al. 2005, their application of adaptive CDFs): the
// distribution of directions for a surface of normal n, ∝ L(ω) · max(0, n · ω), not L(ω) alone.
// In the map's own frame (lat_long.h) like EnvironmentTable, so lights of any rotation share it.
//
// A uniform table of it is four-dimensional, every normal cell a full-resolution map table:
// 32 × 64 normal cells × a 1024 × 512 map = 1G floats, 4 GiB (denseBytes()). This one factorises
// it, never materialising the dense grid. The map is split into blocks of B × B pixels (the last
// ones may be partial), and
//     P(pixel | n) = P(block | N) · P(pixel | block),   N = the normal cell holding n,
// - P(pixel | block) ∝ luminance × ΔΩ (the global tabulated function, EnvironmentMap::pixelPower,
//   restricted to the block): independent of the normal, shared by every normal cell. One
//   Cascade conditioned on the block (block row, block column | pixel row, pixel column in the
//   block), uniform levels, so the probabilities inside a block are exact. A block without mass
//   samples its pixels uniformly (never its padding past the map's edge).
// - P(block | N) ∝ mass(block) × cosBound(N, block): a 2D adaptive Cascade over the block grid
//   per normal cell ("slice"), built on first use by a normal in it (thread-safe) or all at once
//   (buildAll(), in parallel).
// A sample picks a block, then a pixel in it, then a direction uniformly in solid angle inside the
// pixel, so the density per steradian is constant per pixel: pdf(ω | n) = P(pixel | n) / ΔΩ_row.
// pdf() uses the slice of n's normal cell, the one sample() draws from, so an MIS weight built
// from it is that of the technique actually used.
//
// The bound. With c the centre direction of a normal cell or block and r an upper bound of its
// angular radius (no point of it farther than r from c),
//     cosBound(N, B) = cos(max(0, ∠(c_N, c_B) − r_N − r_B)),  and 0 when that angle is >= π/2.
// Proof that it bounds the cosine: for n in N and ω in B the triangle inequality on the sphere
// gives ∠(c_N, c_B) <= ∠(c_N, n) + ∠(n, ω) + ∠(ω, c_B) <= r_N + ∠(n, ω) + r_B, so
// ∠(n, ω) >= ∠(c_N, c_B) − r_N − r_B and, cos being decreasing on [0, π], n · ω <= cosBound; when
// the angle is >= π/2, n · ω <= 0. Hence L(ω) max(0, n · ω) > 0 for any n in N implies
// cosBound(N, block of ω) > 0 and mass(block) > 0 (the pixel of ω has luminance): the slice's
// value for the block is positive, so is its probability (the engine keeps pdf > 0 wherever the
// tabulated function is > 0, docs/engine.md), and so is P(pixel | block). The pdf is positive
// wherever the integrand is, for every normal in the cell: light sampling alone is unbiased.
// The radius of a lat-long cell [θa, θb] × [φa, φb] around its centre (θc, φc): any point (θ, φ)
// of it is reached along the meridian φc (|θ − θc| <= (θb − θa)/2) and then along the parallel θ
// (sin θ |φ − φc| <= max(sin θ over the cell) (φb − φa)/2), a path no shorter than the geodesic,
// so r = (θb − θa)/2 + max sin θ · (φb − φa)/2 (capped at π) is safe.
//
// Compensated (Karlík et al. 2019, as EnvironmentTable's Compensated for the whole map, here per
// normal cell): a slice holds max(0, v_b − m_N Ω_b) instead of v_b = mass(b) cosBound(N, b), with
// Ω_b the block's solid angle and m_N = Σ_b v_b / 4π the mean of the slice's function over the
// sphere, as Compensated takes the map's (the mean over the lit hemisphere, twice that, left too
// much to BSDF sampling: docs/performance.md, "Local environment sampling"). Blocks below the
// mean get pdf 0 and are left to BSDF sampling under MIS: an incomplete pdf. Inside a block the
// pixels keep P(pixel | block), so the compensation is as coarse as the blocks. A slice with
// nothing above its mean keeps v_b.
//
// A black map (or one whose every pixel underflows in the table) emits nothing: sample() returns
// pdf 0, pdf() returns 0, as EnvironmentTable. A normal cell whose every lit block is below its
// horizon gets the engine's uniform fallback over blocks: its integrand is 0, any pdf will do.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/environment_table.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/simplify.h"

namespace acdf {

struct LocalEnvironmentOptions {
  uint32_t normalRows = 32;     // normal cells in θ (from the map's +Y)
  uint32_t normalColumns = 64;  // normal cells in φ
  uint32_t blockSize = 16;      // B: pixels per block side
  bool operator==(const LocalEnvironmentOptions&) const = default;
};

// The one check of these options. Throws OptionError: normal_rows, normal_columns, block_size
// outside [1, 4096].
void validate(const LocalEnvironmentOptions& options);

class LocalEnvironmentTable {
 public:
  using Sample = EnvironmentTable::Sample;

  // Builds the per-block pixel tables; the slices, adaptive with `simplify`, are built on first
  // use; `compensated` slices are those of the header comment's compensation. Throws
  // std::invalid_argument for no map, OptionError for bad options.
  explicit LocalEnvironmentTable(std::shared_ptr<const EnvironmentMap> map, const LocalEnvironmentOptions& options = {},
                                 const SimplifyOptions& simplify = {}, bool compensated = false);

  // normal: map frame, non-zero (any length); u0, u1 in [0, 1) (clamped into it). Thread-safe.
  Sample sample(const Vec3d& normal, float u0, float u1) const;
  // Density per steradian of sample(normal, ·) at the map-frame direction w (non-zero).
  double pdf(const Vec3d& normal, const Vec3d& w) const;
  // The same at any direction of map pixel p (the density is constant per pixel), for a caller
  // that already knows w's pixel.
  double pdf(const Vec3d& normal, PixelIndex p) const;
  // sample() and pdf() for the normals of normal cell `cell` (sliceOf), for a caller that makes
  // several calls with one normal and finds its cell once.
  Sample sampleInCell(std::size_t cell, float u0, float u1) const;
  double pdfInCell(std::size_t cell, PixelIndex p) const;

  // Builds every slice not built yet, in parallel.
  void buildAll() const;

  // The tables themselves, for sampling them in other arithmetic (acdf.mitsuba's drjit arrays):
  // P(block | normal cell `cell`), a 2D cascade over the block grid (built on first use), and
  // P(pixel | block), conditioned on (block row, block column) over B × B pixels (null when the
  // light emits nothing).
  const Cascade& blocksOfCell(std::size_t cell) const { return slice(cell); }
  const Cascade* pixelTable() const { return pixels_ ? &*pixels_ : nullptr; }
  uint32_t blockHeight() const { return blockHeight_; }
  uint32_t blockWidth() const { return blockWidth_; }

  const EnvironmentMap& map() const { return *map_; }
  const LocalEnvironmentOptions& options() const { return options_; }
  const SimplifyOptions& simplify() const { return simplify_; }
  bool emitsNothing() const { return emitsNothing_; }
  // Whether the slices are compensated: pdf 0 on blocks below their normal cell's mean, for
  // estimators that allow an incomplete pdf only.
  bool compensated() const { return compensated_; }

  // Normal cells, row-major (θ, φ); the one holding a normal (map frame, non-zero), as
  // LatLongMapping::pixelOf puts it in a normalColumns × normalRows grid.
  std::size_t slices() const { return std::size_t{options_.normalRows} * options_.normalColumns; }
  std::size_t sliceOf(const Vec3d& normal) const;
  std::size_t slicesBuilt() const { return built_.load(std::memory_order_acquire); }
  // Bytes of the pixel tables and the slices built so far.
  std::size_t bytes() const;
  // What the dense 4D uniform float table would take: slices() × pixels × 4 bytes.
  uint64_t denseBytes() const { return uint64_t{slices()} * map_->width() * map_->height() * sizeof(float); }

  // Probability sample(normal, ·) gives each pixel, row-major (empty if it emits nothing). Exact.
  std::vector<double> pixelProbabilities(const Vec3d& normal) const;

  // cosBound(N, B) of the header comment for cells given by centre directions (unit) and radii.
  static double cosBound(const Vec3d& cellCentre, double cellRadius, const Vec3d& blockCentre, double blockRadius);
  // Centre direction and radius bound of the lat-long cell [θa, θb] × [φa, φb].
  struct Cap {
    Vec3d centre;
    double radius;
  };
  static Cap capOf(double thetaA, double thetaB, double phiA, double phiB);

 private:
  struct Slice {
    std::once_flag once;
    std::atomic<bool> ready{false};
    std::optional<Cascade> blocks;  // P(block | normal cell)
  };
  const Cascade& slice(std::size_t index) const;
  PixelIndex pixelOf(uint32_t blockRow, uint32_t blockColumn, uint32_t row, uint32_t column) const {
    return {blockRow * blockHeight_ + row, blockColumn * blockWidth_ + column};
  }
  // The pixel table's slice of a block: its conditioning cells (block row, block column), row-major.
  std::size_t blockIndex(uint32_t blockRow, uint32_t blockColumn) const {
    return std::size_t{blockRow} * blockColumns_ + blockColumn;
  }

  std::shared_ptr<const EnvironmentMap> map_;
  LocalEnvironmentOptions options_;
  LatLongMapping normalCells_;  // the normal cells as the pixels of a lat-long grid
  SimplifyOptions simplify_;
  bool compensated_ = false;
  bool emitsNothing_ = true;
  uint32_t blockHeight_ = 0, blockWidth_ = 0;  // B, or the map's size if smaller
  uint32_t blockRows_ = 0, blockColumns_ = 0;
  std::vector<double> blockMass_;  // Σ luminance × ΔΩ per block, row-major
  std::vector<Cap> blockCaps_;     // per block
  std::vector<double> blockSolidAngle_;  // Ω_b per block (compensated only)
  std::optional<Cascade> pixels_;  // P(pixel | block)
  std::vector<double> pdfScale_;   // per map row: 1 / (blocks × block pixels × ΔΩ_row)
  std::unique_ptr<Slice[]> slices_;
  mutable std::atomic<std::size_t> built_{0};
};

}  // namespace acdf

#pragma once
// The distribution of directions a sampling strategy gives one environment map, in the map's own
// frame (lat_long.h): the expensive part of an environment light, built once and shared by every
// light of that map whatever its rotation and scale (environment_light.h), and cached on disk
// (docs/table-cache.md).
//
// Distribution. A table holds, per pixel, luminance × ΔΩ (EnvironmentMap::pixelPower(), ∝
// luminance × sin θ) on the grid (v, u) ∈ [0,1)², v = row axis (θ / π), u = column axis (φ / 2π).
// A sample picks a pixel with probability P(pixel) from the table, then a direction uniformly in
// solid angle inside it (LatLongMapping::directionInPixel), so the density per steradian is
// constant on each pixel:
//     pdf(ω) = P(pixel) / ΔΩ_row = p(v, u) / (W H ΔΩ_row) = p(v, u) / (2π² · s̄_row),
// where p(v, u) is the table's density on the unit square and s̄_row = (cos θa − cos θb) / Δθ is
// the mean of sin θ over the row: pbrt's p(u,v) / (2π² sin θ) with sin θ averaged over the pixel.
// s̄ > 0 on every row (also at the poles), so nothing is ever divided by zero; and since the
// radiance is constant per pixel too (nearest lookup), a table with the exact pixel probabilities
// gives L/pdf = ∫L dω for every sample: zero variance. The uniform table's probabilities are the
// exact ones rounded through its float CDFs (a few ulps of F per level, docs/engine.md), so a dim
// pixel's pdf can be off by a large factor while the estimator hardly notices: the relative
// variance of L/pdf it leaves is its χ²-divergence from the exact probabilities: 4e-11 to 8e-8 on
// the 1024 × 512 generated and real maps of the tests (tested below 1e-6), 2.2e-6 on a 4096 × 2048
// sun and sky whose sun is a few of its 8M pixels (`acdf envmap-stats` reports it as
// uniform_chi2_divergence).
//
// Every lit pixel is reachable: pdf > 0 wherever the radiance is > 0, for every complete table
// (all but Compensated; the CDFs keep a positive step for every cell of positive mass,
// docs/engine.md), so a light-only estimator is unbiased with any of them.
//
// Strategies (EnvironmentTableStrategy; the constructor builds only the chosen one):
//   UniformSphere directions uniform on the sphere, pdf 1/(4π), whatever the map: no table;
//   Uniform       cascade of full-resolution 1D CDFs (pbrt's and Mitsuba's table);
//   Alias         PixelAlias: O(1) pixel choice (alias tables over rows, then over the row's
//                 columns; pixel_alias.h says why not one table over all pixels);
//   Adaptive      cascade of simplified 1D CDFs (the paper's method; `simplify`, libsampling's
//                 defaults);
//   Hierarchical  HierarchicalWarp2D: sample warping down a mip-map pyramid of the table (Clarberg
//                 et al. 2005, Mitsuba 3's Hierarchical2D); keeps stratified variates stratified;
//   Compensated   the Adaptive table of max(0, L − L̄) × ΔΩ with L̄ = ∫L dω / 4π the mean luminance
//                 (pbrt-v4's MIS compensation, Karlík et al. 2019): directions dimmer than the mean
//                 get pdf 0 and are left to BSDF sampling under MIS. A map with nothing above its
//                 mean (a constant one) falls back to the uncompensated table
//                 (compensationFellBack()).
// A light offers two more strategies (EnvironmentSampling): Local, the distribution of
// L(ω) max(0, n · ω) for the surface normal n of each call, which is no table of one map but one
// per normal cell (LocalEnvironmentTable, local_environment_table.h), and LocalCompensated, the
// same with each normal cell's table compensated as Compensated compensates the map's.
// complete() is false for Compensated unless it fell back: its pdf may be 0 where the map has
// light, so it serves only estimators that allow an incomplete pdf (EnvironmentLight chooses).
//
// A black map emits nothing: no table is built, sample() returns pdf 0 (no sample, the caller
// skips it; an MIS weight against it is then 1 for the other technique), pdf() returns 0.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/pixel_alias.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/hierarchical_warp_2d.h"
#include "acdf/sampling/simplify.h"
#include "acdf/sampling/sphere.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

// How a light samples its map (EnvironmentLightOptions::strategy; the choice the command line,
// scene files and reports name): a table of this class, or Local.
enum class EnvironmentSampling {
  UniformSphere,
  Uniform,
  Alias,
  Adaptive,
  Compensated,
  Hierarchical,
  Local,
  LocalCompensated
};

inline constexpr EnvironmentSampling kEnvironmentSamplings[] = {
    EnvironmentSampling::UniformSphere, EnvironmentSampling::Uniform,     EnvironmentSampling::Alias,
    EnvironmentSampling::Adaptive,      EnvironmentSampling::Compensated, EnvironmentSampling::Hierarchical,
    EnvironmentSampling::Local,         EnvironmentSampling::LocalCompensated};

// "uniform-sphere", "uniform", "alias", "adaptive", "compensated", "hierarchical", "local",
// "local-compensated"; parse throws std::invalid_argument naming them.
std::string_view toString(EnvironmentSampling strategy);
EnvironmentSampling parseEnvironmentSampling(std::string_view name);
// What the strategy samples, in one line: the command line's help and Python's
// acdf.environment_samplings() list every strategy from here.
std::string_view describe(EnvironmentSampling strategy);
// Every strategy's name in kEnvironmentSamplings' order, joined by `separator`.
std::string environmentSamplingNames(std::string_view separator);

// The tables of one map this class builds: every light strategy but Local.
enum class EnvironmentTableStrategy { UniformSphere, Uniform, Alias, Adaptive, Compensated, Hierarchical };

inline constexpr EnvironmentTableStrategy kEnvironmentTableStrategies[] = {
    EnvironmentTableStrategy::UniformSphere, EnvironmentTableStrategy::Uniform,
    EnvironmentTableStrategy::Alias,         EnvironmentTableStrategy::Adaptive,
    EnvironmentTableStrategy::Compensated,   EnvironmentTableStrategy::Hierarchical};

// The light strategy of that name; its table's name (the light's spelling, in cache keys and
// messages).
EnvironmentSampling samplingOf(EnvironmentTableStrategy strategy);
std::string_view toString(EnvironmentTableStrategy strategy);
// The table a light strategy samples with; none for the local ones.
std::optional<EnvironmentTableStrategy> tableStrategyOf(EnvironmentSampling strategy);

// What every table strategy gives the light: a pixel and where in it, with the density on the
// unit square of the pixel grid (P(pixel) · W H). One adapter per table, in environment_table.cpp.
class PixelDistribution;

class EnvironmentTable {
 public:
  struct Sample {
    Vec3d direction;   // map frame, unit length
    PixelIndex pixel;  // the pixel it lies in, whose radiance it carries
    double pdf = 0;    // per steradian; 0 only for a map that emits nothing
  };

  // Throws std::invalid_argument for no map or bad simplify options (or what the table's
  // constructor throws).
  EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentTableStrategy strategy,
                   const SimplifyOptions& simplify = {});

  // Caching. Only the cascades (Uniform, Adaptive, Compensated) are worth saving; the other tables
  // and everything else the constructor computes (the tabulated function, per-row pdf scales)
  // take O(pixels) and are rebuilt.
  //
  // The table serialize() saved for the same map, strategy and options: the same samples and
  // pdfs bit for bit. Throws SerializationError if `saved` is not a valid table of this map's
  // size and these options (the cache key guards the rest: same pixels, strategy).
  EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentTableStrategy strategy,
                   const SimplifyOptions& simplify, std::span<const std::byte> saved);
  // The cascade, serialized; empty for the other strategies and for a map that emits nothing.
  std::vector<std::byte> serialize() const;
  // The map's size and pixels, the strategy, the simplify options and the format versions.
  static CacheKey key(const EnvironmentMap& map, EnvironmentTableStrategy strategy, const SimplifyOptions& simplify);
  // The table from `cache` if it holds a valid one, else built (and stored if worth caching).
  // `what` names the table in warnings.
  static Cached<EnvironmentTable> cached(TableCache& cache, std::shared_ptr<const EnvironmentMap> map,
                                         EnvironmentTableStrategy strategy, const SimplifyOptions& simplify,
                                         std::string_view what);

  // u0, u1 in [0, 1) (clamped into it).
  Sample sample(float u0, float u1) const;
  // Density per steradian of sample() at the map-frame direction w (non-zero).
  double pdf(const Vec3d& w) const;
  // The same, for every direction of the map's pixel p (the pdf is constant on a pixel): for a
  // caller that has the pixel already.
  double pdf(PixelIndex p) const;

  EnvironmentTableStrategy strategy() const { return strategy_; }
  const EnvironmentMap& map() const { return *map_; }
  // True for a black map (and one whose every pixel underflows in the table): nothing to sample.
  bool emitsNothing() const { return emitsNothing_; }
  bool compensationFellBack() const { return compensationFellBack_; }
  // pdf > 0 wherever the map has light.
  bool complete() const { return strategy_ != EnvironmentTableStrategy::Compensated || compensationFellBack_; }

  // The cascade of a Uniform, Adaptive or Compensated table, for a caller that samples it in its
  // own arithmetic (its grid cells are the pixels: axis 0 the rows, axis 1 the columns); null for
  // the other strategies and a map that emits nothing.
  const Cascade* cascade() const;
  // The same for an Alias and a Hierarchical table.
  const PixelAlias* alias() const;
  const HierarchicalWarp2D* hierarchical() const;
  // Bytes of the table (0 without one).
  std::size_t bytes() const;
  // Probability the table gives each pixel, row-major (empty without a table). Exact.
  std::vector<double> pixelProbabilities() const;
  // The tabulated function (per pixel, row-major), whose normalisation the table approximates
  // (empty without a table).
  const std::vector<float>& tabulated() const { return tabulated_; }

 private:
  // The constructors' shared work; saved: null to build the cascade, else to read it.
  EnvironmentTable(std::shared_ptr<const EnvironmentMap> map, EnvironmentTableStrategy strategy,
                   const SimplifyOptions& simplify, const std::span<const std::byte>* saved);

  std::shared_ptr<const EnvironmentMap> map_;
  EnvironmentTableStrategy strategy_;
  bool emitsNothing_ = true;
  bool compensationFellBack_ = false;
  std::vector<float> tabulated_;
  std::shared_ptr<const PixelDistribution> pixels_;  // null for UniformSphere and a map that emits nothing
  std::vector<double> pdfScale_;                     // per row: 1 / (W H ΔΩ_row), grid density → per steradian
};

}  // namespace acdf

#pragma once
// An environment light: an EnvironmentMap placed in the world (rotation, scale), with a sampling
// distribution over its pixels built by libsampling.
//
// Distribution. The table holds, per pixel, luminance × ΔΩ (EnvironmentMap::pixelPower(), ∝
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
// Every lit pixel is reachable: pdf > 0 wherever the radiance is > 0, for every strategy but
// Compensated (the CDFs keep a positive step for every cell of positive mass, docs/engine.md), so
// a light-only estimator is unbiased with any of them.
//
// Strategies (only the chosen table is built, by the constructor):
//   Uniform      Cascade of full-resolution 1D CDFs (pbrt's and Mitsuba's table);
//   Alias        PixelAlias: O(1) pixel choice (alias tables over rows, then over the row's
//                columns; pixel_alias.h says why not one table over all pixels);
//   Adaptive     Cascade of simplified 1D CDFs (the paper's method; options.simplify, libsampling's
//                defaults);
//   Hierarchical HierarchicalWarp2D: sample warping down a mip-map pyramid of the table (Clarberg
//                et al. 2005, Mitsuba 3's Hierarchical2D); keeps stratified variates stratified;
//   Compensated  the Adaptive table of max(0, L − L̄) × ΔΩ with L̄ = ∫L dω / 4π the mean luminance
//                (pbrt-v4's MIS compensation, Karlík et al. 2019): directions dimmer than the mean
//                get pdf 0 and are left to BSDF sampling under MIS. A map with nothing above its
//                mean (a constant one) falls back to the uncompensated table
//                (compensationFellBack()).
// pdf(ω) of Compensated may be 0 where eval(ω) is not: it is meant for MIS only.
//
// A black map emits nothing: no table is built, sample() returns pdf 0 (no sample, the caller
// skips it; an MIS weight against this light is then 1 for the other technique), pdf() and
// eval() return 0.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/pixel_alias.h"
#include "acdf/envmap/rotation.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/hierarchical_warp_2d.h"
#include "acdf/sampling/simplify.h"
#include "acdf/sampling/sphere.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

enum class EnvironmentSampling { Uniform, Alias, Adaptive, Compensated, Hierarchical };

// "uniform", "alias", "adaptive", "compensated", "hierarchical"; parse throws std::invalid_argument.
std::string_view toString(EnvironmentSampling strategy);
EnvironmentSampling parseEnvironmentSampling(std::string_view name);

struct EnvironmentLightOptions {
  EnvironmentSampling strategy = EnvironmentSampling::Adaptive;
  SimplifyOptions simplify{};  // Adaptive and Compensated
  Rotation worldFromMap{};     // the map frame's directions in the world (default: the same)
  float scale = 1.0f;          // radiance multiplier; finite and > 0
};

struct EnvironmentSample {
  Vec3d direction;  // world frame, unit length
  Rgb radiance;     // scale × the pixel's radiance
  double pdf = 0;   // per steradian; 0 only for a light that emits nothing
};

class EnvironmentLight {
 public:
  // Throws std::invalid_argument for a bad scale or simplify options (or what the table's
  // constructor throws).
  EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options = {});

  // Table caching (docs/table-cache.md). Only the cascades (Uniform, Adaptive, Compensated) are
  // worth saving; the other tables and everything else the constructor computes (the tabulated
  // function, per-row pdf scales) take O(pixels) and are rebuilt.
  //
  // The light from a table that serializeTable() saved for the same map and options: the same
  // samples and pdfs bit for bit. Throws SerializationError if `savedTable` is not a valid table
  // of this map's size and these options (the cache key guards the rest: same pixels, strategy).
  EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options,
                   std::span<const std::byte> savedTable);
  // The cascade, serialized; empty for the other strategies and for a light that emits nothing.
  std::vector<std::byte> serializeTable() const;
  // The table's key: the map's size and pixels, the strategy, the simplify options and the
  // format versions. Rotation and scale do not change the table and are not part of it.
  static CacheKey tableKey(const EnvironmentMap& map, const EnvironmentLightOptions& options);
  // The light with its table from `cache` if it holds a valid one, else built (and stored if
  // the strategy's table is worth caching). `what` names the light in warnings.
  static Cached<EnvironmentLight> cached(TableCache& cache, std::shared_ptr<const EnvironmentMap> map,
                                         EnvironmentLightOptions options, std::string_view what);

  // u0, u1 in [0, 1) (clamped into it).
  EnvironmentSample sample(float u0, float u1) const;
  // Density per steradian of sample() at the world direction w (non-zero).
  double pdf(const Vec3d& w) const;
  // Radiance arriving from the world direction w (non-zero): nearest pixel, times the scale.
  Rgb eval(const Vec3d& w) const;

  // True for a black map (and one whose every pixel underflows in the table): nothing to sample.
  bool emitsNothing() const { return pdfScale_.empty(); }
  bool compensationFellBack() const { return compensationFellBack_; }
  const EnvironmentMap& map() const { return *map_; }
  const EnvironmentLightOptions& options() const { return options_; }

  // Bytes of the sampling table (0 without one).
  std::size_t tableBytes() const;
  // Probability the table gives each pixel, row-major (empty without a table). Exact.
  std::vector<double> pixelProbabilities() const;
  // The tabulated function (per pixel, row-major), whose normalisation the table approximates.
  const std::vector<float>& tabulated() const { return tabulated_; }

 private:
  // The constructors' shared work; savedTable: null to build the cascade, else to read it.
  EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options,
                   const std::span<const std::byte>* savedTable);
  // Density per steradian of pixel p's directions.
  double pixelPdf(PixelIndex p) const;
  // Density per steradian of a pixel of `row` chosen with `probability` (Alias, Hierarchical).
  double probabilityPdf(double probability, uint32_t row) const { return probability * pixels_ * pdfScale_[row]; }

  std::shared_ptr<const EnvironmentMap> map_;
  EnvironmentLightOptions options_;
  std::vector<float> tabulated_;
  bool compensationFellBack_ = false;
  std::optional<Cascade> cascade_;          // Uniform, Adaptive, Compensated
  std::optional<PixelAlias> alias_;         // Alias
  std::optional<HierarchicalWarp2D> warp_;  // Hierarchical
  std::vector<double> pdfScale_;            // per row: 1 / (W H ΔΩ_row), table density → per steradian
  double pixels_ = 0;                       // W H
};

}  // namespace acdf

#pragma once
// Importance sampling of any BRDF model (brdf_model.h: measured or analytic) from a tabulated CDF
// of the half vector (Lawrence, Rusinkiewicz & Ramamoorthi 2005, §5): for each cell of outgoing
// directions ωo, a 2D distribution over the half vector ωh ∝ f(ωo, ωi)·cosθi, sampled, then
// reflected: ωi = 2(ωo·ωh)ωh − ωo.
//
// Parameterisation. θh on MERL's square-root scale, s = √(θh / (π/2)) in [0, 1), so the cells
// crowd near the specular peak; φh linear. Each cell holds the mass of the target density of ωh,
//   ∫cell f·cosθi · 4(ωo·ωh) dωh,   (dωh = sinθh dθh dφh, dθh = π s ds)
// since p(ωi) = p(ωh) / (4 |ωo·ωh|) (the reflection, half_vector.h): sampling ωh ∝ it samples
// ωi ∝ f·cosθi.
// The cascade chooses a cell; inside it, ωh is placed uniformly in solid angle (the position in s
// is carried over to the same fraction of 1 − cosθh), so
//   p(ωh) = P(cell) / Ω(cell) = p(s, φh) · Δs / Δ(1 − cosθh)
// is bounded everywhere. (Uniform in s within a cell, it would grow as 1/(s sinθh) ~ s⁻³ towards
// the pole: an integrable spike no quadrature checks well and a poor fit to f·cosθi.)
//
// Layouts.
//   Full4D     (θo, φo | s, φh): the paper's table, default 32 × 16 × 256 × 32 cells.
//   Isotropic  (θo | s, Δφ) with Δφ = φh − φo: an isotropic BRDF depends on ωo only through θo,
//              so one slice per θo serves every φo (the sample is rotated by φo): 1/16 of the
//              cells. With `mirror`, f(Δφ) = f(−Δφ) (reflection across the plane of incidence)
//              halves it again: |Δφ| in [0, π) is tabulated and its sign drawn at sample time.
//              Isotropic models only (BrdfModel::isotropic()).
// Each slice (cell of the conditioning axes) is used for every ωo in it (nearest cell).
//
// Cell values are averages over `supersampling`^dims stratified points of the cell (outgoing
// and half-vector axes alike), never a single centre point, in double, of the luminance of f.
// An isotropic model is evaluated once per (θo, θh, Δφ) point of a lattice that every φo shares
// (BrdfModel::evalHalfDiff), any other model at every point (BrdfModel::luminance).
//
// Defensive mixture: with probability `cosineWeight` the direction is drawn cosine-weighted
// instead; pdf = (1 − w)·p_table + w·cosθi/π. The table is zero where its cells saw no
// reflectance (or the simplification left too little), while f·cosθi may still be > 0 there for
// a particular ωo of the slice; the mixture keeps pdf > 0 wherever cosθi > 0, so estimators using
// this sampler alone stay unbiased.
//
// Tables are tabulated and built in parallel (oneTBB); the result does not depend on the thread
// count.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/outgoing_cells.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/simplify.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

struct TabulatedBrdfOptions {
  enum class Layout : uint8_t { Full4D, Isotropic };

  Layout layout = Layout::Full4D;
  DimensionMethod method = DimensionMethod::Adaptive;  // for both half-vector axes
  // Adaptive only. Defaults chosen on the paper's three materials (their figures in
  // docs/engine.md): the χ² metric puts points where the variance is; MassScaled spends them where
  // the mass is; the weight bound costs storage here without lowering the variance (the cosine
  // mixture already bounds the weights where the table is coarse); ε = 5e-5 keeps nickel's
  // variance close to the uniform table's at a small fraction of its storage.
  SimplifyOptions simplify = {.metric = ErrorMetric::ChiSquare, .epsilon = 5e-5, .weightBound = 0.0};
  ConditionalTolerance tolerance = ConditionalTolerance::MassScaled;
  // Cells of θo in [0, π/2), φo in [0, 2π) (Full4D only), s in [0, 1) and φh in [0, 2π). An
  // isotropic table has phiHalfCells cells of Δφ over [0, 2π), i.e. phiHalfCells / 2 over
  // [0, π) when mirrored (phiHalfCells must then be even).
  uint32_t thetaOutCells = 32, phiOutCells = 16, thetaHalfCells = 256, phiHalfCells = 32;
  bool mirror = true;          // Isotropic only
  uint32_t supersampling = 2;  // stratified points per cell per axis, >= 1
  // Defensive mixture weight in [0, 1]. Every sample pays for it (E[Y²] grows by 1/(1 − w)), so
  // it is small: 0.05 gave the lowest variances of the adaptive table over the three materials
  // among 0.02, 0.05, 0.1 and 0.25, and keeps pdf > 0 wherever cosθi > 0.
  double cosineWeight = 0.05;
  // Slice grouping (CascadeOptions::sliceGroupingTolerance): neighbouring outgoing slices share
  // one distribution where that raises a slice's χ²-divergence by at most this; 0 keeps one per
  // slice. Adaptive tables only gain from it (a uniform slice costs the same either way).
  double sliceGrouping = 0.0;

  // The table's name, e.g. "adaptive-4d", "uniform-iso".
  std::string name() const;
};

// The one spelling of each layout, used by the command line, the scene format, the JSON outputs
// and the table cache keys: "4d", "isotropic". parse throws std::invalid_argument for any other
// name.
std::string_view toString(TabulatedBrdfOptions::Layout layout);
TabulatedBrdfOptions::Layout parseTableLayout(std::string_view name);

// The one check of these options, for the sampler, the command line and the scene loader. Throws
// OptionError (option names as in the scene format's "table": "theta_out", "phi_half", ...): an
// axis without cells, an odd phiHalfCells for a mirrored isotropic table, supersampling 0, a
// cosine weight outside [0, 1], bad simplify options. Whether the model suits the layout is the
// sampler's check.
void validate(const TabulatedBrdfOptions& options);

class TabulatedBrdfSampler final : public BrdfSampler {
 public:
  // Throws std::invalid_argument for a null model, the isotropic layout for a model that is not
  // isotropic, and OptionError for options validate() rejects.
  explicit TabulatedBrdfSampler(std::shared_ptr<const BrdfModel> model, const TabulatedBrdfOptions& options = {});

  // Table caching (docs/table-cache.md): the constructor above is buildCascade() plus the one
  // below, so a renderer can keep the expensive part in a TableCache:
  //   Cached<Cascade> t = cache.getOrBuild(tableKey(*model, o), "BRDF table nickel",
  //                                        [&] { return buildCascade(*model, o); });
  //   TabulatedBrdfSampler sampler(model, o, std::move(t.value));
  // `table` must come from buildCascade() with the same model and options; a grid or cascade
  // options that differ from those `options` give throw SerializationError (a corrupt or
  // colliding cache entry), bad options std::invalid_argument. tabulationMs() and buildMs() are 0.
  TabulatedBrdfSampler(std::shared_ptr<const BrdfModel> model, const TabulatedBrdfOptions& options, Cascade table);
  static Cascade buildCascade(const BrdfModel& model, const TabulatedBrdfOptions& options);
  // The table's key: the model's (BrdfModel::addToKey: every MERL value and the interpolation,
  // say), every option that shapes the table (not cosineWeight, which only mixes at sample time)
  // and the tabulation and format versions.
  static CacheKey tableKey(const BrdfModel& model, const TabulatedBrdfOptions& options);

  // The vertex knows ωo's slice of the table.
  BrdfVertex vertex(const Vec3d& wo) const override;
  double pdf(const Vec3d& wo, const Vec3d& wi) const override { return pdfAt(vertex(wo), wi); }
  // The table's density of the half vector ωh (upper hemisphere) given ωo, per steradian,
  // without the defensive mixture.
  double halfVectorPdf(const Vec3d& wo, const Vec3d& wh) const { return halfVectorPdfAt(vertex(wo), wh); }
  // The defensive mixture's cosine weight, and the table's density on its own half-vector cells.
  HalfVectorDensity halfVectorDensity(const Vec3d& wo) const override;

  std::size_t bytes() const override { return table_.bytes(); }
  std::string name() const override { return options_.name(); }

  const TabulatedBrdfOptions& options() const { return options_; }
  const Cascade& table() const { return table_; }
  // Wall-clock milliseconds spent evaluating the BRDF into the grid, and building the CDFs.
  double tabulationMs() const { return tabulationMs_; }
  double buildMs() const { return buildMs_; }

 protected:
  SampledDirection sampleDirection(const Vec3d& wo, float u0, float u1) const override {
    return sampleDirectionAt(vertex(wo), u0, u1);
  }
  SampledDirection sampleDirectionAt(const BrdfVertex& v, float u0, float u1) const override;
  double pdfAt(const BrdfVertex& v, const Vec3d& wi) const override;

 private:
  double halfVectorPdfAt(const BrdfVertex& v, const Vec3d& wh) const;
  // The cells of the table's outgoing axes: θo, and φo for a Full4D table.
  static OutgoingCells outgoingCellsOf(const Cascade& table);
  // The cells of the table's half-vector axes: s, and φh (Full4D) or Δφ.
  static HalfVectorCells halfVectorCellsOf(const Cascade& table, const TabulatedBrdfOptions& options);
  // The table's density in (s, φ) on s-cell `cell`, per steradian of the half vector.
  double perSteradian(double density, uint32_t cell) const;

  TabulatedBrdfOptions options_;
  double tabulationMs_ = 0, buildMs_ = 0;
  Cascade table_;
  std::vector<double> capAreas_;     // 1 − cosθh at the s-cell boundaries
  OutgoingCells outgoingCells_;      // the conditioning cells of ωo (θo, and φo for Full4D)
  HalfVectorCells halfVectorCells_;  // the sampled cells of ωh (s, and φh or Δφ)
};

}  // namespace acdf

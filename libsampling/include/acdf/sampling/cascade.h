#pragma once
// The cascaded N-dimensional CDF (Lawrence et al. 2005): a distribution over a box, given as a
// dense row-major grid of non-negative values (axis 0 varies slowest).
//
// The first `conditioningDims` axes are given at sample time and only looked up (nearest cell):
// each of their cells ("slice") owns an independent distribution over the remaining, sampled axes
// — the BRDF case, where ωo is given and ωh sampled. Over the sampled axes the cascade is
//   p(x0) · p(x1 | interval of x0) · p(x2 | intervals of x0, x1) · ...
// Each factor is a 1D CDF, uniform (every grid cell) or adaptive (simplified, see simplify.h), per
// dimension. The conditional below an adaptive interval is, by default, the exact conditional
// given that interval (masses summed over it, so the cascade's cell probabilities are exact
// wherever no simplification happened); ConditionalRule::AverageOfNormalized instead averages
// the normalised conditionals of the interval's cells (the paper's eq. 10).
//
// Storage: per sampled dimension, the 1D CDFs of that level are pooled: float CDF values, and for
// adaptive levels 8/16/32-bit vertex indices plus one 32-bit offset per 1D CDF. Only interior
// points are stored: every CDF starts at 0 on vertex 0 and ends at 1 on the last vertex, so the
// end points are implicit (uniform and adaptive levels alike). The children of a level's CDF are
// contiguous in the next level, so no child pointers are stored.
// Precision: all sums in double; stored CDFs in float; pdf = product of the per-level densities
// computed in double and clamped into the positive float range.
// Zero mass: a slice (or sub-block) with no mass gets a uniform distribution of two points;
// isUniformFallback(slice) reports it.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/sample.h"
#include "acdf/sampling/simplify.h"
#include "acdf/sampling/vertex_indices.h"

namespace acdf {

enum class DimensionMethod : uint8_t { Uniform, Adaptive };
enum class ConditionalRule : uint8_t { ExactMass, AverageOfNormalized };
// The simplification tolerance of each conditional 1D CDF. Constant: ε for every CDF (the paper).
// MassScaled: a CDF whose block carries a share P of the slice's mass (the product of its parent
// intervals' probabilities) gets a tolerance scaled so that every conditional adds the same to
// the joint χ²-divergence, so storage goes where the mass is. The conditional's divergence
// reaches the joint one scaled by P. With the CDF-distance metrics it grows as ε², so they get
// ε/√P (at most 1/2); ErrorMetric::ChiSquare measures divergence itself and gets ε/P (at most
// cells − 1, which keeps only the end points). The first level (P = 1) keeps ε.
enum class ConditionalTolerance : uint8_t { Constant, MassScaled };

// "uniform", "adaptive"; "exact-mass", "average-of-normalized"; "constant", "mass-scaled". The
// parse functions throw std::invalid_argument naming the spellings.
std::string_view toString(DimensionMethod method);
std::string_view toString(ConditionalRule rule);
std::string_view toString(ConditionalTolerance tolerance);
DimensionMethod parseDimensionMethod(std::string_view name);
ConditionalRule parseConditionalRule(std::string_view name);
ConditionalTolerance parseConditionalTolerance(std::string_view name);

struct CascadeOptions {
  uint32_t conditioningDims = 0;
  // One entry per sampled dimension; empty means every sampled dimension is adaptive.
  std::vector<DimensionMethod> methods;
  SimplifyOptions simplify;
  ConditionalRule conditional = ConditionalRule::ExactMass;
  ConditionalTolerance tolerance = ConditionalTolerance::Constant;
  // Slice grouping (the paper's future work): when > 0, a conditioning slice reuses the
  // distribution of the current group (run of neighbouring slices in row-major order, represented
  // by its first slice) if that leaves none of the slice's mass unreachable and raises its
  // χ²-divergence (see quality.h) by at most this tolerance over the slice's own distribution.
  // Slices without mass only group with each other (they keep their uniform distribution).
  // 0 keeps one distribution per slice.
  double sliceGroupingTolerance = 0.0;

  bool operator==(const CascadeOptions&) const = default;
};

// The one check of these options for a grid of `axes` axes, for the constructor and the table
// cache reader alike. Throws OptionError: conditioningDims >= axes, a methods count other than 0
// or the sampled axes', bad simplify options (validate above), a slice grouping tolerance that is
// negative or not finite.
void validate(const CascadeOptions& options, std::size_t axes);

class ByteReader;
class ByteWriter;

// A sample of a Cascade given by the grid cells it lies in: for callers that map each cell to
// their own domain (a pixel, a cap of half vectors) and must not find the cells again from float
// coordinates, where a point on a cell boundary may land in the neighbour.
struct CellSample {
  std::array<uint32_t, kMaxDims> cells{};    // per sampled axis: the cell of sample()'s point
  std::array<double, kMaxDims> fractions{};  // where in its cell, in [0, 1): 0 at the low edge
  std::array<float, kMaxDims> x{};           // sample()'s coordinates, in those cells
  float pdf = 0;                             // sample()'s density: that of the cells
  uint8_t dims = 0;
};

class Cascade {
 public:
  // values.size() must equal the product of the axes' cell counts; 1 <= axes.size() <= kMaxDims;
  // conditioningDims < axes.size(). Throws std::invalid_argument otherwise, or on a negative, NaN
  // or Inf value (naming the first bad index and its cell). Built in parallel (oneTBB); the result
  // does not depend on the number of threads.
  Cascade(std::span<const float> values, std::vector<GridAxis> axes, CascadeOptions options = {});

  // condition: conditioningDims() coordinates; u: sampledDims() variates in [0,1).
  SampleND sample(std::span<const float> condition, std::span<const float> u) const;
  // Density of the sampled coordinates x given the condition; 0 outside the domain.
  float pdf(std::span<const float> condition, std::span<const float> x) const;
  // The variates that sample() maps to x (up to float rounding); u gets sampledDims() entries.
  void invert(std::span<const float> condition, std::span<const float> x, std::span<float> u) const;

  // Shorthands without conditioning dimensions.
  SampleND sample(std::span<const float> u) const { return sample({}, u); }
  float pdf(std::span<const float> x) const { return pdf({}, x); }

  std::size_t dims() const { return axes_.size(); }
  std::size_t conditioningDims() const { return conditioningDims_; }
  std::size_t sampledDims() const { return axes_.size() - conditioningDims_; }
  const std::vector<GridAxis>& axes() const { return axes_; }
  const CascadeOptions& options() const { return options_; }

  std::size_t slices() const { return sliceIntegral_.size(); }
  // Distributions stored: slices() unless slice grouping merged some.
  std::size_t distinctSlices() const;
  // The distribution `slice` samples: its first-level CDF's index in breakpoints(conditioningDims())
  // (the slice itself unless slice grouping gave it an earlier slice's). Throws std::out_of_range
  // for slice >= slices().
  std::size_t distributionOf(std::size_t slice) const;
  std::size_t sliceOf(std::span<const float> condition) const;
  // sample() and pdf() in a slice the caller found itself (sliceOf's row-major index of the
  // conditioning cells), for callers that know their condition's cells without coordinates.
  // Throws std::out_of_range for slice >= slices().
  SampleND sampleInSlice(std::size_t slice, std::span<const float> u) const;
  float pdfInSlice(std::size_t slice, std::span<const float> x) const;
  // sampleInSlice's point with its cells and the fractions within them: pdfOfCellsInSlice(slice,
  // cells) is its pdf, bit for bit. A fraction may be 0 (a point on a cell's low edge); a caller
  // whose mapping rounds keeps its point a margin inside the cell.
  CellSample sampleCellsInSlice(std::size_t slice, std::span<const float> u) const;
  CellSample sampleCells(std::span<const float> u) const { return sampleCellsInSlice(0, u); }
  // pdfInSlice at any point of the sampled grid cell `cells` (one cell per sampled axis): the
  // density is constant on grid cells, so a caller that knows its point's cells needs no
  // coordinates. 0 for a cell outside its axis, as pdfInSlice outside the domain.
  float pdfOfCellsInSlice(std::size_t slice, std::span<const uint32_t> cells) const;
  // ∫ f over the sampled axes of a slice (double sum); 0 means the slice samples uniformly.
  double integral(std::size_t slice) const { return sliceIntegral_[slice]; }
  bool isUniformFallback(std::size_t slice) const { return sliceIntegral_[slice] == 0.0; }

  std::size_t bytes() const;
  // Per axis: the average number of intervals of its 1D CDFs (the paper's "average resolution");
  // conditioning axes report their cell count.
  std::vector<double> averageIntervals() const;
  // Kept points (interval ends, the implicit end points included) summed over all 1D CDFs of
  // each sampled axis.
  std::vector<std::size_t> pointsPerDimension() const;
  // The grid vertices each 1D CDF of sampled axis `axis` keeps (0 and the cell count included),
  // one list per CDF in storage order: the first level holds one CDF per distinct slice; CDF j of
  // the next level is the conditional below interval j of this one, intervals counted across the
  // level's CDFs in order. What a figure of the adaptive intervals draws. Throws
  // std::invalid_argument for a conditioning or missing axis.
  std::vector<std::vector<uint32_t>> breakpoints(std::size_t axis) const;
  // The CDF's value at each of breakpoints(axis)' vertices, per CDF in the same order (0 first, 1
  // last): with breakpoints(), the whole table, for a caller that samples it in its own arithmetic
  // (the Mitsuba plugin's drjit arrays). Throws as breakpoints() does.
  std::vector<std::vector<float>> breakpointValues(std::size_t axis) const;

  // Probability the distribution of `slice` gives each cell of the sampled grid, row-major.
  // Exact (the pdf is constant on grid cells); used for quality metrics and chi-square tests.
  std::vector<double> cellProbabilities(std::size_t slice) const;

  // Binary serialization of the built table (cascade_io.cpp): what write() stores, read() gives
  // back exactly, so the copy's sample/pdf/invert are bit-identical to the original's. read()
  // validates everything (shapes, options, offsets, vertex indices, monotone finite CDFs from 0
  // to 1, slice integrals), so whatever it accepts samples inside the domain like a built table;
  // anything else throws SerializationError (byte_io.h). kSerialVersion changes with the layout.
  static constexpr uint32_t kSerialVersion = 2;  // 2: interior CDF points only
  void write(ByteWriter& out) const;
  static Cascade read(ByteReader& in);
  std::vector<std::byte> serialize() const;
  // All of `bytes` must be one serialized cascade.
  static Cascade deserialize(std::span<const std::byte> bytes);

  struct Level {
    DimensionMethod method;
    std::vector<float> cdf;        // pooled interior CDF values of all 1D CDFs of this level
    VertexIndices vertices;        // adaptive only: grid vertex of each pooled value
    std::vector<uint32_t> starts;  // adaptive only: first pooled value of each 1D CDF, plus end
  };

 private:
  Cascade() = default;  // for read()
  std::vector<std::size_t> groupSlices(std::span<const float> values, std::size_t sliceSize);
  std::vector<double> cellProbabilitiesOfRoot(std::size_t root) const;
  std::size_t rootOf(std::size_t slice) const { return sliceRoot_.empty() ? slice : sliceRoot_[slice]; }
  void requireSlice(std::size_t slice) const;
  // pdfOfCellsInSlice without its checks.
  float pdfOfCells(std::size_t slice, std::span<const uint32_t> cells) const;
  std::vector<std::size_t> cdfsPerLevel() const;

  std::vector<GridAxis> axes_;
  std::size_t conditioningDims_ = 0;
  CascadeOptions options_;
  std::vector<double> sliceIntegral_;
  std::vector<uint32_t> sliceRoot_;  // slice -> its distribution's root; empty: the identity
  std::vector<Level> levels_;        // one per sampled axis
};

}  // namespace acdf

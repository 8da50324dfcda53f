#include "acdf/sampling/cascade.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/grid_check.h"
#include "acdf/sampling/quality.h"
#include "breakpoint_cdf.h"

namespace acdf {

namespace {

// One 1D CDF of a level, and where its children start in the next level.
struct NodeView {
  detail::BreakpointCdf cdf;
  std::size_t childBase;  // index in the next level of the child of interval 0
};

// The pooled 1D CDFs of one level, interior points only (see BreakpointCdf). A uniform level
// (no starts) holds cells − 1 values per CDF, one per inner grid vertex; an adaptive level
// locates the interior points of CDF k at [starts[k], starts[k+1]).
struct LevelView {
  const float* cdf;
  const VertexIndices* vertices;
  const uint32_t* starts;
  uint32_t cells;

  NodeView node(std::size_t index) const {
    if (!starts) return {{cdf + index * (cells - 1), cells + 1u, cells}, index * cells};
    const std::size_t first = starts[index], end = starts[index + 1];
    // Every earlier 1D CDF of the level has (interior points + 1) children before ours.
    return {{cdf + first, end - first + 2, cells, vertices, first}, first + index};
  }
};

// Probability of every cell of the grid below `root` of levels[0], row-major. Each interval
// spreads its mass evenly over its cells; a cell's probability is the product of its shares.
void fillCellProbabilities(std::span<const LevelView> levels, std::size_t root, std::span<double> out) {
  const std::size_t dims = levels.size();
  std::array<std::size_t, kMaxDims> stride{};
  stride[dims - 1] = 1;
  for (std::size_t d = dims - 1; d-- > 0;) stride[d] = stride[d + 1] * levels[d + 1].cells;
  std::fill(out.begin(), out.end(), 0.0);

  std::array<uint32_t, kMaxDims> first{}, end{};
  auto fillBox = [&](double perCell) {
    std::array<uint32_t, kMaxDims> i = first;
    while (true) {
      std::size_t offset = 0;
      for (std::size_t d = 0; d < dims; ++d) offset += i[d] * stride[d];
      out[offset] = perCell;
      std::size_t d = dims;
      while (d-- > 0) {
        if (++i[d] < end[d]) break;
        i[d] = first[d];
      }
      if (d == static_cast<std::size_t>(-1)) return;
    }
  };
  auto visit = [&](auto& self, std::size_t level, std::size_t index, double perCell) -> void {
    const NodeView n = levels[level].node(index);
    for (std::size_t j = 0; j + 1 < n.cdf.count; ++j) {
      const double mass = n.cdf.mass(j);
      if (mass == 0.0) continue;
      first[level] = n.cdf.vertex(j);
      end[level] = n.cdf.vertex(j + 1);
      const double share = perCell * mass / (end[level] - first[level]);
      if (level + 1 == dims)
        fillBox(share);
      else
        self(self, level + 1, n.childBase + j, share);
    }
  };
  visit(visit, 0, root, 1.0);
}

LevelView viewOf(const Cascade::Level& level, uint32_t cells) {
  if (level.method == DimensionMethod::Uniform) return {level.cdf.data(), nullptr, nullptr, cells};
  return {level.cdf.data(), &level.vertices, level.starts.data(), cells};
}

// 1D CDFs of one level as produced by a build, before offsets are fixed.
struct LevelBuffer {
  DimensionMethod method;
  std::vector<float> cdf;
  VertexIndices vertices;
  std::vector<uint32_t> counts;  // interior points of each 1D CDF, in level order
};
using Subtree = std::vector<LevelBuffer>;  // one buffer per sampled level

void append(Subtree& to, const Subtree& from) {
  for (std::size_t d = 0; d < to.size(); ++d) {
    to[d].cdf.insert(to[d].cdf.end(), from[d].cdf.begin(), from[d].cdf.end());
    to[d].vertices.append(from[d].vertices);
    to[d].counts.insert(to[d].counts.end(), from[d].counts.begin(), from[d].counts.end());
  }
}

std::vector<uint32_t> startsOf(const std::vector<uint32_t>& counts) {
  std::vector<uint32_t> starts;
  starts.reserve(counts.size() + 1);
  uint32_t start = 0;
  for (uint32_t count : counts) {
    starts.push_back(start);
    start += count;
  }
  starts.push_back(start);
  return starts;
}

// Float CDFs resolve probabilities to about 2^-24; the joint weight bound forgives differences
// below this, or it would split intervals over rounding it cannot remove.
constexpr double kProbabilityResolution = 0x1p-22;

// Builds the 1D CDFs of a block of the grid and, depth first, of everything below it. Appending
// depth first keeps each level in parent order, which is what makes child offsets implicit.
class Builder {
 public:
  Builder(std::vector<uint32_t> sizes, const CascadeOptions& options)
      : sizes_(std::move(sizes)), options_(options), rowSize_(sizes_.size(), 1) {
    for (std::size_t d = sizes_.size() - 1; d-- > 0;) rowSize_[d] = rowSize_[d + 1] * sizes_[d + 1];
  }

  Subtree emptySubtree() const {
    Subtree t(sizes_.size());
    for (std::size_t d = 0; d < sizes_.size(); ++d) {
      t[d].method = method(d);
      t[d].vertices = VertexIndices(sizes_[d] - 1);  // the largest interior vertex
    }
    return t;
  }

  std::size_t blockSize() const { return rowSize_[0] * sizes_[0]; }

  // block: the joint masses of the remaining axes (level..), row-major; share: the probability
  // the block carries in its slice. Appends the block's 1D CDFs to `out` and returns Σ block.
  template <class T>
  double build(std::span<const T> block, std::size_t level, Subtree& out, bool parallelChildren,
               double share = 1.0) const {
    const uint32_t m = sizes_[level];
    const std::size_t row = rowSize_[level];
    std::vector<double> masses(m, 0.0);
    for (uint32_t j = 0; j < m; ++j) {
      double sum = 0.0;
      for (std::size_t r = 0; r < row; ++r) sum += static_cast<double>(block[j * row + r]);
      masses[j] = sum;
    }
    std::vector<float> cdf;
    cdf.reserve(m + 1);
    const double total = detail::appendCdf<double>(masses, cdf);

    std::vector<uint32_t> kept;  // interval ends of this 1D CDF
    if (method(level) == DimensionMethod::Uniform) {
      kept.resize(m + 1);
      for (uint32_t k = 0; k <= m; ++k) kept[k] = k;
    } else {
      kept = simplifyCdf(cdf, simplifyOptions(share, m));
    }

    std::vector<Child> children;
    if (level + 1 < sizes_.size()) {
      children = buildChildren(block, masses, total, share, cdf, level, kept, parallelChildren);
      kept.clear();
      for (const Child& c : children) kept.push_back(c.a);
      kept.push_back(m);
    }

    LevelBuffer& buffer = out[level];
    for (std::size_t j = 1; j + 1 < kept.size(); ++j) {
      buffer.cdf.push_back(cdf[kept[j]]);
      if (buffer.method == DimensionMethod::Adaptive) buffer.vertices.push_back(kept[j]);
    }
    buffer.counts.push_back(static_cast<uint32_t>(kept.size() - 2));
    for (const Child& c : children) append(out, c.tree);
    return total;
  }

 private:
  struct Child {
    uint32_t a, b;  // the interval [a, b) of the parent's axis
    Subtree tree;
    bool built = false, checked = false;
  };

  // cells: of the axis this 1D CDF samples. See ConditionalTolerance for the scaling.
  SimplifyOptions simplifyOptions(double share, uint32_t cells) const {
    SimplifyOptions o = options_.simplify;
    if (options_.tolerance != ConditionalTolerance::MassScaled || share >= 1.0) return o;
    // A χ² contribution C of the conditional adds share·C to the joint divergence, a CDF error e
    // about share·e². The cap keeps ε finite for tiny shares: a 1D χ² contribution is at most
    // cells − 1, so that tolerance keeps only the end points.
    const bool chiSquare = o.metric == ErrorMetric::ChiSquare;
    const double scale = chiSquare ? share : std::sqrt(share);
    const double loosest = chiSquare ? cells - 1.0 : 0.5;
    o.epsilon = scale > 0.0 ? std::min(loosest, o.epsilon / scale) : loosest;
    return o;
  }

  DimensionMethod method(std::size_t level) const {
    return options_.methods.empty() ? DimensionMethod::Adaptive : options_.methods[level];
  }

  // Builds the children of the intervals `kept`. With a weight bound on an adaptive level, an
  // interval is split while a cell of its rows would get more than ρ times the probability the
  // cascade gives it: (row mass share) × (the row's conditional / the child's cell probability).
  template <class T>
  std::vector<Child> buildChildren(std::span<const T> block, const std::vector<double>& masses, double total,
                                   double share, const std::vector<float>& cdf, std::size_t level,
                                   const std::vector<uint32_t>& kept, bool parallel) const {
    std::vector<Child> children;
    for (std::size_t i = 0; i + 1 < kept.size(); ++i) children.push_back({kept[i], kept[i + 1], emptySubtree()});
    const bool bounded = method(level) == DimensionMethod::Adaptive && options_.simplify.weightBound >= 1.0;
    while (true) {
      std::vector<std::size_t> pending;
      for (std::size_t i = 0; i < children.size(); ++i) {
        if (!children[i].built) pending.push_back(i);
      }
      auto buildOne = [&](std::size_t k) {
        Child& c = children[pending[k]];
        buildChild(block, masses, total, share, level, c);
        c.built = true;
      };
      if (parallel && pending.size() > 1)
        tbb::parallel_for(std::size_t{0}, pending.size(), buildOne);
      else
        for (std::size_t k = 0; k < pending.size(); ++k) buildOne(k);
      if (!bounded) return children;

      std::vector<Child> next;
      bool split = false;
      for (Child& c : children) {
        const bool violates = !c.checked && c.b - c.a >= 2 && exceedsJointBound(block, masses, level, c);
        c.checked = true;
        if (!violates) {
          next.push_back(std::move(c));
          continue;
        }
        const uint32_t v = worstVertex(cdf, c.a, c.b, options_.simplify.metric);
        next.push_back({c.a, v, emptySubtree()});
        next.push_back({v, c.b, emptySubtree()});
        split = true;
      }
      children = std::move(next);
      if (!split) return children;
    }
  }

  template <class T>
  void buildChild(std::span<const T> block, const std::vector<double>& masses, double total, double share,
                  std::size_t level, Child& c) const {
    const std::size_t row = rowSize_[level];
    double intervalMass = 0.0;
    for (uint32_t j = c.a; j < c.b; ++j) intervalMass += masses[j];
    const double childShare = total > 0.0 ? share * intervalMass / total : 0.0;
    if (c.b - c.a == 1) {
      build<T>(block.subspan(c.a * row, row), level + 1, c.tree, false, childShare);
    } else {
      const std::vector<double> merged = mergeRows(block, masses, c.a, c.b, row);
      build<double>(merged, level + 1, c.tree, false, childShare);
    }
  }

  template <class T>
  bool exceedsJointBound(std::span<const T> block, const std::vector<double>& masses, std::size_t level,
                         const Child& c) const {
    double intervalMass = 0.0;
    for (uint32_t j = c.a; j < c.b; ++j) intervalMass += masses[j];
    if (intervalMass == 0.0) return false;
    const std::size_t row = rowSize_[level];
    std::vector<std::vector<uint32_t>> starts(sizes_.size());
    std::vector<LevelView> views;
    for (std::size_t d = level + 1; d < sizes_.size(); ++d) {
      const LevelBuffer& b = c.tree[d];
      if (b.method == DimensionMethod::Uniform) {
        views.push_back({b.cdf.data(), nullptr, nullptr, sizes_[d]});
      } else {
        starts[d] = startsOf(b.counts);
        views.push_back({b.cdf.data(), &b.vertices, starts[d].data(), sizes_[d]});
      }
    }
    std::vector<double> q(row);
    fillCellProbabilities(views, 0, q);
    // p(cell) / q(cell) = block[j][r] · (b − a) / (intervalMass · q[r]) must stay <= ρ.
    const double scale = static_cast<double>(c.b - c.a) / (options_.simplify.weightBound * intervalMass);
    for (uint32_t j = c.a; j < c.b; ++j) {
      const T* source = block.data() + j * row;
      for (std::size_t r = 0; r < row; ++r) {
        if (static_cast<double>(source[r]) * scale > q[r] + kProbabilityResolution) return true;
      }
    }
    return false;
  }

  // The joint of the next axes given the interval [a, b) of this one.
  template <class T>
  std::vector<double> mergeRows(std::span<const T> block, const std::vector<double>& masses, uint32_t a, uint32_t b,
                                std::size_t row) const {
    std::vector<double> merged(row, 0.0);
    for (uint32_t j = a; j < b; ++j) {
      // Exact conditional: sum the rows. Eq. 10: average the normalised rows (the common 1/count
      // factor is dropped, every 1D CDF normalises its own masses).
      double weight = 1.0;
      if (options_.conditional == ConditionalRule::AverageOfNormalized) {
        if (masses[j] == 0.0) continue;
        weight = 1.0 / masses[j];
      }
      const T* source = block.data() + j * row;
      for (std::size_t r = 0; r < row; ++r) merged[r] += static_cast<double>(source[r]) * weight;
    }
    return merged;
  }

  std::vector<uint32_t> sizes_;
  const CascadeOptions& options_;
  std::vector<std::size_t> rowSize_;  // cells of one row at each level (product of later sizes)
};

}  // namespace

namespace {
constexpr EnumName<DimensionMethod> kDimensionMethodNames[] = {{DimensionMethod::Uniform, "uniform"},
                                                               {DimensionMethod::Adaptive, "adaptive"}};
constexpr EnumName<ConditionalRule> kConditionalRuleNames[] = {
    {ConditionalRule::ExactMass, "exact-mass"}, {ConditionalRule::AverageOfNormalized, "average-of-normalized"}};
constexpr EnumName<ConditionalTolerance> kConditionalToleranceNames[] = {
    {ConditionalTolerance::Constant, "constant"}, {ConditionalTolerance::MassScaled, "mass-scaled"}};
}  // namespace

std::string_view toString(DimensionMethod method) { return nameOf(kDimensionMethodNames, method); }
std::string_view toString(ConditionalRule rule) { return nameOf(kConditionalRuleNames, rule); }
std::string_view toString(ConditionalTolerance tolerance) { return nameOf(kConditionalToleranceNames, tolerance); }

DimensionMethod parseDimensionMethod(std::string_view name) {
  return valueNamed(kDimensionMethodNames, name, "dimension method");
}
ConditionalRule parseConditionalRule(std::string_view name) {
  return valueNamed(kConditionalRuleNames, name, "conditional rule");
}
ConditionalTolerance parseConditionalTolerance(std::string_view name) {
  return valueNamed(kConditionalToleranceNames, name, "conditional tolerance");
}

void validate(const CascadeOptions& o, std::size_t axes) {
  if (o.conditioningDims >= axes) {
    throw OptionError("cascade", "conditioning_dims",
                      std::to_string(o.conditioningDims) + " leaves no axis to sample out of " + std::to_string(axes));
  }
  const std::size_t sampled = axes - o.conditioningDims;
  if (!o.methods.empty() && o.methods.size() != sampled) {
    throw OptionError(
        "cascade", "methods",
        "has " + std::to_string(o.methods.size()) + " entries for " + std::to_string(sampled) + " sampled axes");
  }
  validate(o.simplify);
  if (!(o.sliceGroupingTolerance >= 0.0) || !std::isfinite(o.sliceGroupingTolerance)) {
    throw OptionError("cascade", "slice_grouping_tolerance",
                      "must be finite and >= 0, got " + OptionError::number(o.sliceGroupingTolerance));
  }
}

Cascade::Cascade(std::span<const float> values, std::vector<GridAxis> axes, CascadeOptions options)
    : axes_(std::move(axes)), conditioningDims_(options.conditioningDims), options_(std::move(options)) {
  checkGridShape(values.size(), axes_);
  validate(options_, axes_.size());
  checkNonNegativeFinite(values, axes_);

  std::vector<uint32_t> sizes;
  double cellVolume = 1.0;
  for (std::size_t d = conditioningDims_; d < axes_.size(); ++d) {
    sizes.push_back(axes_[d].cells());
    cellVolume *= axes_[d].cellWidth();
  }
  const Builder builder(sizes, options_);
  const std::size_t sliceSize = builder.blockSize();
  const std::size_t slices = values.size() / sliceSize;

  std::vector<Subtree> parts(slices, builder.emptySubtree());
  sliceIntegral_.resize(slices);
  auto buildSlice = [&](std::size_t s) {
    sliceIntegral_[s] =
        builder.build<float>(values.subspan(s * sliceSize, sliceSize), 0, parts[s], slices == 1) * cellVolume;
  };
  if (slices == 1)
    buildSlice(0);
  else
    tbb::parallel_for(std::size_t{0}, slices, buildSlice);

  // Pools the chosen slices' subtrees into levels_; root i of level 0 is roots[i].
  auto assemble = [&](const std::vector<std::size_t>& roots) {
    Subtree all = builder.emptySubtree();
    for (std::size_t s : roots) append(all, parts[s]);
    levels_.clear();
    for (std::size_t d = 0; d < sizes.size(); ++d) {
      Level level{all[d].method, std::move(all[d].cdf), {}, {}};
      if (level.cdf.size() > UINT32_MAX) throw std::invalid_argument("cascade: table too large");
      if (level.method == DimensionMethod::Adaptive) {
        level.vertices = std::move(all[d].vertices);
        level.starts = startsOf(all[d].counts);
      }
      level.cdf.shrink_to_fit();
      level.vertices.shrink_to_fit();
      levels_.push_back(std::move(level));
    }
  };
  std::vector<std::size_t> roots(slices);
  for (std::size_t s = 0; s < slices; ++s) roots[s] = s;
  assemble(roots);
  if (options_.sliceGroupingTolerance > 0.0 && slices > 1) {
    roots = groupSlices(values, sliceSize);
    if (roots.size() < slices)
      assemble(roots);
    else
      sliceRoot_.clear();
  }
}

std::vector<std::size_t> Cascade::groupSlices(std::span<const float> values, std::size_t sliceSize) {
  // Greedy run-length grouping against the current group's first slice. levels_ still holds
  // every slice here (root s is slice s), so each slice's own distribution is at hand.
  std::vector<std::size_t> firsts{0};
  sliceRoot_.assign(slices(), 0);
  std::vector<double> groupCells = cellProbabilitiesOfRoot(0);
  std::vector<double> exact(sliceSize);
  for (std::size_t s = 1; s < slices(); ++s) {
    const bool zero = isUniformFallback(s);
    bool join = zero == isUniformFallback(firsts.back());  // empty slices keep their uniform table
    if (join && !zero) {
      const std::span<const float> slice = values.subspan(s * sliceSize, sliceSize);
      double total = 0.0;
      for (float v : slice) total += v;
      for (std::size_t i = 0; i < sliceSize; ++i) exact[i] = slice[i] / total;
      const CompressionQuality shared = compareCellProbabilities(exact, groupCells);
      const CompressionQuality own = compareCellProbabilities(exact, cellProbabilitiesOfRoot(s));
      join = shared.unreachableMass == 0.0 &&
             shared.chi2Divergence - own.chi2Divergence <= options_.sliceGroupingTolerance;
    }
    if (join) {
      sliceRoot_[s] = static_cast<uint32_t>(firsts.size() - 1);
      continue;
    }
    sliceRoot_[s] = static_cast<uint32_t>(firsts.size());
    firsts.push_back(s);
    groupCells = cellProbabilitiesOfRoot(s);
  }
  return firsts;
}

std::size_t Cascade::sliceOf(std::span<const float> condition) const {
  if (condition.size() != conditioningDims_) {
    throw std::invalid_argument("cascade: " + std::to_string(condition.size()) + " condition coordinates for " +
                                std::to_string(conditioningDims_) + " conditioning axes");
  }
  std::size_t slice = 0;
  for (std::size_t d = 0; d < conditioningDims_; ++d) {
    slice = slice * axes_[d].cells() + axes_[d].cellOf(condition[d]);
  }
  return slice;
}

// The checks of every sample() and pdf() call are inlined there; the messages are built out of line.
namespace {
[[noreturn]] void throwArity(std::size_t given, std::size_t needed, const char* what) {
  throw std::invalid_argument(std::string("cascade: ") + std::to_string(given) + " " + what + " for " +
                              std::to_string(needed) + " sampled axes");
}

[[noreturn]] void throwNoSlice(std::size_t slice, std::size_t slices) {
  throw std::out_of_range("cascade: slice " + std::to_string(slice) + " of " + std::to_string(slices));
}

inline void requireArity(std::size_t given, std::size_t needed, const char* what) {
  if (given != needed) [[unlikely]]
    throwArity(given, needed, what);
}
}  // namespace

inline void Cascade::requireSlice(std::size_t slice) const {
  if (slice >= slices()) [[unlikely]]
    throwNoSlice(slice, slices());
}

SampleND Cascade::sample(std::span<const float> condition, std::span<const float> u) const {
  return sampleInSlice(sliceOf(condition), u);
}

float Cascade::pdf(std::span<const float> condition, std::span<const float> x) const {
  return pdfInSlice(sliceOf(condition), x);
}

SampleND Cascade::sampleInSlice(std::size_t slice, std::span<const float> u) const {
  const CellSample c = sampleCellsInSlice(slice, u);
  SampleND result;
  result.x = c.x;
  result.pdf = c.pdf;
  result.dims = c.dims;
  return result;
}

CellSample Cascade::sampleCellsInSlice(std::size_t slice, std::span<const float> u) const {
  requireSlice(slice);
  requireArity(u.size(), sampledDims(), "variates");
  std::size_t index = rootOf(slice);
  CellSample result;
  result.dims = static_cast<uint8_t>(levels_.size());
  double density = 1.0;
  const GridAxis* axis = axes_.data() + conditioningDims_;
  std::size_t d = 0;
  for (const Level& level : levels_) {
    const NodeView n = viewOf(level, axis->cells()).node(index);
    const detail::Draw drawn = detail::draw(n.cdf, *axis, clampUnit(u[d]));
    result.x[d] = drawn.placed.x;
    result.cells[d] = drawn.placed.cell;
    result.fractions[d] = drawn.placed.gridCoordinate - drawn.placed.cell;
    density *= drawn.density;
    index = n.childBase + drawn.interval;
    ++axis, ++d;
  }
  result.pdf = clampDensity(density);
  return result;
}

float Cascade::pdfInSlice(std::size_t slice, std::span<const float> x) const {
  requireSlice(slice);
  requireArity(x.size(), sampledDims(), "coordinates");
  std::array<uint32_t, kMaxDims> cells;
  for (std::size_t level = 0; level < x.size(); ++level) {
    const GridAxis& axis = axes_[conditioningDims_ + level];
    if (!axis.contains(x[level])) return 0.0f;
    cells[level] = axis.cellOf(x[level]);
  }
  return pdfOfCells(slice, std::span(cells.data(), x.size()));
}

float Cascade::pdfOfCellsInSlice(std::size_t slice, std::span<const uint32_t> cells) const {
  requireSlice(slice);
  requireArity(cells.size(), sampledDims(), "cells");
  for (std::size_t level = 0; level < cells.size(); ++level)
    if (cells[level] >= axes_[conditioningDims_ + level].cells()) return 0.0f;
  return pdfOfCells(slice, cells);
}

float Cascade::pdfOfCells(std::size_t slice, std::span<const uint32_t> cells) const {
  std::size_t index = rootOf(slice);
  double density = 1.0;
  for (std::size_t level = 0; level < levels_.size(); ++level) {
    const GridAxis& axis = axes_[conditioningDims_ + level];
    const NodeView n = viewOf(levels_[level], axis.cells()).node(index);
    const detail::Lookup l = detail::lookupCell(n.cdf, axis, cells[level]);
    if (l.density == 0.0) return 0.0f;
    density *= l.density;
    index = n.childBase + l.interval;
  }
  return clampDensity(density);
}

void Cascade::invert(std::span<const float> condition, std::span<const float> x, std::span<float> u) const {
  requireArity(x.size(), sampledDims(), "coordinates");
  requireArity(u.size(), sampledDims(), "variates");
  std::size_t index = rootOf(sliceOf(condition));
  for (std::size_t level = 0; level < levels_.size(); ++level) {
    const GridAxis& axis = axes_[conditioningDims_ + level];
    const NodeView n = viewOf(levels_[level], axes_[conditioningDims_ + level].cells()).node(index);
    u[level] = detail::invert(n.cdf, axis, x[level]);
    index = n.childBase + n.cdf.intervalOfCell(axis.cellOf(x[level]));
  }
}

std::size_t Cascade::bytes() const {
  std::size_t total = sliceIntegral_.size() * sizeof(double) + sliceRoot_.size() * sizeof(uint32_t);
  for (const Level& l : levels_) {
    total += l.cdf.size() * sizeof(float) + l.vertices.bytes() + l.starts.size() * sizeof(uint32_t);
  }
  return total;
}

std::size_t Cascade::distinctSlices() const {
  // Roots are numbered in slice order, so the last slice has the largest.
  return sliceRoot_.empty() ? slices() : sliceRoot_.back() + std::size_t{1};
}

std::size_t Cascade::distributionOf(std::size_t slice) const {
  requireSlice(slice);
  return rootOf(slice);
}

std::vector<std::size_t> Cascade::cdfsPerLevel() const {
  // A level's CDFs are the intervals of the level above: each CDF has its interior points + 1.
  std::vector<std::size_t> cdfs{distinctSlices()};
  for (std::size_t level = 0; level + 1 < levels_.size(); ++level)
    cdfs.push_back(levels_[level].cdf.size() + cdfs.back());
  return cdfs;
}

std::vector<double> Cascade::averageIntervals() const {
  std::vector<double> result;
  for (std::size_t d = 0; d < conditioningDims_; ++d) result.push_back(axes_[d].cells());
  const std::vector<std::size_t> cdfs = cdfsPerLevel();
  for (std::size_t level = 0; level < levels_.size(); ++level) {
    result.push_back(static_cast<double>(levels_[level].cdf.size() + cdfs[level]) / static_cast<double>(cdfs[level]));
  }
  return result;
}

std::vector<std::size_t> Cascade::pointsPerDimension() const {
  std::vector<std::size_t> result;
  const std::vector<std::size_t> cdfs = cdfsPerLevel();
  for (std::size_t level = 0; level < levels_.size(); ++level)
    result.push_back(levels_[level].cdf.size() + 2 * cdfs[level]);
  return result;
}

std::vector<std::vector<uint32_t>> Cascade::breakpoints(std::size_t axis) const {
  if (axis < conditioningDims_ || axis >= dims())
    throw std::invalid_argument("cascade: axis " + std::to_string(axis) + " is not a sampled axis");
  const std::size_t level = axis - conditioningDims_;
  const Level& l = levels_[level];
  const uint32_t cells = axes_[axis].cells();
  std::vector<std::vector<uint32_t>> result(cdfsPerLevel()[level]);
  for (std::size_t c = 0; c < result.size(); ++c) {
    std::vector<uint32_t>& vertices = result[c];
    vertices.push_back(0);
    if (l.method == DimensionMethod::Uniform) {
      for (uint32_t k = 1; k < cells; ++k) vertices.push_back(k);
    } else {
      for (uint32_t k = l.starts[c]; k < l.starts[c + 1]; ++k) vertices.push_back(l.vertices[k]);
    }
    vertices.push_back(cells);
  }
  return result;
}

std::vector<std::vector<float>> Cascade::breakpointValues(std::size_t axis) const {
  if (axis < conditioningDims_ || axis >= dims())
    throw std::invalid_argument("cascade: axis " + std::to_string(axis) + " is not a sampled axis");
  const std::size_t level = axis - conditioningDims_;
  const LevelView view = viewOf(levels_[level], axes_[axis].cells());
  std::vector<std::vector<float>> result(cdfsPerLevel()[level]);
  for (std::size_t c = 0; c < result.size(); ++c) {
    const detail::BreakpointCdf cdf = view.node(c).cdf;
    for (std::size_t j = 0; j < cdf.count; ++j) result[c].push_back(cdf.value(j));
  }
  return result;
}

std::vector<double> Cascade::cellProbabilities(std::size_t slice) const {
  if (slice >= slices()) throw std::invalid_argument("cascade: no slice " + std::to_string(slice));
  return cellProbabilitiesOfRoot(rootOf(slice));
}

std::vector<double> Cascade::cellProbabilitiesOfRoot(std::size_t root) const {
  std::vector<LevelView> views;
  std::size_t cells = 1;
  for (std::size_t level = 0; level < levels_.size(); ++level) {
    views.push_back(viewOf(levels_[level], axes_[conditioningDims_ + level].cells()));
    cells *= views.back().cells;
  }
  std::vector<double> out(cells);
  fillCellProbabilities(views, root, out);
  return out;
}

}  // namespace acdf

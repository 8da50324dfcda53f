#include "acdf/sampling/hierarchical_warp_2d.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "acdf/sampling/grid_check.h"

namespace acdf {

namespace {

// The largest double below 1: a rescaled variate stays in [0, 1) despite rounding.
constexpr double kOneMinusEpsilonDouble = 0x1.fffffffffffffp-1;

std::vector<GridAxis> checked(std::span<const float> values, std::vector<GridAxis> axes) {
  if (axes.size() != 2)
    throw std::invalid_argument("hierarchical warp: needs 2 axes, got " + std::to_string(axes.size()));
  checkGridShape(values.size(), axes);
  checkNonNegativeFinite(values, axes);
  return axes;
}

// One binary choice of the descent: the first branch has mass `first`, the second `second`
// (first + second > 0). Returns the branch taken and rescales u to [0, 1) inside it.
uint32_t choose(double& u, double first, double second) {
  const double total = first + second;
  const double p = first / total;
  if (u < p) {
    u = std::min(u / p, kOneMinusEpsilonDouble);
    return 0;
  }
  u = std::min((u - p) / (second / total), kOneMinusEpsilonDouble);
  return 1;
}

// The inverse of choose() for a known branch.
double unchoose(double u, double first, double second, uint32_t branch) {
  const double total = first + second;
  return branch == 0 ? u * (first / total) : first / total + u * (second / total);
}

}  // namespace

HierarchicalWarp2D::HierarchicalWarp2D(std::span<const float> values, std::vector<GridAxis> axes)
    : axes_(checked(values, std::move(axes))), cellArea_(axes_[0].cellWidth() * axes_[1].cellWidth()) {
  double total = 0;
  for (float v : values) total += v;
  uniformFallback_ = total == 0.0;

  // Level 0 holds the normalised values; each further level the float sums of the one below,
  // until the level whose parent is the 1 × 1 top.
  uint32_t rows = this->rows(), columns = this->columns();
  std::vector<float> masses(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    masses[i] = uniformFallback_ ? static_cast<float>(1.0 / static_cast<double>(values.size()))
                                 : static_cast<float>(values[i] / total);
  for (;;) {
    Level level;
    level.parentColumns = (columns + 1) / 2;
    const uint32_t parentRows = (rows + 1) / 2;
    level.blocks.assign(4 * std::size_t{parentRows} * level.parentColumns, 0.0f);
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < columns; ++c) level.blocks[slot(level, r, c)] = masses[std::size_t{r} * columns + c];
    masses.assign(std::size_t{parentRows} * level.parentColumns, 0.0f);
    for (std::size_t node = 0; node < masses.size(); ++node) {
      const float* b = &level.blocks[4 * node];
      masses[node] = static_cast<float>(double{b[0]} + b[1] + b[2] + b[3]);
    }
    levels_.push_back(std::move(level));
    if (parentRows == 1 && levels_.back().parentColumns == 1) break;
    rows = parentRows;
    columns = levels_.back().parentColumns;
  }
}

HierarchicalWarp2D::CellSample HierarchicalWarp2D::sampleCell(double u0, double u1) const {
  u0 = u0 >= 0.0 ? std::min(u0, kOneMinusEpsilonDouble) : 0.0;  // NaN too
  u1 = u1 >= 0.0 ? std::min(u1, kOneMinusEpsilonDouble) : 0.0;
  uint32_t row = 0, column = 0;  // the node entered, on the level above the one read
  for (auto level = levels_.rbegin(); level != levels_.rend(); ++level) {
    const float* b = &level->blocks[4 * (std::size_t{row} * level->parentColumns + column)];
    const uint32_t down = choose(u0, double{b[0]} + b[1], double{b[2]} + b[3]);
    const uint32_t right = choose(u1, b[2 * down], b[2 * down + 1]);
    row = 2 * row + down;
    column = 2 * column + right;
  }
  return {row, column, u0, u1, leaf(row, column)};
}

std::array<double, 2> HierarchicalWarp2D::invertCell(uint32_t row, uint32_t column, double fractionDown,
                                                     double fractionRight) const {
  if (row >= rows() || column >= columns() || leaf(row, column) == 0.0) return {0.0, 0.0};
  double u0 = std::clamp(fractionDown, 0.0, 1.0), u1 = std::clamp(fractionRight, 0.0, 1.0);
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    const uint32_t r = row >> k, c = column >> k;  // the ancestor on level k
    const float* b = &levels_[k].blocks[4 * (std::size_t{r / 2} * levels_[k].parentColumns + c / 2)];
    const uint32_t down = r & 1, right = c & 1;
    u0 = unchoose(u0, double{b[0]} + b[1], double{b[2]} + b[3], down);
    u1 = unchoose(u1, b[2 * down], b[2 * down + 1], right);
  }
  return {u0, u1};
}

SampleND HierarchicalWarp2D::sample(std::span<const float> u) const {
  if (u.size() != 2)
    throw std::invalid_argument("hierarchical warp: " + std::to_string(u.size()) + " variates for 2 axes");
  const CellSample s = sampleCell(clampUnit(u[0]), clampUnit(u[1]));
  SampleND result;
  result.dims = 2;
  result.x[0] = axes_[0].place(s.row, s.row + 1, s.fractionDown);
  result.x[1] = axes_[1].place(s.column, s.column + 1, s.fractionRight);
  result.pdf = densityOf(s.probability);
  return result;
}

float HierarchicalWarp2D::pdf(std::span<const float> x) const {
  if (x.size() != 2)
    throw std::invalid_argument("hierarchical warp: " + std::to_string(x.size()) + " coordinates for 2 axes");
  if (!axes_[0].contains(x[0]) || !axes_[1].contains(x[1])) return 0.0f;
  return densityOf(leaf(axes_[0].cellOf(x[0]), axes_[1].cellOf(x[1])));
}

void HierarchicalWarp2D::invert(std::span<const float> x, std::span<float> u) const {
  if (x.size() != 2 || u.size() != 2) throw std::invalid_argument("hierarchical warp: invert needs 2 coordinates");
  const uint32_t row = axes_[0].cellOf(x[0]), column = axes_[1].cellOf(x[1]);
  const std::array<double, 2> v =
      invertCell(row, column, axes_[0].gridCoordinate(x[0]) - row, axes_[1].gridCoordinate(x[1]) - column);
  u[0] = clampUnit(static_cast<float>(v[0]));
  u[1] = clampUnit(static_cast<float>(v[1]));
}

std::size_t HierarchicalWarp2D::bytes() const {
  std::size_t total = 0;
  for (const Level& level : levels_) total += level.blocks.size() * sizeof(float);
  return total;
}

std::vector<double> HierarchicalWarp2D::cellProbabilities() const {
  std::vector<double> p;
  p.reserve(std::size_t{rows()} * columns());
  for (uint32_t r = 0; r < rows(); ++r)
    for (uint32_t c = 0; c < columns(); ++c) p.push_back(leaf(r, c));
  return p;
}

}  // namespace acdf

#include "acdf/sampling/windowed_table_2d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace acdf {

namespace {

// The CDF at the n + 1 vertices of masses that sum to `total` (a uniform one when it is 0), in
// float: what simplifyCdf reads.
std::vector<float> cdfOf(const std::vector<double>& masses, double total) {
  std::vector<float> cdf(masses.size() + 1, 0.0f);
  double running = 0;
  for (std::size_t k = 0; k < masses.size(); ++k) {
    running += masses[k];
    cdf[k + 1] = total > 0 ? static_cast<float>(running / total)
                           : static_cast<float>(static_cast<double>(k + 1) / masses.size());
  }
  cdf.back() = 1.0f;
  return cdf;
}

// For each fine cell, the coarse cell whose vertices [v[c], v[c + 1]) hold it.
std::vector<uint32_t> coarseOfFine(const std::vector<uint32_t>& vertices) {
  std::vector<uint32_t> coarse(vertices.back());
  for (uint32_t c = 0; c + 1 < vertices.size(); ++c)
    std::fill(coarse.begin() + vertices[c], coarse.begin() + vertices[c + 1], c);
  return coarse;
}

// `vertices` with the midpoints of the marked intervals added, sorted. Halving (rather than the
// marginal's worst vertex) bounds the weight-bound passes by log2 of the fine cells: the fine cell
// breaking the bound need not be where the marginal bends most.
void splitMarked(std::vector<uint32_t>& vertices, const std::vector<char>& marked) {
  std::vector<uint32_t> split;
  split.reserve(vertices.size() * 2);
  for (std::size_t c = 0; c + 1 < vertices.size(); ++c) {
    split.push_back(vertices[c]);
    if (marked[c]) split.push_back(vertices[c] + (vertices[c + 1] - vertices[c]) / 2);
  }
  split.push_back(vertices.back());
  vertices = std::move(split);
}

std::vector<double> coordinatesOf(const std::vector<uint32_t>& vertices) {
  std::vector<double> x(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) x[k] = static_cast<double>(vertices[k]) / vertices.back();
  x.back() = 1.0;
  return x;
}

// x moved strictly inside [lo, hi] (lo < hi) by a margin that survives a direction's round trip
// (1e-9 of the square, or a quarter of a narrower interval).
double inside(double x, double lo, double hi) {
  const double margin = std::min(1e-9, 0.25 * (hi - lo));
  return std::clamp(x, lo + margin, hi - margin);
}

}  // namespace

WindowedTable2D::WindowedTable2D(std::span<const float> function, uint32_t columns, uint32_t rows,
                                 const SimplifyOptions& options) {
  if (columns == 0 || rows == 0 || function.size() != static_cast<std::size_t>(columns) * rows)
    throw std::invalid_argument("WindowedTable2D: the function must have columns × rows > 0 values");
  validate(options);
  std::vector<double> columnMass(columns, 0.0), rowMass(rows, 0.0);
  double total = 0;
  for (uint32_t j = 0; j < rows; ++j)
    for (uint32_t i = 0; i < columns; ++i) {
      const float f = function[static_cast<std::size_t>(j) * columns + i];
      if (!(f >= 0.0f) || !std::isfinite(f))
        throw std::invalid_argument("WindowedTable2D: value " + std::to_string(j * columns + i) +
                                    " is negative or not finite");
      columnMass[i] += f;
      rowMass[j] += f;
      total += f;
    }
  std::vector<uint32_t> columnVertices = simplifyCdf(cdfOf(columnMass, total), options);
  std::vector<uint32_t> rowVertices = simplifyCdf(cdfOf(rowMass, total), options);

  // The coarse cells' sums, then the weight bound on whole cells.
  std::vector<double> sums;
  for (;;) {
    const std::vector<uint32_t> columnOf = coarseOfFine(columnVertices), rowOf = coarseOfFine(rowVertices);
    const std::size_t nI = columnVertices.size() - 1, nJ = rowVertices.size() - 1;
    sums.assign(nI * nJ, 0.0);
    std::vector<float> largest(nI * nJ, 0.0f);
    for (uint32_t j = 0; j < rows; ++j)
      for (uint32_t i = 0; i < columns; ++i) {
        const std::size_t cell = rowOf[j] * nI + columnOf[i];
        const float f = function[static_cast<std::size_t>(j) * columns + i];
        sums[cell] += f;
        largest[cell] = std::max(largest[cell], f);
      }
    if (!(options.weightBound > 0)) break;
    std::vector<char> splitColumn(nI, 0), splitRow(nJ, 0);
    bool any = false;
    for (std::size_t J = 0; J < nJ; ++J)
      for (std::size_t I = 0; I < nI; ++I) {
        const uint32_t width = columnVertices[I + 1] - columnVertices[I];
        const uint32_t height = rowVertices[J + 1] - rowVertices[J];
        const double mean = sums[J * nI + I] / (static_cast<double>(width) * height);
        if (!(largest[J * nI + I] > options.weightBound * mean)) continue;
        // The longer side (in fine cells) is halved; a cell over the bound has two fine cells or more.
        (width >= height ? splitColumn[I] : splitRow[J]) = 1;
        any = true;
      }
    if (!any) break;
    splitMarked(columnVertices, splitColumn);
    splitMarked(rowVertices, splitRow);
  }

  const std::size_t nI = columnVertices.size() - 1, nJ = rowVertices.size() - 1;
  coarseColumnOf_ = coarseOfFine(columnVertices);
  coarseRowOf_ = coarseOfFine(rowVertices);
  columnVertices_ = coordinatesOf(columnVertices);
  rowVertices_ = coordinatesOf(rowVertices);
  density_.resize(nI * nJ);
  for (std::size_t J = 0; J < nJ; ++J)
    for (std::size_t I = 0; I < nI; ++I)
      density_[J * nI + I] = sums[J * nI + I] / (static_cast<double>(columnVertices[I + 1] - columnVertices[I]) *
                                                 (rowVertices[J + 1] - rowVertices[J]));
  rowIntegral_.assign(nJ * (nI + 1), 0.0);
  summedArea_.assign((nJ + 1) * (nI + 1), 0.0);
  for (std::size_t J = 0; J < nJ; ++J) {
    double* row = &rowIntegral_[J * (nI + 1)];
    for (std::size_t I = 0; I < nI; ++I)
      row[I + 1] = row[I] + density_[J * nI + I] * (columnVertices_[I + 1] - columnVertices_[I]);
    const double height = rowVertices_[J + 1] - rowVertices_[J];
    for (std::size_t I = 0; I <= nI; ++I)
      summedArea_[(J + 1) * (nI + 1) + I] = summedArea_[J * (nI + 1) + I] + row[I] * height;
  }
}

namespace {
// The fine cell of x in [0, 1] among `cells`, clamped (NaN to 0).
std::size_t fineCellOf(double x, std::size_t cells) {
  const double fine = std::floor(x * static_cast<double>(cells));
  return fine >= 0 ? static_cast<std::size_t>(std::min(fine, cells - 1.0)) : 0;
}
}  // namespace

uint32_t WindowedTable2D::columnOf(double a) const { return coarseColumnOf_[fineCellOf(a, coarseColumnOf_.size())]; }

uint32_t WindowedTable2D::rowOf(double b) const { return coarseRowOf_[fineCellOf(b, coarseRowOf_.size())]; }

uint32_t WindowedTable2D::columnOfEnd(double a) const {
  const uint32_t column = columnOf(a);
  return column > 0 && a <= columnVertices_[column] ? column - 1 : column;
}

uint32_t WindowedTable2D::rowOfEnd(double b) const {
  const uint32_t row = rowOf(b);
  return row > 0 && b <= rowVertices_[row] ? row - 1 : row;
}

double WindowedTable2D::alongRow(uint32_t row, double a, uint32_t column) const {
  const std::size_t nI = columnVertices_.size() - 1;
  return rowIntegral_[row * (nI + 1) + column] + density_[row * nI + column] * (a - columnVertices_[column]);
}

double WindowedTable2D::belowRow(uint32_t row, double a, uint32_t column) const {
  const std::size_t stride = columnVertices_.size();
  const double lo = summedArea_[row * stride + column], hi = summedArea_[row * stride + column + 1];
  const double t = (a - columnVertices_[column]) / (columnVertices_[column + 1] - columnVertices_[column]);
  return lo + (hi - lo) * t;
}

double WindowedTable2D::density(double a, double b) const {
  return density_[rowOf(b) * (columnVertices_.size() - 1) + columnOf(a)];
}

std::size_t WindowedTable2D::bytes() const {
  return (columnVertices_.size() + rowVertices_.size() + density_.size() + summedArea_.size() + rowIntegral_.size()) *
             sizeof(double) +
         (coarseColumnOf_.size() + coarseRowOf_.size()) * sizeof(uint32_t);
}

// The window's mass row by row: the first and last coarse rows it cuts from their own running
// integrals along a, the whole rows between from the summed-area table. sample() walks the same
// terms, so its row search and mass() agree.
double WindowedTable2D::mass(const Window& w) const {
  if (!(w.a1 > w.a0) || !(w.b1 > w.b0)) return 0.0;
  const uint32_t I0 = columnOf(w.a0), I1 = columnOfEnd(w.a1), J0 = rowOf(w.b0), J1 = rowOfEnd(w.b1);
  auto across = [&](uint32_t J) { return alongRow(J, w.a1, I1) - alongRow(J, w.a0, I0); };
  if (J0 == J1) return std::max(0.0, (w.b1 - w.b0) * across(J0));
  const double strips = (belowRow(J1, w.a1, I1) - belowRow(J1, w.a0, I0)) -
                        (belowRow(J0 + 1, w.a1, I1) - belowRow(J0 + 1, w.a0, I0));
  return std::max(0.0, (rowVertices_[J0 + 1] - w.b0) * across(J0) + strips + (w.b1 - rowVertices_[J1]) * across(J1));
}

WindowedTable2D::Sample WindowedTable2D::sample(const Window& w, double mass, double u0, double u1) const {
  const std::size_t nI = columnVertices_.size() - 1;
  const uint32_t I0 = columnOf(w.a0), I1 = columnOfEnd(w.a1), J0 = rowOf(w.b0), J1 = rowOfEnd(w.b1);
  auto across = [&](uint32_t J) { return alongRow(J, w.a1, I1) - alongRow(J, w.a0, I0); };
  auto strip = [&](uint32_t J) { return belowRow(J, w.a1, I1) - belowRow(J, w.a0, I0); };
  const double target = std::clamp(u1, 0.0, 1.0) * mass;

  // The row: the first whose upper end's running mass exceeds the target (so its own mass in the
  // window is positive), with M(B_J) = first + strip(J) − strip(J0 + 1) at the row vertices between.
  uint32_t J = J0;
  double below = 0;  // the window's mass under row J's lower end (b0 for J0)
  if (J1 > J0) {
    const double first = (rowVertices_[J0 + 1] - w.b0) * across(J0);
    if (!(target < first)) {
      const double base = strip(J0 + 1);
      auto massAt = [&](uint32_t vertex) { return first + strip(vertex) - base; };
      uint32_t lo = J0 + 1, hi = J1;  // the answer is in [lo, hi]
      while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (massAt(mid + 1) > target) hi = mid;
        else lo = mid + 1;
      }
      J = lo;
      below = massAt(J);
    }
  }
  // The summed-area table's differences round where its rows are many times the window's: a row
  // of no mass in the window can win by an ulp. The nearest row with mass takes its place, the
  // sample at its middle.
  const bool replaced = !(across(J) > 0);
  if (replaced) {
    uint32_t k = 1;
    for (; k <= J1 - J0; ++k)
      if ((J >= J0 + k && across(J - k) > 0) || (J + k <= J1 && across(J + k) > 0)) break;
    if (k > J1 - J0) return {0.5 * (w.a0 + w.a1), 0.5 * (w.b0 + w.b1), 0.0};  // no mass: `mass` was rounding
    J = J >= J0 + k && across(J - k) > 0 ? J - k : J + k;
  }
  const double rowLo = std::max(rowVertices_[J], w.b0), rowHi = std::min(rowVertices_[J + 1], w.b1);
  const double b = replaced ? 0.5 * (rowLo + rowHi) : inside(rowLo + (target - below) / across(J), rowLo, rowHi);

  // The column: inside row J, over [a0, a1], the first coarse column whose upper end's running
  // integral exceeds the target; its density is positive (a zero one adds nothing to the integral).
  const double* running = &rowIntegral_[J * (nI + 1)];
  const double start = alongRow(J, w.a0, I0), end = alongRow(J, w.a1, I1);
  const double along = start + std::clamp(u0, 0.0, 1.0) * (end - start);
  uint32_t lo = I0, hi = I1;
  while (lo < hi) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (running[mid + 1] > along) hi = mid;
    else lo = mid + 1;
  }
  uint32_t I = lo;
  while (!(density_[J * nI + I] > 0) && I > I0) --I;  // `along` rounded to the end: the last column with mass
  const double columnLo = std::max(columnVertices_[I], w.a0), columnHi = std::min(columnVertices_[I + 1], w.a1);
  const double a = inside(columnLo + (along - std::max(running[I], start)) / density_[J * nI + I], columnLo, columnHi);
  return {a, b, density_[J * nI + I] / mass};
}

}  // namespace acdf

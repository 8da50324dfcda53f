#pragma once
// A piecewise-constant density on [0, 1)², sampled inside any axis-aligned window of it: what a
// portal needs (envmap/portal_table.h), whose rectified map is seen from each point through a
// different rectangle of the square (Bitterli et al. 2015; pbrt-v4's WindowedPiecewiseConstant2D).
//
// Adaptive. The function is given on a fine regular grid; the table keeps a tensor grid whose
// column and row vertices are those of the function's two marginal CDFs that simplification keeps
// (simplify.h), then splits columns and rows while a fine cell's density exceeds ρ times its
// coarse cell's (SimplifyOptions::weightBound, on whole cells as a Cascade bounds it). A sun of a
// few pixels keeps small cells around it; a smooth sky, a few wide ones.
//
// Windows. The cascade's per-row conditional CDFs would need every row's share of the window per
// call; a summed-area table over the coarse grid gives the window's mass from four lookups and its
// marginal over rows at any row vertex from two, so a sample costs two binary searches over the
// coarse vertices. The table integrates the piecewise-constant function exactly: S at the grid
// vertices in double, bilinear inside a cell. Sums in double; masses in the function's own units.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "acdf/sampling/simplify.h"

namespace acdf {

class WindowedTable2D {
 public:
  // An axis-aligned rectangle [a0, a1] × [b0, b1] inside [0, 1]², a0 <= a1, b0 <= b1.
  struct Window {
    double a0, a1, b0, b1;
  };
  struct Sample {
    double a, b;  // strictly inside the window and inside one coarse cell of positive density
    double pdf;   // w.r.t. da db, over the window: density(a, b) / mass(window)
  };

  // function: columns × rows values, row-major (row index along b), finite and >= 0; options as a
  // Cascade's (ε of the marginal CDFs' simplification, ρ). Throws std::invalid_argument for an
  // empty grid or a bad value (naming its index), OptionError for bad options.
  WindowedTable2D(std::span<const float> function, uint32_t columns, uint32_t rows, const SimplifyOptions& options);

  // ∫ of the table's function over the window (0 for an empty one).
  double mass(const Window& window) const;
  // A point of the window with density proportional to the function, for u0, u1 in [0, 1];
  // `mass` is mass(window) > 0 (a caller that chose the window by its mass has it at hand). u1
  // picks the row coordinate b, u0 the column coordinate a in that row.
  Sample sample(const Window& window, double mass, double u0, double u1) const;  // pdf 0 only if mass was rounding
  // The table's piecewise-constant function at (a, b) in [0, 1]² (the coarse cell's mean).
  double density(double a, double b) const;

  uint32_t coarseColumns() const { return static_cast<uint32_t>(columnVertices_.size() - 1); }
  uint32_t coarseRows() const { return static_cast<uint32_t>(rowVertices_.size() - 1); }
  std::size_t bytes() const;
  // The arrays, for a sampler of the same table written elsewhere (acdf.mitsuba's drjit one):
  // vertex coordinates of each axis (coarse cells + 1 each, 0 and 1 at the ends), the fine cell
  // of each axis' coarse cell (fine cells each), the coarse density (row-major), the summed-area
  // table at the vertices (row-major, (rows + 1) × (columns + 1)) and each row's running integral
  // along a at the column vertices (rows × (columns + 1)).
  std::span<const double> columnVertices() const { return columnVertices_; }
  std::span<const double> rowVertices() const { return rowVertices_; }
  std::span<const uint32_t> coarseColumnOfFine() const { return coarseColumnOf_; }
  std::span<const uint32_t> coarseRowOfFine() const { return coarseRowOf_; }
  std::span<const double> coarseDensity() const { return density_; }
  std::span<const double> summedArea() const { return summedArea_; }
  std::span<const double> rowIntegral() const { return rowIntegral_; }

 private:
  uint32_t columnOf(double a) const;
  uint32_t rowOf(double b) const;
  // The cell a window ending at a (or b) ends in: the one below a vertex it ends on.
  uint32_t columnOfEnd(double a) const;
  uint32_t rowOfEnd(double b) const;
  // ∫ over [0, a] × [0, B_row] (row a vertex index): linear in a inside a coarse column.
  double belowRow(uint32_t row, double a, uint32_t column) const;
  // ∫ over [0, a] of row `row`'s density (a in column `column`).
  double alongRow(uint32_t row, double a, uint32_t column) const;

  std::vector<double> columnVertices_, rowVertices_;
  std::vector<uint32_t> coarseColumnOf_, coarseRowOf_;
  std::vector<double> density_, summedArea_, rowIntegral_;
};

}  // namespace acdf

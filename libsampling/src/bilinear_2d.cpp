#include "acdf/sampling/bilinear_2d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "acdf/sampling/grid_check.h"
#include "acdf/sampling/linear_segment.h"
#include "breakpoint_cdf.h"

namespace acdf {

namespace {

constexpr std::size_t kMaxCorners = std::size_t{1} << Bilinear2D::kMaxParameters;

std::invalid_argument error(const std::string& what) { return std::invalid_argument("bilinear 2D: " + what); }

std::vector<GridAxis> vertexAxes(uint32_t rows, uint32_t columns) {
  if (rows < 2 || columns < 2) {
    throw error("needs at least 2 vertices per axis, got " + std::to_string(rows) + " × " + std::to_string(columns));
  }
  return {GridAxis(rows - 1), GridAxis(columns - 1)};
}

std::vector<std::vector<float>> checkedParameters(std::vector<std::vector<float>> parameters) {
  if (parameters.size() > Bilinear2D::kMaxParameters) {
    throw error(std::to_string(parameters.size()) + " parameters, at most " +
                std::to_string(Bilinear2D::kMaxParameters) + " are supported");
  }
  for (std::size_t p = 0; p < parameters.size(); ++p) {
    const std::vector<float>& v = parameters[p];
    const std::string name = "parameter " + std::to_string(p);
    if (v.empty()) throw error(name + " has no values");
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!std::isfinite(v[i])) throw error(name + " value " + std::to_string(i) + " is not finite");
      if (i > 0 && !(v[i - 1] < v[i])) {
        throw error(name + " values are not strictly increasing at index " + std::to_string(i) + " (" +
                    std::to_string(v[i - 1]) + ", then " + std::to_string(v[i]) + ")");
      }
    }
  }
  return parameters;
}

std::size_t checkedProduct(std::size_t a, std::size_t b) {
  if (b != 0 && a > std::numeric_limits<std::size_t>::max() / b) throw error("the table size overflows");
  return a * b;
}

// The largest i in [0, size − 2] with value(i) <= target, for value non-decreasing with
// value(0) <= target < value(size − 1): the interval [value(i), value(i + 1)) holding target,
// which therefore has positive width.
template <class Value>
uint32_t findInterval(uint32_t size, double target, const Value& value) {
  uint32_t lo = 0, hi = size - 1;  // value(lo) <= target; hi is size − 1 or value(hi) > target
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (value(mid) <= target)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// The position of x inside its cell of `axis`, in [0, 1]: computed the same way wherever a
// coordinate is evaluated, so sample() and pdf() agree bit for bit.
double fraction(const GridAxis& axis, float x, uint32_t cell) { return axis.gridCoordinate(x) - cell; }

}  // namespace

struct Bilinear2D::Blend {
  struct Corner {
    const float* slice;  // the slice's block of table_
    double weight;       // > 0 (a product of many tiny weights could underflow to 0: harmless)
  };
  std::array<Corner, kMaxCorners> corners;
  std::size_t count = 0;
};

// At x[0] = (row + down) / (rows − 1): per corner, the vertex rows row and row + 1 of its slice
// and their weights in the lerp, near = (1 − down) and far = down times the corner's weight. The
// density along the line is Σ (near · f_row + far · f_row+1), its CDF over columns
// Σ (near · T_row · C_row + far · T_row+1 · C_row+1), with C a row's normalised CDF and T its mass.
struct Bilinear2D::Strip {
  struct Rows {
    const float *density0, *density1;  // vertex rows row, row + 1
    const float *cdf0, *cdf1;
    double near, far;        // the two rows' weights in the blended density
    double cdfNear, cdfFar;  // near · T_row, far · T_row+1
  };
  std::array<Rows, kMaxCorners> rows;
  std::size_t count = 0;
  double acrossRows = 0;  // the density over x[0] at this line (0 where the strip has no mass)
  double total = 0;       // cdf(columns − 1): the line's mass
  double columnWidth = 0;

  // The blended conditional CDF over columns at vertex `column`, unnormalised (total at the last).
  double cdf(uint32_t column) const {
    double sum = 0;
    for (std::size_t k = 0; k < count; ++k)
      sum += rows[k].cdfNear * rows[k].cdf0[column] + rows[k].cdfFar * rows[k].cdf1[column];
    return sum;
  }
  // The mass of cell [column, column + 1] on the line: the sum of the rows' steps, not a
  // difference of two cdf() values, so a share below double resolution still counts (pdf > 0).
  double cellMass(uint32_t column) const {
    double sum = 0;
    for (std::size_t k = 0; k < count; ++k) {
      const Rows& r = rows[k];
      sum += r.cdfNear * (double{r.cdf0[column + 1]} - r.cdf0[column]) +
             r.cdfFar * (double{r.cdf1[column + 1]} - r.cdf1[column]);
    }
    return sum;
  }
  // The blended density at vertex `column` of the line.
  double value(uint32_t column) const {
    double sum = 0;
    for (std::size_t k = 0; k < count; ++k)
      sum += rows[k].near * rows[k].density0[column] + rows[k].far * rows[k].density1[column];
    return sum;
  }
  // The density of the sampled law at fraction `right` of cell `column` on this line: the
  // density over x[0] times the cell's conditional probability × its linear shape (per unit of
  // x[1]). 0 where the strip or the cell has no mass.
  double density(uint32_t column, double right) const {
    if (!(acrossRows > 0.0)) return 0.0;
    const double mass = cellMass(column);
    if (!(mass > 0.0)) return 0.0;
    const double c0 = value(column), c1 = value(column + 1);
    return acrossRows * (mass / total) * ((1.0 - right) * c0 + right * c1) / (0.5 * (c0 + c1) * columnWidth);
  }
};

Bilinear2D::Bilinear2D(std::span<const float> values, uint32_t rows, uint32_t columns,
                       std::vector<std::vector<float>> parameterValues)
    : rows_(rows),
      columns_(columns),
      axes_(vertexAxes(rows, columns)),
      parameterValues_(checkedParameters(std::move(parameterValues))) {
  const std::size_t vertices = checkedProduct(rows, columns);
  std::size_t slices = 1;
  parameterStrides_.assign(parameterValues_.size(), 0);
  for (std::size_t p = parameterValues_.size(); p-- > 0;) {
    parameterStrides_[p] = slices;
    slices = checkedProduct(slices, parameterValues_[p].size());
  }
  if (values.size() != checkedProduct(slices, vertices)) {
    throw error(std::to_string(values.size()) + " values for " + std::to_string(slices) + " slice(s) of " +
                std::to_string(rows) + " × " + std::to_string(columns) + " vertices (" +
                std::to_string(slices * vertices) + " expected)");
  }
  // The value grid's shape, so a bad value is named by its (parameter..., row, column) index.
  std::vector<GridAxis> shape;
  for (const auto& v : parameterValues_) shape.emplace_back(static_cast<uint32_t>(v.size()));
  shape.emplace_back(rows);
  shape.emplace_back(columns);
  try {
    checkNonNegativeFinite(values, shape);
  } catch (const std::invalid_argument& e) {
    throw error(e.what());
  }

  rowCdfOffset_ = vertices;
  rowMassOffset_ = 2 * vertices;
  marginalOffset_ = 2 * vertices + rows;
  sliceFloats_ = 2 * vertices + 2 * std::size_t{rows};
  table_.resize(checkedProduct(slices, sliceFloats_));
  uniformFallback_.resize(slices);
  for (std::size_t s = 0; s < slices; ++s)
    uniformFallback_[s] = buildSlice(values.subspan(s * vertices, vertices), table_.data() + s * sliceFloats_);
}

// Fills one slice's block; returns true for the uniform fallback (no mass).
bool Bilinear2D::buildSlice(std::span<const float> values, float* out) {
  const uint32_t rows = rows_, columns = columns_;
  const double rowWidth = axes_[0].cellWidth(), columnWidth = axes_[1].cellWidth();
  // ∫ of the bilinear interpolant = the trapezoid rule on the vertices (exact for it).
  double integral = 0;
  for (uint32_t r = 0; r < rows; ++r) {
    double line = 0;
    for (uint32_t c = 0; c < columns; ++c) line += (c == 0 || c + 1 == columns ? 0.5 : 1.0) * values[r * columns + c];
    integral += (r == 0 || r + 1 == rows ? 0.5 : 1.0) * line;
  }
  integral *= rowWidth * columnWidth;
  const bool fallback = !(integral > 0.0);

  // Normalised densities; every later table is computed from these stored floats, so the tables
  // describe one function. clampDensity keeps a positive value positive.
  float* density = out;
  for (std::size_t i = 0; i < values.size(); ++i)
    density[i] = fallback ? 1.0f : clampDensity(static_cast<double>(values[i]) / integral);

  std::vector<double> masses(columns - 1);
  std::vector<float> cdf;
  cdf.reserve(std::max(rows, columns));
  float* rowMass = out + rowMassOffset_;
  for (uint32_t r = 0; r < rows; ++r) {
    const float* d = density + std::size_t{r} * columns;
    double mass = 0;
    for (uint32_t c = 0; c + 1 < columns; ++c) {
      masses[c] = static_cast<double>(d[c]) + d[c + 1];
      mass += masses[c];
    }
    rowMass[r] = clampDensity(0.5 * mass * columnWidth);
    cdf.clear();
    detail::appendCdf(std::span<const double>(masses), cdf);
    std::copy(cdf.begin(), cdf.end(), out + rowCdfOffset_ + std::size_t{r} * columns);
  }
  masses.resize(rows - 1);
  for (uint32_t r = 0; r + 1 < rows; ++r) masses[r] = static_cast<double>(rowMass[r]) + rowMass[r + 1];
  cdf.clear();
  detail::appendCdf(std::span<const double>(masses), cdf);
  std::copy(cdf.begin(), cdf.end(), out + marginalOffset_);
  return fallback;
}

Bilinear2D::Blend Bilinear2D::blend(std::span<const float> params) const {
  const std::size_t n = parameterValues_.size();
  if (params.size() != n) {
    throw error(std::to_string(params.size()) + " parameter values for " + std::to_string(n) + " parameters");
  }
  // Start from the first slice; each parameter moves every corner to its interval and, between
  // two values, splits it into the two ends (weights 1 − α and α).
  Blend b;
  b.corners[0] = {table_.data(), 1.0};
  b.count = 1;
  for (std::size_t p = 0; p < n; ++p) {
    const std::vector<float>& v = parameterValues_[p];
    const float x = params[p];
    const std::size_t stride = parameterStrides_[p] * sliceFloats_;
    std::size_t first = 0;
    double alpha = 0;                     // weight of the value after `first`
    if (v.size() > 1 && x > v.front()) {  // otherwise (NaN too) the first value
      if (x >= v.back()) {
        first = v.size() - 2;
        alpha = 1;
      } else {
        first = static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), x) - v.begin()) - 1;
        alpha = (static_cast<double>(x) - v[first]) / (static_cast<double>(v[first + 1]) - v[first]);
      }
    }
    if (alpha == 1) {
      first += 1;
      alpha = 0;
    }
    for (std::size_t k = 0; k < b.count; ++k) b.corners[k].slice += first * stride;
    if (alpha == 0) continue;
    for (std::size_t k = 0; k < b.count; ++k) {
      b.corners[b.count + k] = {b.corners[k].slice + stride, b.corners[k].weight * alpha};
      b.corners[k].weight *= 1 - alpha;
    }
    b.count *= 2;
  }
  return b;
}

double Bilinear2D::marginal(const Blend& b, uint32_t row) const {
  double sum = 0;
  for (std::size_t k = 0; k < b.count; ++k) sum += b.corners[k].weight * b.corners[k].slice[marginalOffset_ + row];
  return sum;
}

// The same for strips: the sum of the slices' steps of the marginal CDF.
double Bilinear2D::stripMass(const Blend& b, uint32_t row) const {
  double sum = 0;
  for (std::size_t k = 0; k < b.count; ++k) {
    const float* m = b.corners[k].slice + marginalOffset_ + row;
    sum += b.corners[k].weight * (double{m[1]} - m[0]);
  }
  return sum;
}

double Bilinear2D::rowMass(const Blend& b, uint32_t row) const {
  double sum = 0;
  for (std::size_t k = 0; k < b.count; ++k) sum += b.corners[k].weight * b.corners[k].slice[rowMassOffset_ + row];
  return sum;
}

Bilinear2D::Strip Bilinear2D::strip(const Blend& b, uint32_t row, double down) const {
  Strip s;
  s.count = b.count;
  const std::size_t line0 = std::size_t{row} * columns_, line1 = line0 + columns_;
  for (std::size_t k = 0; k < b.count; ++k) {
    const float* slice = b.corners[k].slice;
    Strip::Rows& r = s.rows[k];
    r.density0 = slice + line0;
    r.density1 = slice + line1;
    r.cdf0 = slice + rowCdfOffset_ + line0;
    r.cdf1 = slice + rowCdfOffset_ + line1;
    r.near = b.corners[k].weight * (1.0 - down);
    r.far = b.corners[k].weight * down;
    r.cdfNear = r.near * slice[rowMassOffset_ + row];
    r.cdfFar = r.far * slice[rowMassOffset_ + row + 1];
  }
  // The strip's probability × the linear shape across it, per unit of x[0].
  const double mass = stripMass(b, row);
  if (mass > 0.0) {
    const double r0 = rowMass(b, row), r1 = rowMass(b, row + 1);
    s.acrossRows =
        (mass / marginal(b, rows_ - 1)) * ((1.0 - down) * r0 + down * r1) / (0.5 * (r0 + r1) * axes_[0].cellWidth());
  }
  s.total = s.cdf(columns_ - 1);
  s.columnWidth = axes_[1].cellWidth();
  return s;
}

SampleND Bilinear2D::sample(std::span<const float> params, std::span<const float> u) const {
  if (u.size() != 2) throw error(std::to_string(u.size()) + " variates for 2 axes");
  const Blend b = blend(params);

  // Rows: the strip from the marginal CDF, then the position inside it.
  const double rowTarget = static_cast<double>(clampUnit(u[0])) * marginal(b, rows_ - 1);
  const uint32_t row = findInterval(rows_, rowTarget, [&](uint32_t r) { return marginal(b, r); });
  // The search leaves marginal(row) <= rowTarget < marginal(row + 1): the strip has mass.
  const double down =
      sampleLinearSegment((rowTarget - marginal(b, row)) / stripMass(b, row), rowMass(b, row), rowMass(b, row + 1));
  SampleND result;
  result.dims = 2;
  result.x[0] = axes_[0].place(row, row + 1, down);
  // The columns are sampled on the float coordinate's line, so the law and pdf() see the same
  // conditional. A line through a vertex row of zero mass has none: move one float inwards.
  Strip s = strip(b, row, fraction(axes_[0], result.x[0], row));
  if (!(s.total > 0.0)) {
    result.x[0] = std::nextafter(result.x[0], 1.0f);
    s = strip(b, row, fraction(axes_[0], result.x[0], row));
  }

  const double columnTarget = static_cast<double>(clampUnit(u[1])) * s.total;
  const uint32_t column = findInterval(columns_, columnTarget, [&](uint32_t c) { return s.cdf(c); });
  const double c0 = s.value(column);
  const double right =
      sampleLinearSegment((columnTarget - s.cdf(column)) / s.cellMass(column), c0, s.value(column + 1));
  result.x[1] = axes_[1].place(column, column + 1, right);
  double placed = fraction(axes_[1], result.x[1], column);
  if (placed == 0.0 && c0 == 0.0) {  // on a vertex of zero density
    result.x[1] = std::nextafter(result.x[1], 1.0f);
    placed = fraction(axes_[1], result.x[1], column);
  }
  result.pdf = clampDensity(s.density(column, placed));
  return result;
}

float Bilinear2D::pdf(std::span<const float> params, std::span<const float> x) const {
  if (x.size() != 2) throw error(std::to_string(x.size()) + " coordinates for 2 axes");
  const Blend b = blend(params);
  if (!axes_[0].contains(x[0]) || !axes_[1].contains(x[1])) return 0.0f;
  const uint32_t row = axes_[0].cellOf(x[0]), column = axes_[1].cellOf(x[1]);
  const Strip s = strip(b, row, fraction(axes_[0], x[0], row));
  return clampDensity(s.density(column, fraction(axes_[1], x[1], column)));
}

std::array<float, 2> Bilinear2D::invert(std::span<const float> params, std::span<const float> x) const {
  if (x.size() != 2) throw error(std::to_string(x.size()) + " coordinates for 2 axes");
  const Blend b = blend(params);
  const uint32_t row = axes_[0].cellOf(x[0]), column = axes_[1].cellOf(x[1]);
  const double down = fraction(axes_[0], x[0], row), right = fraction(axes_[1], x[1], column);

  const double u0 =
      (marginal(b, row) + stripMass(b, row) * linearSegmentCdf(down, rowMass(b, row), rowMass(b, row + 1))) /
      marginal(b, rows_ - 1);
  const Strip s = strip(b, row, down);
  const double u1 =
      s.total > 0.0
          ? (s.cdf(column) + s.cellMass(column) * linearSegmentCdf(right, s.value(column), s.value(column + 1))) /
                s.total
          : 0.0;
  return {clampUnit(static_cast<float>(u0)), clampUnit(static_cast<float>(u1))};
}

std::size_t Bilinear2D::uniformFallbackSlices() const {
  return static_cast<std::size_t>(std::count(uniformFallback_.begin(), uniformFallback_.end(), uint8_t{1}));
}

std::size_t Bilinear2D::bytes() const {
  std::size_t total = table_.size() * sizeof(float) + uniformFallback_.size();
  for (const auto& v : parameterValues_) total += v.size() * sizeof(float);
  return total;
}

}  // namespace acdf

// libsampling in Python: the 1D tables, the cascade, the quality metrics and the chi-square test.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>
#include <iterator>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/quality.h"
#include "arrays.h"
#include "bindings.h"
#include "options.h"

namespace acdf::python {

using namespace pybind11::literals;

py::list cascadeArrays(std::span<const Cascade* const> cascades) {
  py::list levels;
  const Cascade& first = *cascades.front();
  for (std::size_t axis = first.conditioningDims(); axis < first.dims(); ++axis) {
    std::vector<std::vector<uint32_t>> vertices;
    std::vector<std::vector<float>> values;
    for (const Cascade* cascade : cascades) {
      std::ranges::move(cascade->breakpoints(axis), std::back_inserter(vertices));
      std::ranges::move(cascade->breakpointValues(axis), std::back_inserter(values));
    }
    std::size_t points = 0;
    for (const auto& cdf : vertices) points += cdf.size();
    auto start = output<uint32_t>(vertices.size() + 1), vertex = output<uint32_t>(points);
    auto value = output<float>(points);
    uint32_t *starts = start.mutable_data(), *vs = vertex.mutable_data();
    float* fs = value.mutable_data();
    std::size_t at = 0;
    for (std::size_t k = 0; k < vertices.size(); ++k) {
      starts[k] = static_cast<uint32_t>(at);
      std::copy(vertices[k].begin(), vertices[k].end(), vs + at);
      std::copy(values[k].begin(), values[k].end(), fs + at);
      at += vertices[k].size();
    }
    starts[vertices.size()] = static_cast<uint32_t>(at);
    levels.append(py::dict("start"_a = start, "vertex"_a = vertex, "value"_a = value));
  }
  return levels;
}

py::list cascadeArrays(const Cascade& cascade) {
  const Cascade* one[] = {&cascade};
  return cascadeArrays(one);
}

namespace {

// sample(u) -> (x, pdf), pdf(x) and, where the table has it, invert(x) for a 1D table.
template <class Table>
void bindBatched1D(py::class_<Table>& c) {
  c.def(
      "sample",
      [](const Table& t, const ArrayArg& u) {
        const Batch<float> variates = batch<float>(u, 0, "u");
        const std::size_t n = variates.rows;
        auto x = output<float>(n), pdf = output<float>(n);
        const float* in = variates.data;
        float *xs = x.mutable_data(), *ps = pdf.mutable_data();
        forEachRow(n, [&](std::size_t i) {
          const Sample1D s = t.sample(in[i]);
          xs[i] = s.x;
          ps[i] = s.pdf;
        });
        return py::make_tuple(x, pdf);
      },
      "u"_a, "Samples for variates u, shape (n,): (x, pdf), both float32 of shape (n,); pdf > 0.");
  c.def(
      "pdf",
      [](const Table& t, const ArrayArg& x) {
        const Batch<float> points = batch<float>(x, 0, "x");
        const std::size_t n = points.rows;
        auto pdf = output<float>(n);
        const float* in = points.data;
        float* ps = pdf.mutable_data();
        forEachRow(n, [&](std::size_t i) { ps[i] = t.pdf(in[i]); });
        return pdf;
      },
      "x"_a, "Density at each x, shape (n,), per unit length of the domain; 0 outside [lo, hi).");
  if constexpr (requires(const Table& t) { t.invert(0.0f); }) {
    c.def(
        "invert",
        [](const Table& t, const ArrayArg& x) {
          const Batch<float> points = batch<float>(x, 0, "x");
          const std::size_t n = points.rows;
          auto u = output<float>(n);
          const float* in = points.data;
          float* us = u.mutable_data();
          forEachRow(n, [&](std::size_t i) { us[i] = t.invert(in[i]); });
          return u;
        },
        "x"_a, "The variates sample() maps to each x (up to float rounding), shape (n,).");
  }
  c.def_property_readonly("bytes", &Table::bytes, "Bytes of the table.");
  c.def_property_readonly("integral", &Table::integral, "Integral of the function over the domain (double sum).");
  c.def_property_readonly("is_uniform_fallback", &Table::isUniformFallback,
                          "True for an all-zero function, which is sampled uniformly.");
  c.def_property_readonly(
      "domain",
      [](const Table& t) {
        return std::pair{t.axis().lo(), t.axis().hi()};
      },
      "(lo, hi) of the domain.");
}

// A 1D table's function values, shape (n,).
std::vector<float> functionValues(const ArrayArg& f) {
  const Batch<float> values = batch<float>(f, 0, "function");
  return {values.data, values.data + values.rows};
}

// Row i of an (n, k) float array, or its only row (broadcast).
std::span<const float> rowOf(const float* data, std::size_t columns, std::size_t rowsInArray, std::size_t i) {
  return {data + columns * (rowsInArray == 1 ? 0 : i), columns};
}

// The condition argument of a Cascade call: none (no conditioning axes), one row, or one per row.
struct Condition {
  std::optional<Batch<float>> values;
  const float* data() const { return values ? values->data : nullptr; }
  std::size_t rows() const { return values ? values->rows : 1; }
};

Condition conditionOf(const Cascade& c, const std::optional<ArrayArg>& condition, std::size_t n) {
  const std::size_t k = c.conditioningDims();
  if (!condition) {
    if (k != 0) throw py::value_error("condition: the cascade has " + std::to_string(k) + " conditioning axes");
    return {};
  }
  if (k == 0) throw py::value_error("condition: the cascade has no conditioning axes");
  Batch<float> b = batch<float>(*condition, k, "condition", true);
  pairedRows(n, b.rows, "condition and the samples");
  if (b.rows != 1 && b.rows != n) throw py::value_error("condition: one row or one per sample");
  return {std::move(b)};
}

// A (n, k) coordinate argument, or (n,) for k = 1.
Batch<float> coordinates(const ArrayArg& a, std::size_t k, const char* name) {
  Array<float> values = numbers<float>(a, name, "of shape " + (k == 1 ? "(n,) or (n, 1)" : rowShape(k)));
  const std::size_t n =
      k == 1 && values.ndim() == 1 ? static_cast<std::size_t>(values.shape(0)) : rows(values, k, name);
  const float* data = values.data();
  return {std::move(values), data, n};
}

Cascade makeCascade(const ArrayArg& valuesArg, const std::optional<std::vector<std::pair<float, float>>>& domains,
                    uint32_t conditioningDims, const std::optional<std::vector<std::string>>& methods,
                    std::optional<double> epsilon, const std::optional<SimplifyOptions>& simplify,
                    const std::string& conditional, const std::string& tolerance, double sliceGrouping) {
  const Array<float> values = numbers<float>(valuesArg, "values", "of shape (n0, n1, ...)");
  if (values.ndim() < 1 || static_cast<std::size_t>(values.ndim()) > kMaxDims)
    throw py::value_error("values: expected 1 to " + std::to_string(kMaxDims) + " dimensions, got " +
                          std::to_string(values.ndim()));
  const auto dims = static_cast<std::size_t>(values.ndim());
  if (domains && domains->size() != dims)
    throw py::value_error("axes: " + std::to_string(domains->size()) + " (lo, hi) pairs for " + std::to_string(dims) +
                          " dimensions");
  std::vector<GridAxis> axes;
  for (std::size_t d = 0; d < dims; ++d) {
    const auto [lo, hi] = domains ? (*domains)[d] : std::pair{0.0f, 1.0f};
    axes.emplace_back(static_cast<uint32_t>(values.shape(d)), lo, hi);
  }
  CascadeOptions options;
  options.conditioningDims = conditioningDims;
  if (methods)
    for (const std::string& m : *methods) options.methods.push_back(parseDimensionMethod(m));
  options.simplify = simplifyOptions(options.simplify, simplify, epsilon);
  options.conditional = parseConditionalRule(conditional);
  options.tolerance = parseConditionalTolerance(tolerance);
  options.sliceGroupingTolerance = sliceGrouping;
  validate(options, dims);
  const std::span<const float> data(values.data(), static_cast<std::size_t>(values.size()));
  py::gil_scoped_release release;
  return Cascade(data, std::move(axes), std::move(options));
}

void bindCascade(py::module_& m) {
  py::class_<Cascade> c(m, "Cascade", R"(The cascaded N-dimensional CDF (Lawrence et al. 2005).

Cascade(values, axes=None, conditioning_dims=0, methods=None, epsilon=None, simplify=None,
        conditional="exact-mass", tolerance="constant", slice_grouping_tolerance=0.0)

values: a non-negative array of 1 to 8 dimensions (float32; axis 0 varies slowest), one value per
  grid cell; the distribution is proportional to it and piecewise constant on the cells.
axes: one (lo, hi) domain per dimension (default [0, 1) each).
conditioning_dims: the first axes are given at sample time (nearest cell: "slices"), the others
  sampled, as p(x0) p(x1 | interval of x0) ...
methods: per sampled axis, "uniform" (every cell kept) or "adaptive" (simplified; the default).
epsilon / simplify: the simplification (acdf.SimplifyOptions; epsilon overrides its tolerance).
conditional: "exact-mass" or "average-of-normalized" (the paper's eq. 10).
tolerance: "constant" or "mass-scaled" (the conditionals' tolerance scaled by their mass).
slice_grouping_tolerance: > 0 lets neighbouring slices share a distribution.

Densities are per unit of the sampled axes' product measure. Raises ValueError for a negative,
NaN or Inf value or bad options.)");
  c.def(py::init(&makeCascade), "values"_a, "axes"_a = py::none(), "conditioning_dims"_a = 0u, "methods"_a = py::none(),
        "epsilon"_a = py::none(), "simplify"_a = py::none(), "conditional"_a = "exact-mass", "tolerance"_a = "constant",
        "slice_grouping_tolerance"_a = 0.0);
  c.def(
      "sample",
      [](const Cascade& t, const ArrayArg& u, const std::optional<ArrayArg>& condition) {
        const std::size_t k = t.sampledDims();
        const Batch<float> variates = coordinates(u, k, "u");
        const std::size_t n = variates.rows;
        const Condition cond = conditionOf(t, condition, n);
        auto x = output<float>(n, k);
        auto pdf = output<float>(n);
        const float* in = variates.data;
        float *xs = x.mutable_data(), *ps = pdf.mutable_data();
        const std::size_t kc = t.conditioningDims();
        forEachRow(n, [&](std::size_t i) {
          const SampleND s = t.sample(rowOf(cond.data(), kc, cond.rows(), i), {in + k * i, k});
          std::memcpy(xs + k * i, s.x.data(), k * sizeof(float));
          ps[i] = s.pdf;
        });
        return py::make_tuple(x, pdf);
      },
      "u"_a, "condition"_a = py::none(),
      "Samples for variates u of shape (n, sampled_dims) ((n,) for one sampled axis): (x, pdf), x of shape\n"
      "(n, sampled_dims) and pdf of shape (n,), float32. condition: (conditioning_dims,) or\n"
      "(n, conditioning_dims) coordinates of the conditioning axes.");
  c.def(
      "pdf",
      [](const Cascade& t, const ArrayArg& x, const std::optional<ArrayArg>& condition) {
        const std::size_t k = t.sampledDims();
        const Batch<float> points = coordinates(x, k, "x");
        const std::size_t n = points.rows;
        const Condition cond = conditionOf(t, condition, n);
        auto pdf = output<float>(n);
        const float* in = points.data;
        float* ps = pdf.mutable_data();
        const std::size_t kc = t.conditioningDims();
        forEachRow(n, [&](std::size_t i) { ps[i] = t.pdf(rowOf(cond.data(), kc, cond.rows(), i), {in + k * i, k}); });
        return pdf;
      },
      "x"_a, "condition"_a = py::none(), "Density at each point x (rows as in sample()); 0 outside the domain.");
  c.def(
      "invert",
      [](const Cascade& t, const ArrayArg& x, const std::optional<ArrayArg>& condition) {
        const std::size_t k = t.sampledDims();
        const Batch<float> points = coordinates(x, k, "x");
        const std::size_t n = points.rows;
        const Condition cond = conditionOf(t, condition, n);
        auto u = output<float>(n, k);
        const float* in = points.data;
        float* us = u.mutable_data();
        const std::size_t kc = t.conditioningDims();
        forEachRow(n, [&](std::size_t i) {
          t.invert(rowOf(cond.data(), kc, cond.rows(), i), {in + k * i, k}, {us + k * i, k});
        });
        return u;
      },
      "x"_a, "condition"_a = py::none(),
      "The variates sample() maps to each x (up to float rounding), (n, sampled_dims).");
  c.def_property_readonly("dims", &Cascade::dims);
  c.def_property_readonly("sampled_dims", &Cascade::sampledDims);
  c.def_property_readonly("conditioning_dims", &Cascade::conditioningDims);
  c.def_property_readonly(
      "shape",
      [](const Cascade& t) {
        py::tuple shape(t.dims());
        for (std::size_t d = 0; d < t.dims(); ++d) shape[d] = t.axes()[d].cells();
        return shape;
      },
      "Cells per axis, as the values array's shape.");
  c.def_property_readonly(
      "domains",
      [](const Cascade& t) {
        py::list domains;
        for (const GridAxis& axis : t.axes()) domains.append(py::make_tuple(axis.lo(), axis.hi()));
        return domains;
      },
      "Each axis' (lo, hi), as the axes argument gives them (float32 values).");
  c.def_property_readonly("bytes", &Cascade::bytes, "Bytes of the stored tables.");
  c.def_property_readonly("points", &Cascade::pointsPerDimension,
                          "Per sampled axis: kept points (interval ends) summed over its 1D CDFs.");
  c.def_property_readonly("average_intervals", &Cascade::averageIntervals,
                          "Per axis: the average number of intervals of its 1D CDFs (the paper's average resolution).");
  c.def_property_readonly("slices", &Cascade::slices);
  c.def_property_readonly("distinct_slices", &Cascade::distinctSlices);
  c.def(
      "slice_of",
      [](const Cascade& t, const ArrayArg& condition) {
        const std::size_t k = t.conditioningDims();
        const Array<float> c = numbers<float>(condition, "condition", "of shape (" + std::to_string(k) + ",)");
        if (c.ndim() != 1 || static_cast<std::size_t>(c.shape(0)) != k)
          throw py::value_error("condition: expected shape (" + std::to_string(k) + ",), got " + shapeText(c));
        return t.sliceOf({c.data(), k});
      },
      "condition"_a, "The slice (index) the conditioning coordinates fall in.");
  c.def("integral", &Cascade::integral, "slice"_a = 0, "Integral of the values over the sampled axes of a slice.");
  c.def(
      "cell_probabilities",
      [](const Cascade& t, std::size_t slice) {
        if (slice >= t.slices()) throw py::value_error("slice: " + std::to_string(slice) + " out of range");
        std::vector<double> p = t.cellProbabilities(slice);
        std::vector<py::ssize_t> shape;
        for (std::size_t d = t.conditioningDims(); d < t.dims(); ++d) shape.push_back(t.axes()[d].cells());
        py::array_t<double> out(shape);
        std::memcpy(out.mutable_data(), p.data(), p.size() * sizeof(double));
        return out;
      },
      "slice"_a = 0, "The probability of each cell of the sampled grid (exact), shaped as that grid.");
  c.def(
      "breakpoints",
      [](const Cascade& t, std::size_t axis) {
        py::list out;
        for (const auto& cdf : t.breakpoints(axis)) out.append(py::array_t<uint32_t>(cdf.size(), cdf.data()));
        return out;
      },
      "axis"_a,
      "The grid vertices each 1D CDF of a sampled axis keeps (ends included), one array per CDF. For a 2D\n"
      "cascade, breakpoints(0)[0] bounds the row intervals and breakpoints(1)[j] the column intervals of\n"
      "row interval j.");
  c.def("arrays", py::overload_cast<const Cascade&>(&cascadeArrays),
        "The whole table, for sampling it in other arithmetic (acdf.mitsuba's drjit arrays): one dict per\n"
        "sampled axis of its 1D CDFs laid end to end, in breakpoints()' order: CDF k's breakpoints are\n"
        "[start[k], start[k + 1]), each a grid vertex (uint32) and the CDF's value there (float32), from\n"
        "(0, 0) to (cells, 1). A slice samples first-level CDF distributions[slice]; below interval j of\n"
        "the CDFs of one axis, counted across them in order, lies CDF j of the next axis. The density is\n"
        "the product over sampled axes of (value step) / (vertex step x cell width).");
  c.def_property_readonly(
      "distributions",
      [](const Cascade& t) {
        auto out = output<uint32_t>(t.slices());
        uint32_t* data = out.mutable_data();
        for (std::size_t s = 0; s < t.slices(); ++s) data[s] = static_cast<uint32_t>(t.distributionOf(s));
        return out;
      },
      "Per slice, the first-level CDF (of arrays()) it samples: the slice itself unless slice grouping\n"
      "gave it an earlier slice's distribution.");
  c.def(
      "serialize",
      [](const Cascade& t) {
        const std::vector<std::byte> b = t.serialize();
        return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
      },
      "The table as bytes, read back exactly by Cascade.deserialize.");
  c.def_static(
      "deserialize",
      [](const py::bytes& data) {
        const std::string_view s = data;
        return Cascade::deserialize(std::as_bytes(std::span(s.data(), s.size())));
      },
      "data"_a);
}

void bindTables1D(py::module_& m) {
  py::class_<PiecewiseConstant1D> pc(m, "PiecewiseConstant1D", R"(The classic tabulated 1D distribution (pbrt, Mitsuba).

PiecewiseConstant1D(function, lo=0.0, hi=1.0): function gives n equal cells over [lo, hi).)");
  pc.def(py::init([](const ArrayArg& f, float lo, float hi) { return PiecewiseConstant1D(functionValues(f), lo, hi); }),
         "function"_a, "lo"_a = 0.0f, "hi"_a = 1.0f);
  bindBatched1D(pc);
  pc.def_property_readonly(
      "cdf", [](const PiecewiseConstant1D& t) { return py::array_t<float>(t.cdf().size(), t.cdf().data()); });

  py::class_<AdaptiveCdf1D> ad(m, "AdaptiveCdf1D",
                               R"(An adaptive 1D CDF: the table's CDF simplified to the vertices that matter.

AdaptiveCdf1D(function, lo=0.0, hi=1.0, epsilon=None, simplify=None))");
  ad.def(py::init([](const ArrayArg& f, float lo, float hi, std::optional<double> epsilon,
                     const std::optional<SimplifyOptions>& simplify) {
           return AdaptiveCdf1D(functionValues(f), lo, hi, simplifyOptions({}, simplify, epsilon));
         }),
         "function"_a, "lo"_a = 0.0f, "hi"_a = 1.0f, "epsilon"_a = py::none(), "simplify"_a = py::none());
  bindBatched1D(ad);
  ad.def_property_readonly("points", &AdaptiveCdf1D::points, "Kept breakpoints, ends included.");
  ad.def_property_readonly(
      "breakpoints",
      [](const AdaptiveCdf1D& t) {
        py::array_t<uint32_t> vertices(t.points());
        py::array_t<float> cdf(t.points());
        for (std::size_t k = 0; k < t.points(); ++k) {
          vertices.mutable_at(k) = t.vertex(k);
          cdf.mutable_at(k) = t.cdfAt(k);
        }
        return py::make_tuple(vertices, cdf);
      },
      "(vertices, cdf): the grid vertex of each kept point and the CDF there.");

  py::class_<AliasTable1D> al(m, "AliasTable1D", R"(A 1D distribution sampled in O(1) by Walker's alias method.

AliasTable1D(function, lo=0.0, hi=1.0). Not invertible.)");
  al.def(py::init([](const ArrayArg& f, float lo, float hi) { return AliasTable1D(functionValues(f), lo, hi); }),
         "function"_a, "lo"_a = 0.0f, "hi"_a = 1.0f);
  bindBatched1D(al);
}

void bindSimplifyOptions(py::module_& m) {
  const SimplifyOptions d;
  py::class_<SimplifyOptions> s(m, "SimplifyOptions", R"(How a 1D CDF is simplified.

SimplifyOptions(method="douglas-peucker", metric="vertical", epsilon=0.002, max_points=0,
                weight_bound=4.0)
method: "douglas-peucker" or "greedy"; metric: "vertical", "perpendicular" or "chi-square";
epsilon: the largest error left; max_points: greedy only, a point budget (0: none);
weight_bound: the largest p_cell / p_adaptive left inside an interval (0: no bound).)");
  s.def(py::init([](const std::string& method, const std::string& metric, double epsilon, uint32_t maxPoints,
                    double weightBound) {
          SimplifyOptions o{parseSimplifier(method), parseErrorMetric(metric), epsilon, maxPoints, weightBound};
          validate(o);
          return o;
        }),
        "method"_a = std::string(toString(d.method)), "metric"_a = std::string(toString(d.metric)),
        "epsilon"_a = d.epsilon, "max_points"_a = d.maxPoints, "weight_bound"_a = d.weightBound);
  s.def_property_readonly("method", [](const SimplifyOptions& o) { return std::string(toString(o.method)); });
  s.def_property_readonly("metric", [](const SimplifyOptions& o) { return std::string(toString(o.metric)); });
  s.def_readonly("epsilon", &SimplifyOptions::epsilon);
  s.def_readonly("max_points", &SimplifyOptions::maxPoints);
  s.def_readonly("weight_bound", &SimplifyOptions::weightBound);
  s.def("__repr__", [](const SimplifyOptions& o) {
    return "SimplifyOptions(method='" + std::string(toString(o.method)) + "', metric='" +
           std::string(toString(o.metric)) + "', epsilon=" + py::repr(py::float_(o.epsilon)).cast<std::string>() +
           ", max_points=" + std::to_string(o.maxPoints) +
           ", weight_bound=" + py::repr(py::float_(o.weightBound)).cast<std::string>() + ")";
  });
}

void bindStatistics(py::module_& m) {
  py::class_<CompressionQuality>(m, "CompressionQuality",
                                 "What sampling q instead of p costs (compare_cell_probabilities).")
      .def_readonly("chi2_divergence", &CompressionQuality::chi2Divergence,
                    "sum p^2/q - sum p over reachable cells: the relative variance q adds.")
      .def_readonly("max_weight_ratio", &CompressionQuality::maxWeightRatio, "max p/q over reachable cells.")
      .def_readonly("unreachable_mass", &CompressionQuality::unreachableMass, "sum p over cells where q == 0.");
  m.def(
      "compare_cell_probabilities",
      [](const ArrayArg& pArg, const ArrayArg& qArg) {
        const Array<double> p = numbers<double>(pArg, "p", "of any shape"), q = numbers<double>(qArg, "q", "of any shape");
        if (p.size() != q.size())
          throw py::value_error("p and q: " + std::to_string(p.size()) + " and " + std::to_string(q.size()) + " cells");
        return compareCellProbabilities({p.data(), static_cast<std::size_t>(p.size())},
                                        {q.data(), static_cast<std::size_t>(q.size())});
      },
      "p"_a, "q"_a,
      "Quality of a compressed distribution from exact cell probabilities: p the reference's, q the\n"
      "approximation's (any shape, the same size; each should sum to 1).");

  py::class_<ChiSquareResult>(m, "ChiSquareResult")
      .def_readonly("statistic", &ChiSquareResult::statistic)
      .def_readonly("dof", &ChiSquareResult::dof)
      .def_readonly("pvalue", &ChiSquareResult::pvalue)
      .def_readonly("pooled_cells", &ChiSquareResult::pooledCells);
  m.def(
      "chi_square_test",
      [](const ArrayArg& observedArg, const ArrayArg& expectedArg, double minExpected) {
        const Array<double> observed = numbers<double>(observedArg, "observed", "of any shape"),
                            expected = numbers<double>(expectedArg, "expected", "of any shape");
        if (observed.size() != expected.size())
          throw py::value_error("observed and expected: " + std::to_string(observed.size()) + " and " +
                                std::to_string(expected.size()) + " cells");
        return chiSquareTest({observed.data(), static_cast<std::size_t>(observed.size())},
                             {expected.data(), static_cast<std::size_t>(expected.size())}, minExpected);
      },
      "observed"_a, "expected"_a, "min_expected"_a = 5.0,
      "Pearson's chi-square goodness-of-fit test. observed: counts per cell; expected: N x probability per\n"
      "cell. The smallest cells are pooled until each pool expects >= min_expected.");
  m.def("sidak_alpha", &sidakAlpha, "alpha"_a, "tests"_a,
        "Per-test level keeping the family-wise level alpha over `tests` tests.");
}

}  // namespace

void bindSampling(py::module_& m) {
  bindSimplifyOptions(m);
  bindTables1D(m);
  bindCascade(m);
  bindStatistics(m);
}

}  // namespace acdf::python

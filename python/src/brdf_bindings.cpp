// brdf in Python: measured and analytic BRDF models and every sampler of them.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/ggx_sampler.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/rgl.h"
#include "acdf/brdf/rgl_sampler.h"
#include "acdf/brdf/table_options.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "arrays.h"
#include "bindings.h"
#include "options.h"

namespace acdf::python {

using namespace pybind11::literals;

namespace {

// A Bilinear2D's stored tables as RglBrdfSampler.warp_arrays documents them.
py::dict bilinearArrays(const Bilinear2D& warp) {
  const std::size_t slices = warp.slices(), rows = warp.rows(), columns = warp.columns();
  const std::span<const float> table = warp.table();
  // The per-slice run of `perSlice` floats at `offset`, as an array of `shape` (slices first).
  const auto gather = [&](std::size_t offset, std::size_t perSlice, std::vector<py::ssize_t> shape) {
    py::array_t<float> out(shape);
    float* data = out.mutable_data();
    for (std::size_t s = 0; s < slices; ++s)
      std::copy_n(table.data() + s * warp.sliceFloats() + offset, perSlice, data + s * perSlice);
    return out;
  };
  const auto n = [](std::size_t count) { return static_cast<py::ssize_t>(count); };
  py::list parameterValues;
  for (std::size_t p = 0; p < warp.parameters(); ++p) {
    const std::vector<float>& v = warp.parameterValues(p);
    parameterValues.append(py::array_t<float>(v.size(), v.data()));
  }
  return py::dict("parameter_values"_a = parameterValues,
                  "density"_a = gather(0, rows * columns, {n(slices), n(rows), n(columns)}),
                  "row_cdf"_a = gather(warp.rowCdfOffset(), rows * columns, {n(slices), n(rows), n(columns)}),
                  "row_mass"_a = gather(warp.rowMassOffset(), rows, {n(slices), n(rows)}),
                  "marginal"_a = gather(warp.marginalOffset(), rows, {n(slices), n(rows)}));
}

// f(wo, wi) for batches of directions in the local frame; either may be one row (broadcast).
template <class Evaluator>
py::array_t<float> evalBatch(const Evaluator& f, const ArrayArg& wo, const ArrayArg& wi) {
  const Directions o = directions(wo, "wo"), i = directions(wi, "wi");
  const std::size_t n = pairedRows(o.rows(), i.rows(), "wo and wi");
  auto out = output<float>(n, 3);
  float* data = out.mutable_data();
  forEachRow(n, [&](std::size_t k) { storeRgb(data, k, f.eval(o[k], i[k])); });
  return out;
}

// The class's docstring: its table options are table_options.h's list, defaults included.
const std::string& tabulatedSamplerDoc() {
  static const std::string doc = [] {
    const TabulatedBrdfOptions defaults;
    std::string text =
        "Half-vector tables of a model, uniform or adaptive.\n\n"
        "TabulatedBrdfSampler(model, method=\"adaptive\", simplify=None, **table_options)\n"
        "method: \"uniform\" or \"adaptive\"; simplify: an acdf.SimplifyOptions (the chi-square metric at\n"
        "epsilon 5e-5 without a weight bound by default; a chi2_epsilon keyword overrides its epsilon).\n"
        "Table options (the scene format's \"table\" keys and the CLI's flags; acdf.table_options()):\n";
    for (const TableOption& option : tableOptionList())
      text += "  " + std::string(option.key) + " (" + std::string(toString(option.type)) + ", default " +
              option.get(defaults) + "): " + std::string(option.help) + "\n";
    return text;
  }();
  return doc;
}

// A Python value of a table option's type as the option's text (TableOption).
std::string tableOptionText(const TableOption& option, py::handle value) {
  const bool isBool = py::isinstance<py::bool_>(value);
  const bool isInt = py::isinstance<py::int_>(value) && !isBool;
  switch (option.type) {
    case TableOption::Type::Count:
      if (isInt) return py::str(value);
      break;
    case TableOption::Type::Number:
      if (isInt || py::isinstance<py::float_>(value)) return fmt::format("{}", value.cast<double>());
      break;
    case TableOption::Type::Boolean:
      if (isBool) return value.cast<bool>() ? "true" : "false";
      break;
    case TableOption::Type::Name:
      if (py::isinstance<py::str>(value)) return value.cast<std::string>();
      break;
  }
  throw py::type_error(fmt::format("TabulatedBrdfSampler: {} must be a {}, got {}", option.key,
                                   toString(option.type), py::str(py::type::of(value).attr("__name__")).cast<std::string>()));
}

void setTableOptions(TabulatedBrdfOptions& o, const py::kwargs& table) {
  for (const auto& [key, value] : table) {
    const std::string name = key.cast<std::string>();
    const TableOption* option = findTableOption(name);
    if (!option) {
      std::vector<std::string_view> keys;
      for (const TableOption& each : tableOptionList()) keys.push_back(each.key);
      throw py::type_error(
          fmt::format("TabulatedBrdfSampler: unknown table option '{}' (one of: {})", name, fmt::join(keys, ", ")));
    }
    option->set(o, tableOptionText(*option, value));
  }
}

const char* kFrameDoc =
    "Directions are float64 unit vectors in the local shading frame (z = normal), shape (n, 3) or (3,)\n"
    "for one direction used with every row of the other argument.";

void bindModels(py::module_& m) {
  py::class_<BrdfModel, std::shared_ptr<BrdfModel>> model(m, "BrdfModel", R"(A BRDF f(wo, wi) in 1/sr.

f is 0 unless both directions are above the horizon (z > 0).)");
  model.def(
      "eval", [](const BrdfModel& f, const ArrayArg& wo, const ArrayArg& wi) { return evalBatch(f, wo, wi); },
      "wo"_a, "wi"_a, (std::string("f(wo, wi) as RGB float32, shape (n, 3). ") + kFrameDoc).c_str());
  model.def_property_readonly("isotropic", &BrdfModel::isotropic);

  py::class_<MerlBrdf, BrdfModel, std::shared_ptr<MerlBrdf>>(
      m, "MerlBrdf",
      R"(A measured MERL BRDF (Matusik et al. 2003), .binary file.

MerlBrdf.load(path, interpolation="nearest"): interpolation as acdf's scene files spell it.
Raises acdf.FileError for a missing, truncated or malformed file.)")
      .def_static(
          "load",
          [](const std::string& path, const std::string& interpolation) {
            const MerlBrdf::Interpolation mode = parseInterpolation(interpolation);
            py::gil_scoped_release release;
            return std::make_shared<MerlBrdf>(MerlBrdf::load(path, mode));
          },
          "path"_a, "interpolation"_a = "nearest")
      .def_property_readonly(
          "values",
          [](const MerlBrdf& b) {
            auto out = output<float>(MerlBrdf::kCells, 3);
            std::copy_n(b.interleavedValues().data(), 3 * MerlBrdf::kCells, out.mutable_data());
            return out;
          },
          "The stored values (file units, negatives as 0), float32 (cells, 3): cell (theta_h, theta_d, phi_d)\n"
          "at row (theta_h * 90 + theta_d) * 180 + phi_d; times channel_scale they are f in 1/sr.")
      .def_property_readonly_static("channel_scale", [](py::handle) { return MerlBrdf::kChannelScale; })
      .def_property_readonly_static("cells", [](py::handle) {
        return py::make_tuple(MerlBrdf::kThetaHalfCells, MerlBrdf::kThetaDiffCells, MerlBrdf::kPhiDiffCells);
      });

  py::class_<RglBrdf, BrdfModel, std::shared_ptr<RglBrdf>>(m, "RglBrdf",
                                                           R"(A measured RGL material (Dupuy & Jakob 2018), .bsdf file.

RglBrdf.load(path). Raises acdf.FileError for a file that is not a valid RGL tensor file.)")
      .def_static(
          "load",
          [](const std::string& path) {
            py::gil_scoped_release release;
            return std::make_shared<RglBrdf>(RglBrdf::load(path));
          },
          "path"_a);

  py::class_<AnalyticBrdf, BrdfModel, std::shared_ptr<AnalyticBrdf>>(m, "AnalyticBrdf",
                                                                     "An analytic isotropic GGX BRDF.")
      .def_static(
          "preset", [](const std::string& name) { return std::make_shared<AnalyticBrdf>(AnalyticBrdf::preset(name)); },
          "name"_a, "A named preset (preset_names()).")
      .def_static("preset_names", &AnalyticBrdf::presetNames)
      .def_static(
          "conductor",
          [](double alpha, const std::array<double, 3>& f0) {
            return std::make_shared<AnalyticBrdf>(AnalyticBrdf::conductor(alpha, f0));
          },
          "alpha"_a, "f0"_a)
      .def_static(
          "coated_diffuse",
          [](double alpha, const std::array<double, 3>& albedo, double ior) {
            return std::make_shared<AnalyticBrdf>(AnalyticBrdf::coatedDiffuse(alpha, albedo, ior));
          },
          "alpha"_a, "albedo"_a, "ior"_a);

  py::class_<LambertianBrdf, BrdfModel, std::shared_ptr<LambertianBrdf>>(m, "LambertianBrdf",
                                                                         "albedo / pi above the horizon.")
      .def(py::init([](const std::array<float, 3>& albedo) {
             return std::make_shared<LambertianBrdf>(Rgb{albedo[0], albedo[1], albedo[2]});
           }),
           "albedo"_a);
}

void bindSamplers(py::module_& m) {
  py::class_<BrdfSampler, std::shared_ptr<BrdfSampler>> s(m, "BrdfSampler",
                                                          R"(Importance sampling of a BRDF times the cosine.

sample(wo, u) -> (wi, weight, pdf): wi (n, 3) float64, weight = f cos(theta_i) / pdf as RGB float32
(n, 3) (0 below the horizon), pdf per steradian (n,) float64, finite and > 0. pdf(wo, wi) is
the density sample() draws wi with (equal to sample()'s pdf to 1e-4 off cell boundaries).)");
  s.def(
      "sample",
      [](const BrdfSampler& sampler, const ArrayArg& wo, const ArrayArg& u) {
        const Directions o = directions(wo, "wo");
        const Batch<float> variates = batch<float>(u, 2, "u");
        const std::size_t n = pairedRows(variates.rows, o.rows(), "u and wo");
        if (o.rows() != 1 && o.rows() != n) throw py::value_error("wo: one row or one per sample");
        if (variates.rows != n)
          throw py::value_error("u: expected shape (" + std::to_string(n) + ", 2), one row per sample, got " +
                                shapeText(variates.array));
        auto wi = output<double>(n, 3), pdf = output<double>(n);
        auto weight = output<float>(n, 3);
        const float* in = variates.data;
        double *ws = wi.mutable_data(), *ps = pdf.mutable_data();
        float* fs = weight.mutable_data();
        forEachRow(n, [&](std::size_t i) {
          const BrdfSample b = sampler.sample(o[i], in[2 * i], in[2 * i + 1]);
          storeVec3(ws, i, b.wi);
          storeRgb(fs, i, b.weight);
          ps[i] = b.pdf;
        });
        return py::make_tuple(wi, weight, pdf);
      },
      "wo"_a, "u"_a, "u: (n, 2) float32 variates; wo: (n, 3) or one (3,) direction.");
  s.def(
      "pdf",
      [](const BrdfSampler& sampler, const ArrayArg& wo, const ArrayArg& wi) {
        const Directions o = directions(wo, "wo"), i = directions(wi, "wi");
        const std::size_t n = pairedRows(o.rows(), i.rows(), "wo and wi");
        auto pdf = output<double>(n);
        double* ps = pdf.mutable_data();
        forEachRow(n, [&](std::size_t k) { ps[k] = sampler.pdf(o[k], i[k]); });
        return pdf;
      },
      "wo"_a, "wi"_a, kFrameDoc);
  s.def(
      "eval",
      [](const BrdfSampler& sampler, const ArrayArg& wo, const ArrayArg& wi) {
        return evalBatch(sampler, wo, wi);
      },
      "wo"_a, "wi"_a, "The model's f(wo, wi), RGB float32 (n, 3).");
  s.def_property_readonly("bytes", &BrdfSampler::bytes, "Bytes of the sampler's tables.");
  s.def_property_readonly("name", &BrdfSampler::name);

  py::class_<CosineBrdfSampler, BrdfSampler, std::shared_ptr<CosineBrdfSampler>>(
      m, "CosineBrdfSampler", "Cosine-weighted hemisphere sampling of any model: no table.")
      .def(py::init([](std::shared_ptr<BrdfModel> model) { return std::make_shared<CosineBrdfSampler>(model); }),
           "model"_a);

  py::class_<TabulatedBrdfSampler, BrdfSampler, std::shared_ptr<TabulatedBrdfSampler>>(
      m, "TabulatedBrdfSampler", tabulatedSamplerDoc().c_str())
      .def(py::init([](std::shared_ptr<BrdfModel> model, const std::string& method,
                       const std::optional<SimplifyOptions>& simplify, const py::kwargs& table) {
             TabulatedBrdfOptions o;
             o.method = parseDimensionMethod(method);
             if (simplify) o.simplify = *simplify;
             setTableOptions(o, table);
             validate(o);
             py::gil_scoped_release release;
             return std::make_shared<TabulatedBrdfSampler>(std::move(model), o);
           }),
           "model"_a, "method"_a = std::string(toString(TabulatedBrdfOptions{}.method)), "simplify"_a = py::none())
      .def_property_readonly(
          "table", [](const TabulatedBrdfSampler& t) -> const Cascade& { return t.table(); },
          py::return_value_policy::reference_internal, "The half-vector acdf.Cascade.")
      .def_property_readonly(
          "table_options",
          [](const TabulatedBrdfSampler& t) {
            py::dict options;
            for (const TableOption& option : tableOptionList())
              options[py::str(std::string(option.key))] = option.get(t.options());
            return options;
          },
          "The sampler's table options (its defaults included) as text, keyed as acdf.table_options() names them.");

  py::class_<GgxBrdfSampler, BrdfSampler, std::shared_ptr<GgxBrdfSampler>>(
      m, "GgxBrdfSampler",
      "Sampling of an analytic model by the GGX distribution of visible normals (Heitz 2018): no table.")
      .def(py::init([](std::shared_ptr<AnalyticBrdf> model) { return std::make_shared<GgxBrdfSampler>(model); }),
           "model"_a);

  py::class_<RglBrdfSampler, BrdfSampler, std::shared_ptr<RglBrdfSampler>>(
      m, "RglBrdfSampler", "The RGL file's own warps (Dupuy & Jakob 2018), as pbrt-v4 and Mitsuba 3 sample it.")
      .def(py::init([](std::shared_ptr<RglBrdf> model) { return std::make_shared<RglBrdfSampler>(model); }), "model"_a)
      .def_property_readonly(
          "warp_arrays",
          [](const RglBrdfSampler& sampler) {
            const auto& rgl = static_cast<const RglBrdf&>(sampler.model());
            return py::dict("luminance"_a = bilinearArrays(rgl.luminanceWarp()),
                            "vndf"_a = bilinearArrays(rgl.vndfWarp()));
          },
          "The two warps it samples (luminance, then vndf), for sampling them in other arithmetic (acdf.mitsuba's\n"
          "drjit arrays). Each is a dict: parameter_values, a list of two float32 arrays, the values of phi_o and\n"
          "of theta_o its slices are conditioned on (at omega_o, float32(atan2(y, x)) and float32(theta), rgl.h);\n"
          "density (slices, rows, columns), the slices' normalised vertex densities; row_cdf (slices, rows,\n"
          "columns), each vertex row's normalised CDF over its columns, 0 to 1; row_mass (slices, rows), each\n"
          "vertex row's mass; marginal (slices, rows), the normalised CDF over the row strips, 0 to 1; all float32\n"
          "as stored. Slices are row-major over the parameters' values (theta_o's fastest); vertex (r, c) lies at\n"
          "x = (r / (rows - 1), c / (columns - 1)), x[0] along the rows. Sampling, density and inversion blend the\n"
          "2 x 2 slices around omega_o's parameters as libsampling's bilinear_2d.h says.");
}

}  // namespace

void bindBrdf(py::module_& m) {
  bindModels(m);
  bindSamplers(m);
  m.def(
      "table_options",
      [] {
        const TabulatedBrdfOptions defaults;
        py::list options;
        for (const TableOption& option : tableOptionList())
          options.append(py::dict("key"_a = option.key, "type"_a = toString(option.type),
                                  "default"_a = option.get(defaults), "help"_a = option.help));
        return options;
      },
      "TabulatedBrdfSampler's table options, as the scene format's \"table\" keys and the CLI's flags name them: "
      "a list of dicts with key, type (count, number, boolean or name), default (as text) and help.");
}

}  // namespace acdf::python

// envmap in Python: lat-long environment maps and the environment light with its strategies.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/environment_map.h"
#include "arrays.h"
#include "bindings.h"
#include "options.h"

namespace acdf::python {

using namespace pybind11::literals;

namespace {

// A (height, width) or (height, width, 3) array of per-pixel values.
template <class T>
py::array_t<T> image(const EnvironmentMap& map, const T* data, std::size_t channels) {
  std::vector<py::ssize_t> shape{map.height(), map.width()};
  if (channels > 1) shape.push_back(static_cast<py::ssize_t>(channels));
  py::array_t<T> out(shape);
  std::memcpy(out.mutable_data(), data, std::size_t{map.width()} * map.height() * channels * sizeof(T));
  return out;
}

std::shared_ptr<EnvironmentMap> mapFromArray(const ArrayArg& rgbArg) {
  const Array<float> rgb = numbers<float>(rgbArg, "rgb", "of shape (height, width, 3)");
  if (rgb.ndim() != 3 || rgb.shape(2) != 3)
    throw py::value_error("rgb: expected shape (height, width, 3), got " + shapeText(rgb));
  std::vector<float> values(rgb.data(), rgb.data() + rgb.size());
  return std::make_shared<EnvironmentMap>(static_cast<uint32_t>(rgb.shape(1)), static_cast<uint32_t>(rgb.shape(0)),
                                          std::move(values));
}

// The local strategy's normal grid and block size, as the scene format names them.
struct LocalGrid {
  uint32_t normalRows, normalColumns, blockSize;
};

// One coordinate triple of a portal: three finite or not numbers (validate() judges them).
Vec3d portalVector(const py::handle& portal, const char* key, std::size_t i) {
  const std::string where = "portals[" + std::to_string(i) + "]." + key;
  try {
    const auto v = py::cast<std::array<double, 3>>(portal[key]);
    return {v[0], v[1], v[2]};
  } catch (const py::error_already_set& e) {
    if (!e.matches(PyExc_KeyError)) throw;
    throw py::value_error("portals[" + std::to_string(i) + "]: needs corner, edge_u and edge_v");
  } catch (const py::cast_error&) {
    throw py::value_error(where + ": expected 3 numbers");
  }
}

// Portals as scene files write them: a list of {"corner": [x, y, z], "edge_u": [...], "edge_v":
// [...]}, world frame; whether they can be used is validate()'s to say.
std::vector<Portal> portalsOf(const std::optional<py::sequence>& portals) {
  std::vector<Portal> out;
  if (!portals) return out;
  for (std::size_t i = 0; i < portals->size(); ++i) {
    const py::object portal = (*portals)[i];
    if (!py::isinstance<py::dict>(portal))
      throw py::value_error("portals[" + std::to_string(i) + "]: expected a dict with corner, edge_u and edge_v");
    for (const auto& [key, value] : py::cast<py::dict>(portal))
      if (const auto name = py::cast<std::string>(py::str(key)); name != "corner" && name != "edge_u" && name != "edge_v")
        throw py::value_error("portals[" + std::to_string(i) + "]: unknown key " + name);
    out.push_back({portalVector(portal, "corner", i), portalVector(portal, "edge_u", i),
                   portalVector(portal, "edge_v", i)});
  }
  return out;
}

EnvironmentLight makeLight(std::shared_ptr<EnvironmentMap> map, const std::string& strategy, float scale,
                           double rotationDegrees, std::optional<double> epsilon,
                           const std::optional<SimplifyOptions>& simplify, const LocalGrid& grid,
                           std::vector<Portal> portals) {
  EnvironmentLightOptions options;
  options.portals = std::move(portals);
  options.local = {grid.normalRows, grid.normalColumns, grid.blockSize};
  options.strategy = parseEnvironmentSampling(strategy);
  options.simplify = simplifyOptions(options.simplify, simplify, epsilon);
  options.scale = scale;
  if (!std::isfinite(rotationDegrees)) throw py::value_error("rotation: must be finite");
  if (rotationDegrees != 0.0) options.worldFromMap = Rotation::aboutY(rotationDegrees * std::numbers::pi / 180.0);
  validate(options);
  py::gil_scoped_release release;
  return EnvironmentLight(std::move(map), options);
}

// The context of row i: the normal and the position of that row (or the only one), if any.
struct Contexts {
  bool allowIncomplete;
  std::optional<Directions> normals;
  std::optional<Batch<double>> positions;
  LightSampleContext operator()(std::size_t i) const {
    LightSampleContext c{.allowIncompletePdf = allowIncomplete};
    if (normals) c.normal = (*normals)[i];
    if (positions) c.position = vec3At(positions->data, positions->rows, i);
    return c;
  }
};

// Alias tables of one size laid end to end (table t's slot j at t x size + j), as alias_arrays documents.
py::dict aliasArrays(std::span<const AliasTable* const> tables) {
  const std::size_t slots = tables.front()->size();
  auto acceptance = output<float>(tables.size() * slots), probability = output<float>(tables.size() * slots);
  auto alias = output<uint32_t>(tables.size() * slots);
  float *as = acceptance.mutable_data(), *ps = probability.mutable_data();
  uint32_t* is = alias.mutable_data();
  for (std::size_t t = 0; t < tables.size(); ++t) {
    for (uint32_t j = 0; j < slots; ++j) {
      const std::size_t at = t * slots + j;
      as[at] = tables[t]->acceptance(j);
      is[at] = tables[t]->alias(j);
      ps[at] = tables[t]->probability(j);
    }
  }
  return py::dict("acceptance"_a = acceptance, "alias"_a = alias, "probability"_a = probability);
}

// One row, or one per sample.
void requireRowsFor(std::size_t rows, std::size_t n, const std::string& name) {
  pairedRows(n, rows, (name + " and the samples").c_str());
  if (rows != 1 && rows != n) throw py::value_error(name + ": one row or one per sample");
}

Contexts contextsOf(bool allowIncomplete, const std::optional<ArrayArg>& normal, const std::optional<ArrayArg>& position,
                    std::size_t n) {
  Contexts c{allowIncomplete, std::nullopt, std::nullopt};
  if (normal) {
    c.normals = directions(*normal, "normal");
    requireRowsFor(c.normals->rows(), n, "normal");
  }
  if (position) {
    c.positions = batch<double>(*position, 3, "position", true);
    requireRowsFor(c.positions->rows, n, "position");
    for (std::size_t i = 0; i < 3 * c.positions->rows; ++i)
      if (!std::isfinite(c.positions->data[i])) throw py::value_error("position: must be finite");
  }
  return c;
}

const char* kLightDoc = R"(An environment map placed in the world and sampled by one strategy.

EnvironmentLight(map, strategy="adaptive", scale=1.0, rotation=0.0, epsilon=None, simplify=None,
                 normal_rows=32, normal_columns=64, block_size=16, portals=None)
EnvironmentLight.load(path, ...the same keywords)

map: an acdf.EnvironmentMap. strategy: a name of acdf.environment_samplings(), which says what each
samples ("compensated" and "local-compensated" are incomplete, see allow_incomplete_pdf; "local" and
"local-compensated" are conditioned on the surface normal). scale multiplies the radiance;
rotation turns the map about +Y (degrees, counter-clockwise seen from above), as in scene files.

Directions are world-frame float64 (n, 3) arrays (+Y up); pdfs are per steradian (float64),
radiance is RGB float32 (n, 3). A sample's pdf is what pdf() returns for its direction.
allow_incomplete_pdf=True: the caller also samples the BSDF and combines the two by MIS, so a
compensated light may leave directions dimmer than the map's mean to it (pdf 0 there).
strategy="local" samples L(w) max(0, n.w) for the shading normal n each call gives (normal=...),
from a grid of normal_rows x normal_columns normal cells over blocks of block_size^2 pixels (Lawrence
et al. 2005; a normal cell's table is built when a normal in it is first used).
portals: windows or doors the map is seen through, as scene files declare them: a list of
{"corner": [x, y, z], "edge_u": [...], "edge_v": [...]} (world frame, edges perpendicular), each
letting light through towards the side edge_u x edge_v points to. From a point on that side
(position=...) portal_share(allow_incomplete_pdf) of the samples go through the portals (all of
them under allow_incomplete_pdf: the rest of the sphere is left to BSDF samples), with the map's
importance inside each (its table over the directions leaving through it, portal_arrays()); pdf()
is the mixture. Calls without a position sample as without portals.)";

void bindLight(py::module_& m) {
  m.def(
      "environment_samplings",
      [] {
        py::list strategies;
        for (EnvironmentSampling s : kEnvironmentSamplings)
          strategies.append(py::dict("name"_a = std::string(toString(s)), "description"_a = std::string(describe(s))));
        return strategies;
      },
      "Every strategy of EnvironmentLight: a list of dicts with its name and a one-line description.");
  m.def(
      "portal_problem",
      [](const py::dict& portal) -> std::optional<std::string> {
        py::list one;
        one.append(portal);
        return portalProblem(portalsOf(one).front());
      },
      "portal"_a,
      "Why a portal ({\"corner\", \"edge_u\", \"edge_v\"}, as EnvironmentLight takes them) cannot be used, or\n"
      "None: the check EnvironmentLight and scene files make.");
  py::class_<EnvironmentLight> c(m, "EnvironmentLight", kLightDoc);
  const LocalEnvironmentOptions d;
  c.def(py::init([](std::shared_ptr<EnvironmentMap> map, const std::string& strategy, float scale, double rotation,
                    std::optional<double> epsilon, const std::optional<SimplifyOptions>& simplify, uint32_t normalRows,
                    uint32_t normalColumns, uint32_t blockSize, const std::optional<py::sequence>& portals) {
          return makeLight(std::move(map), strategy, scale, rotation, epsilon, simplify,
                           {normalRows, normalColumns, blockSize}, portalsOf(portals));
        }),
        "map"_a, "strategy"_a = "adaptive", "scale"_a = 1.0f, "rotation"_a = 0.0, "epsilon"_a = py::none(),
        "simplify"_a = py::none(), "normal_rows"_a = d.normalRows, "normal_columns"_a = d.normalColumns,
        "block_size"_a = d.blockSize, "portals"_a = py::none());
  c.def_static(
      "load",
      [](const std::string& path, const std::string& strategy, float scale, double rotation,
         std::optional<double> epsilon, const std::optional<SimplifyOptions>& simplify, uint32_t normalRows,
         uint32_t normalColumns, uint32_t blockSize, const std::optional<py::sequence>& portals) {
        std::vector<Portal> portalList = portalsOf(portals);
        std::shared_ptr<EnvironmentMap> map;
        {
          py::gil_scoped_release release;
          map = std::make_shared<EnvironmentMap>(EnvironmentMap::load(path));
        }
        return makeLight(std::move(map), strategy, scale, rotation, epsilon, simplify,
                         {normalRows, normalColumns, blockSize}, std::move(portalList));
      },
      "path"_a, "strategy"_a = "adaptive", "scale"_a = 1.0f, "rotation"_a = 0.0, "epsilon"_a = py::none(),
      "simplify"_a = py::none(), "normal_rows"_a = d.normalRows, "normal_columns"_a = d.normalColumns,
      "block_size"_a = d.blockSize, "portals"_a = py::none(), "Reads a lat-long image (OpenEXR, HDR, ...; acdf.FileError if it cannot).");
  c.def(
      "sample",
      [](const EnvironmentLight& light, const ArrayArg& u, const std::optional<ArrayArg>& normal,
         const std::optional<ArrayArg>& position, bool allowIncomplete) {
        const Batch<float> variates = batch<float>(u, 2, "u");
        const std::size_t n = variates.rows;
        const Contexts context = contextsOf(allowIncomplete, normal, position, n);
        auto dirs = output<double>(n, 3), pdf = output<double>(n);
        auto radiance = output<float>(n, 3);
        const float* in = variates.data;
        double *ds = dirs.mutable_data(), *ps = pdf.mutable_data();
        float* rs = radiance.mutable_data();
        forEachRow(n, [&](std::size_t i) {
          const LightSample s = light.sample(context(i), in[2 * i], in[2 * i + 1]);
          storeVec3(ds, i, s.direction);
          storeRgb(rs, i, s.radiance);
          ps[i] = s.pdf;
        });
        return py::make_tuple(dirs, radiance, pdf);
      },
      "u"_a, "normal"_a = py::none(), "position"_a = py::none(), "allow_incomplete_pdf"_a = false,
      "Samples for variates u of shape (n, 2): (dirs (n, 3), radiance (n, 3), pdf (n,)). pdf is 0 only\n"
      "for a light that emits nothing (then there is no sample). normal: the shading normals (world\n"
      "frame, (n, 3) or one (3,)) the local strategy samples L(w) max(0, n.w) for; without them a local\n"
      "light samples its adaptive table. position: the points lit (world frame, (n, 3) or one (3,)),\n"
      "which the portals are seen from; without them no portal is used. pdf() must be given the same\n"
      "normals and positions.");
  c.def(
      "pdf",
      [](const EnvironmentLight& light, const ArrayArg& dirs, const std::optional<ArrayArg>& normal,
         const std::optional<ArrayArg>& position, bool allowIncomplete) {
        const Directions w = directions(dirs, "dirs");
        const Contexts context = contextsOf(allowIncomplete, normal, position, w.rows());
        auto pdf = output<double>(w.rows());
        double* ps = pdf.mutable_data();
        forEachRow(w.rows(), [&](std::size_t i) { ps[i] = light.pdf(context(i), w[i]); });
        return pdf;
      },
      "dirs"_a, "normal"_a = py::none(), "position"_a = py::none(), "allow_incomplete_pdf"_a = false,
      "Density per steradian of sample() at each direction, shape (n,) (with the same normals and\n"
      "positions).");
  c.def(
      "eval",
      [](const EnvironmentLight& light, const ArrayArg& dirs) {
        const Directions w = directions(dirs, "dirs");
        auto radiance = output<float>(w.rows(), 3);
        float* rs = radiance.mutable_data();
        forEachRow(w.rows(), [&](std::size_t i) { storeRgb(rs, i, light.eval(w[i])); });
        return radiance;
      },
      "dirs"_a, "Radiance arriving from each direction (nearest pixel, times the scale), shape (n, 3).");
  c.def(
      "pixel_probabilities",
      [](const EnvironmentLight& light, bool allowIncomplete) {
        const EnvironmentTable& table = light.table({.allowIncompletePdf = allowIncomplete});
        const std::vector<double> p = table.pixelProbabilities();
        if (p.empty()) throw py::value_error("pixel_probabilities: this light has no table (uniform-sphere or black)");
        return image(light.map(), p.data(), 1);
      },
      "allow_incomplete_pdf"_a = false, "The probability the light's table gives each pixel (exact), (height, width).");
  c.def(
      "cascade_arrays",
      [](const EnvironmentLight& light, bool allowIncomplete) -> py::object {
        const Cascade* cascade = light.table({.allowIncompletePdf = allowIncomplete}).cascade();
        if (!cascade) return py::none();
        return cascadeArrays(*cascade);
      },
      "allow_incomplete_pdf"_a = false,
      "The cascade of a uniform, adaptive or compensated table (None for other strategies and a black map),\n"
      "for sampling it in other arithmetic (acdf.mitsuba's drjit arrays): one dict per axis (rows, then\n"
      "columns) of its 1D CDFs laid end to end: CDF k's breakpoints are [start[k], start[k + 1]), each a\n"
      "grid vertex (pixel edge) and the CDF's value there, from (0, 0) to (cells, 1). The CDF of the\n"
      "rows is CDF 0 of axis 0; below its interval j lies CDF j of axis 1. The density on the unit square\n"
      "is the product over axes of (value step) / (vertex step / cells); per steradian, divide by\n"
      "width x height x the row's pixel solid angle.");
  c.def(
      "alias_arrays",
      [](const EnvironmentLight& light) -> py::object {
        const PixelAlias* alias = light.table({}).alias();
        if (!alias) return py::none();
        const AliasTable* rows[] = {&alias->rows()};
        std::vector<const AliasTable*> columns(alias->rows().size());
        for (uint32_t r = 0; r < columns.size(); ++r) columns[r] = &alias->columns(r);
        return py::dict("rows"_a = aliasArrays(rows), "columns"_a = aliasArrays(columns));
      },
      "The alias tables of an alias light (None for other strategies and a black map), for sampling them in\n"
      "other arithmetic (acdf.mitsuba's drjit arrays): rows, the table of the map's rows, and columns, every\n"
      "row's table of its columns end to end (row r's slot j at r x width + j); each a dict of per-slot arrays\n"
      "acceptance (float32), alias (uint32) and probability (float32, of the slot's own cell). A table of n\n"
      "slots takes a variate u in [0, 1) to slot i = min(floor(u n), n - 1) with fraction f = u n - i (in\n"
      "double) and keeps cell i if f < acceptance[i], remapping f to f / acceptance[i], else takes cell\n"
      "alias[i], remapping f to (f - acceptance[i]) / (1 - acceptance[i]); the remapped fraction is rounded to\n"
      "float32, at most the largest float below 1. u0 draws the row, u1 a column of that row; the two remapped\n"
      "fractions are the position in the pixel (down, right). A pixel's probability is the product of its\n"
      "row's and its column's, in double; per steradian, divide by the row's pixel solid angle.");
  c.def(
      "hierarchical_arrays",
      [](const EnvironmentLight& light) -> py::object {
        const HierarchicalWarp2D* warp = light.table({}).hierarchical();
        if (!warp) return py::none();
        py::list levels;
        for (std::size_t k = 0; k < warp->levels(); ++k) {
          const std::span<const float> blocks = warp->blocks(k);
          auto masses = output<float>(blocks.size());
          std::copy(blocks.begin(), blocks.end(), masses.mutable_data());
          levels.append(py::dict("parent_columns"_a = warp->parentColumns(k), "blocks"_a = masses));
        }
        return levels;
      },
      "The mip pyramid of a hierarchical light (None for other strategies and a black map), for sampling it\n"
      "in other arithmetic (acdf.mitsuba's drjit arrays): its levels from the map's pixels (level 0) up to the\n"
      "four children of the 1 x 1 top, each a dict of parent_columns (nodes per row of the level above) and\n"
      "blocks (float32): the masses of each node's four children (top-left, top-right, bottom-left,\n"
      "bottom-right; 0 for one past the grid's edge), node (r, c) of the level above at 4 (r parent_columns +\n"
      "c). The descent starts at the top's node (0, 0) with the variates u0, u1 in double. At a node whose\n"
      "children have masses a b / c d it takes the bottom row if u0 >= p = (a + b) / (a + b + c + d), the sums\n"
      "in double, and rescales u0 to u0 / p, else to (u0 - p) / ((c + d) / (a + b + c + d)); then u1 chooses\n"
      "the right column of that row the same way from its two masses; each rescaled variate is at most the\n"
      "largest double below 1. The child taken, (2 r + bottom, 2 c + right), is the node on the level below.\n"
      "At level 0 the variates left are the position in the pixel (down, right) and the pixel's probability\n"
      "is its mass there; per steradian, divide by the row's pixel solid angle.");
  c.def(
      "local_arrays",
      [](const EnvironmentLight& light) -> py::object {
        const LocalEnvironmentTable* local = light.localTable();
        if (!local || !local->pixelTable()) return py::none();
        std::vector<const Cascade*> cells(local->slices());
        {
          py::gil_scoped_release release;
          local->buildAll();
          for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = &local->blocksOfCell(i);
        }
        const Cascade& pixels = *local->pixelTable();
        auto distributions = output<uint32_t>(pixels.slices());
        uint32_t* ds = distributions.mutable_data();
        for (std::size_t s = 0; s < pixels.slices(); ++s) ds[s] = static_cast<uint32_t>(pixels.distributionOf(s));
        const LocalEnvironmentOptions& o = local->options();
        return py::dict("normal_rows"_a = o.normalRows, "normal_columns"_a = o.normalColumns,
                        "block_height"_a = local->blockHeight(), "block_width"_a = local->blockWidth(),
                        "blocks"_a = cascadeArrays(cells), "pixels"_a = cascadeArrays(pixels),
                        "pixel_distributions"_a = distributions);
      },
      "The tables of a local or local-compensated light's calls with a normal (None for other strategies and\n"
      "a black map), every normal cell's built, for sampling them in other arithmetic (acdf.mitsuba's drjit\n"
      "arrays); the map frame's normal cells are the pixels of a normal_columns x normal_rows lat-long grid,\n"
      "row-major. blocks: P(block | normal cell) as cascade_arrays lays out a cascade, the cells' cascades\n"
      "(over the grid of block_height x block_width-pixel blocks, the last ones partial) end to end: CDF k of\n"
      "axis 0 is normal cell k's. pixels: P(pixel | block), block b (row-major) sampling first-level CDF\n"
      "pixel_distributions[b] over its rows, then its columns. The density per steradian is the product of\n"
      "the two tables' (each as cascade_arrays says) over blocks x block_height x block_width x the row's\n"
      "pixel solid angle.");
  c.def(
      "portal_arrays",
      [](const EnvironmentLight& light) {
        auto copied = [](auto values) {
          auto out = output<typename decltype(values)::value_type>(values.size());
          std::copy(values.begin(), values.end(), out.mutable_data());
          return out;
        };
        auto vector = [](const Vec3d& v) { return py::make_tuple(v.x, v.y, v.z); };
        py::list portals;
        for (std::size_t i = 0; i < light.options().portals.size(); ++i) {
          const PortalTable& portal = light.portalTable(i);
          const WindowedTable2D& t = portal.table();
          portals.append(py::dict(
              "corner"_a = vector(portal.corner()), "axis_u"_a = vector(portal.axisU()),
              "axis_v"_a = vector(portal.axisV()), "normal"_a = vector(portal.normal()),
              "length_u"_a = portal.lengthU(), "length_v"_a = portal.lengthV(), "min_power"_a = portal.minPower(),
              "column_vertices"_a = copied(t.columnVertices()), "row_vertices"_a = copied(t.rowVertices()),
              "coarse_column_of_fine"_a = copied(t.coarseColumnOfFine()),
              "coarse_row_of_fine"_a = copied(t.coarseRowOfFine()), "density"_a = copied(t.coarseDensity()),
              "summed_area"_a = copied(t.summedArea()), "row_integral"_a = copied(t.rowIntegral())));
        }
        return portals;
      },
      "Per portal (world frame), its table over the square of directions leaving through it (acdf's\n"
      "PortalTable, WindowedTable2D): the frame (corner, unit axis_u, axis_v, normal into the room, the\n"
      "edges' lengths), the least power a view is sampled with (min_power), the coarse grid's\n"
      "vertices along a and b, the coarse cell of each fine cell along each axis, the coarse density\n"
      "(row-major, rows along b), the summed-area table at the vertices ((rows + 1) x (columns + 1))\n"
      "and each row's running integral along a (rows x (columns + 1)). For sampling the portals in\n"
      "other arithmetic (acdf.mitsuba's drjit arrays).");
  c.def_static(
      "portal_share",
      [](bool allowIncomplete) { return EnvironmentLight::portalShare({.allowIncompletePdf = allowIncomplete}); },
      "allow_incomplete_pdf"_a = false,
      "The share of the samples drawn through the portals from a point that sees one: 1 where the caller\n"
      "combines the light with BSDF samples by MIS (allow_incomplete_pdf), else 0.9 (the table keeps the\n"
      "mixture complete).");
  c.def_property_readonly("strategy",
                          [](const EnvironmentLight& l) { return std::string(toString(l.options().strategy)); });
  c.def_property_readonly("bytes", &EnvironmentLight::tableBytes, "Bytes of the tables the light holds.");
  c.def_property_readonly("emits_nothing", &EnvironmentLight::emitsNothing);
  c.def_property_readonly(
      "map", [](const EnvironmentLight& l) -> const EnvironmentMap& { return l.map(); },
      py::return_value_policy::reference_internal);
}

void bindMap(py::module_& m) {
  py::class_<EnvironmentMap, std::shared_ptr<EnvironmentMap>> c(m, "EnvironmentMap", R"(A lat-long HDR environment map.

EnvironmentMap(rgb): rgb of shape (height, width, 3), row 0 the top scanline (theta = 0, +Y),
column j at phi = 2 pi (j + 0.5) / width, as OpenEXR's LatLong layout.
EnvironmentMap.load(path): OpenEXR, or any image OpenImageIO reads where acdf is built with it
(acdf.FileError if it cannot).)");
  c.def(py::init(&mapFromArray), "rgb"_a);
  c.def_static(
      "load",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return std::make_shared<EnvironmentMap>(EnvironmentMap::load(path));
      },
      "path"_a);
  c.def_property_readonly("width", &EnvironmentMap::width);
  c.def_property_readonly("height", &EnvironmentMap::height);
  c.def_property_readonly(
      "rgb", [](const EnvironmentMap& map) { return image(map, map.rgb().data(), 3); },
      "The pixels, (height, width, 3) float32 (a copy).");
  c.def(
      "pixel_power", [](const EnvironmentMap& map) { return image(map, map.pixelPower().data(), 1); },
      "Luminance x solid angle per pixel, (height, width): what the tables are built from.");
  c.def_property_readonly("is_black", &EnvironmentMap::isBlack);
  c.def_property_readonly(
      "declared_chromaticities",
      [](const EnvironmentMap& map) -> py::object {
        const auto& c = map.declaredChromaticities();
        if (!c) return py::none();
        return py::dict(
            "red"_a = py::make_tuple(c->red[0], c->red[1]), "green"_a = py::make_tuple(c->green[0], c->green[1]),
            "blue"_a = py::make_tuple(c->blue[0], c->blue[1]), "white"_a = py::make_tuple(c->white[0], c->white[1]));
      },
      "The CIE xy of the primaries and white the file declared (OpenEXR's chromaticities), as a dict, or\n"
      "None. rgb is linear Rec. 709 / D65 either way: declared pixels were converted through XYZ without\n"
      "chromatic adaptation, as Mitsuba 3 reads them.");
}

}  // namespace

void bindEnvmap(py::module_& m) {
  bindMap(m);
  bindLight(m);
}

}  // namespace acdf::python

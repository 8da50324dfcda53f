// The scene file reader (docs/scene-format.md). Two phases: every field is read and checked
// into plain descriptions first, so a typo at the end of the file is reported before a
// 35 MB material is loaded; then the used materials, the shapes and the light are built.

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <span>
#include <sstream>

#include <fmt/format.h>
#include <tiny_obj_loader.h>
#include <nlohmann/json.hpp>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/brdf_sampler_factory.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/brdf/table_options.h"
#include "acdf/envmap/image_file.h"
#include "acdf/integrator/film.h"
#include "acdf/integrator/scene.h"
#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/transform.h"

namespace acdf {

namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

// A JSON value and where it sits in the file, for messages like "$.shapes[2].radius: ...".
class Node {
 public:
  Node(const Json& value, std::string path, const std::string& file)
      : value_(value), path_(std::move(path)), file_(file) {}

  [[noreturn]] void fail(const std::string& problem) const { throw FileError(file_, path_ + ": " + problem); }
  // `validate(options)` for options read from this object: a rejected option is reported at its
  // key when the scene gives it, else at the object.
  template <class Options>
  void validated(const Options& options) const {
    try {
      validate(options);
    } catch (const OptionError& e) {
      if (has(e.option())) (*this)[e.option()].fail(e.problem());
      fail(e.what());
    }
  }

  // An object whose keys are all among `allowed`.
  const Node& object(std::initializer_list<std::string_view> allowed) const {
    return object(std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  const Node& object(std::span<const std::string_view> allowed) const {
    if (!value_.is_object()) fail("expected an object, got " + typeName());
    for (const auto& item : value_.items()) {
      bool known = false;
      for (std::string_view k : allowed) known = known || item.key() == k;
      if (!known) {
        std::string list;
        for (std::string_view k : allowed) list += (list.empty() ? "" : ", ") + std::string(k);
        child(item.key()).fail("unknown key (expected one of: " + list + ")");
      }
    }
    return *this;
  }
  bool has(const std::string& key) const { return value_.contains(key); }
  bool isNumber() const { return value_.is_number(); }
  bool isString() const { return value_.is_string(); }
  Node operator[](const std::string& key) const {
    if (!value_.contains(key)) fail("missing key \"" + key + "\"");
    return child(key);
  }
  std::vector<Node> elements() const {
    if (!value_.is_array()) fail("expected an array, got " + typeName());
    std::vector<Node> out;
    for (std::size_t i = 0; i < value_.size(); ++i) out.emplace_back(value_[i], fmt::format("{}[{}]", path_, i), file_);
    return out;
  }
  std::vector<std::pair<std::string, Node>> members() const {
    if (!value_.is_object()) fail("expected an object, got " + typeName());
    std::vector<std::pair<std::string, Node>> out;
    for (const auto& item : value_.items()) out.emplace_back(item.key(), child(item.key()));
    return out;
  }

  double number() const {
    if (!value_.is_number()) fail("expected a number, got " + typeName());
    return value_.get<double>();
  }
  double positive() const {
    const double v = number();
    if (!(v > 0) || !std::isfinite(v)) fail("must be positive");
    return v;
  }
  uint32_t count(uint32_t minimum, uint32_t maximum = uint32_t{1} << 30) const {
    if (!value_.is_number_integer() && !value_.is_number_unsigned()) fail("expected an integer, got " + typeName());
    const auto v = value_.get<int64_t>();
    if (v < minimum || v > maximum)
      fail(fmt::format("must be an integer in [{}, {}]", minimum,
                       maximum == uint32_t{1} << 30 ? "2^30" : std::to_string(maximum)));
    return static_cast<uint32_t>(v);
  }
  bool boolean() const {
    if (!value_.is_boolean()) fail("expected true or false, got " + typeName());
    return value_.get<bool>();
  }
  std::string string() const {
    if (!value_.is_string()) fail("expected a string, got " + typeName());
    return value_.get<std::string>();
  }
  Vec3d vec3() const {
    if (!value_.is_array() || value_.size() != 3) fail("expected an array of 3 numbers, got " + typeName());
    const auto e = elements();
    const Vec3d v{e[0].number(), e[1].number(), e[2].number()};
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) fail("must be finite");
    return v;
  }
  // A number (gray) or [r, g, b]; each channel in [0, maximum]. In double, as written.
  std::array<double, 3> color(double maximum) const {
    std::array<double, 3> c;
    if (isNumber()) {
      c.fill(number());
    } else {
      const Vec3d v = vec3();
      c = {v.x, v.y, v.z};
    }
    for (double x : c)
      if (!(x >= 0 && x <= maximum)) fail(fmt::format("each channel must be in [0, {}]", maximum));
    return c;
  }
  // A file path, relative ones against the scene's directory.
  fs::path file(const fs::path& baseDir) const {
    const fs::path p = string();
    return (p.is_absolute() ? p : baseDir / p).lexically_normal();
  }
  // The same, which must exist (the loaders report finer problems, naming the file).
  fs::path existingFile(const fs::path& baseDir) const {
    const fs::path resolved = file(baseDir);
    requireFile(resolved, path_);
    return resolved;
  }
  static void requireFile(const fs::path& file, const std::string& where) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw FileError(file.string(), "no such file (referenced by " + where + ")");
  }
  template <class Parse>
  auto parsed(Parse parse) const {
    const std::string s = string();
    try {
      return parse(s);
    } catch (const std::invalid_argument& e) {
      fail(e.what());
    }
  }

  const std::string& path() const { return path_; }

 private:
  Node child(const std::string& key) const { return Node(value_.at(key), path_ + "." + key, file_); }
  std::string typeName() const {
    if (value_.is_null()) return "null";
    if (value_.is_boolean()) return "a boolean";
    if (value_.is_number()) return "a number";
    if (value_.is_string()) return "a string";
    if (value_.is_array()) return "an array";
    return "an object";
  }

  const Json& value_;
  std::string path_;
  const std::string& file_;
};

Transform readTransform(const Node& node) {
  node.object({"scale", "rotate", "translate"});
  Vec3d scale{1, 1, 1}, translation;
  Rotation rotation;
  if (node.has("scale")) {
    const Node s = node["scale"];
    if (s.isNumber()) {
      const double k = s.positive();
      scale = {k, k, k};
    } else {
      scale = s.vec3();
      if (!(scale.x > 0 && scale.y > 0 && scale.z > 0)) s.fail("scale factors must be positive");
    }
  }
  if (node.has("rotate")) {
    const Node r = node["rotate"];
    r.object({"axis", "degrees"});
    try {
      rotation = Rotation::aboutAxis(r["axis"].vec3(), r["degrees"].number() * std::numbers::pi / 180.0);
    } catch (const std::invalid_argument&) {
      r.fail("the axis must be non-zero");
    }
  }
  if (node.has("translate")) translation = node["translate"].vec3();
  return {scale, rotation, translation};
}

TriangleMesh readObj(const fs::path& path, const Node& node, const Transform& transform) {
  tinyobj::ObjReader reader;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  if (!reader.ParseFromFile(path.string(), config)) {
    std::string message = reader.Error();
    while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
    throw FileError(path.string(),
                    (message.empty() ? "cannot read the OBJ file" : message) + " (referenced by " + node.path() + ")");
  }
  TriangleMesh mesh;
  const auto& vertices = reader.GetAttrib().vertices;
  for (std::size_t i = 0; i + 2 < vertices.size(); i += 3)
    mesh.positions.push_back(transform.point({vertices[i], vertices[i + 1], vertices[i + 2]}));
  for (const auto& shape : reader.GetShapes()) {
    const auto& idx = shape.mesh.indices;
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      std::array<uint32_t, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const int v = idx[i + k].vertex_index;
        if (v < 0 || static_cast<std::size_t>(v) >= mesh.positions.size())
          throw FileError(path.string(), "a face refers to a vertex that does not exist");
        tri[k] = static_cast<uint32_t>(v);
      }
      mesh.triangles.push_back(tri);
    }
  }
  if (mesh.triangles.empty()) throw FileError(path.string(), "no faces (referenced by " + node.path() + ")");
  return mesh;
}

// A material's table options, and whether the scene chose the layout: a table of an isotropic
// model without one is isotropic (smaller, and of lower variance on every isotropic material
// measured, docs/performance.md), the 4D layout the paper's and the one of anisotropic models.
struct TableSpec {
  TabulatedBrdfOptions options;
  bool layoutGiven = false;

  TabulatedBrdfOptions forModel(const BrdfModel& model) const {
    TabulatedBrdfOptions o = options;
    if (!layoutGiven && model.isotropic()) o.layout = TabulatedBrdfOptions::Layout::Isotropic;
    return o;
  }
};

// The JSON value of a table option as the option's text (TableOption).
std::string tableOptionText(const Node& node, TableOption::Type type) {
  switch (type) {
    case TableOption::Type::Count: return std::to_string(node.count(0));
    case TableOption::Type::Number: return fmt::format("{}", node.number());
    case TableOption::Type::Boolean: return node.boolean() ? "true" : "false";
    case TableOption::Type::Name: return node.string();
  }
  node.fail("unknown option type");
}

TableSpec readTableOptions(const Node& node) {
  std::vector<std::string_view> keys;
  for (const TableOption& option : tableOptionList()) keys.push_back(option.key);
  node.object(keys);
  TableSpec spec;
  TabulatedBrdfOptions& o = spec.options;
  spec.layoutGiven = node.has("layout");
  for (const TableOption& option : tableOptionList()) {
    const std::string key(option.key);
    if (!node.has(key)) continue;
    const Node value = node[key];
    try {
      option.set(o, tableOptionText(value, option.type));
    } catch (const OptionError& e) {
      value.fail(e.problem());
    }
  }
  node.validated(o);
  if (!spec.layoutGiven) {  // the layout an isotropic model gets must be valid with them too
    TabulatedBrdfOptions isotropic = o;
    isotropic.layout = TabulatedBrdfOptions::Layout::Isotropic;
    node.validated(isotropic);
  }
  return spec;
}

// Material descriptions are read up front (to report every error early) and built on demand.
struct MaterialSpec {
  std::string path;              // JSON path, for messages
  std::optional<fs::path> file;  // the data file it needs, checked once the material is used
  std::function<std::shared_ptr<const BrdfSampler>(SceneAssets&)> build;
  bool measured = false;  // "type": "measured": its sampler is the BRDF sampling strategy's
};

MaterialSpec readMaterial(const Node& node, const fs::path& baseDir, const SceneOverrides& overrides) {
  const std::string type = node["type"].string();
  MaterialSpec spec{node.path(), std::nullopt, {}, type == "measured"};
  if (type == "diffuse") {
    node.object({"type", "albedo"});
    const std::array<double, 3> a = node["albedo"].color(1.0);
    const Rgb albedo{static_cast<float>(a[0]), static_cast<float>(a[1]), static_cast<float>(a[2])};
    spec.build = [albedo](SceneAssets&) {
      return std::make_shared<const CosineBrdfSampler>(std::make_shared<const LambertianBrdf>(albedo));
    };
  } else if (type == "measured") {
    node.object({"type", "file", "preset", "sampling", "interpolation", "table"});
    if (node.has("file") == node.has("preset"))
      node.fail("a measured material needs exactly one of \"file\" and \"preset\"");
    std::optional<fs::path> file;
    std::string preset;
    if (node.has("file")) {
      file = node["file"].file(baseDir);
      spec.file = file;
    } else {
      preset = node["preset"].string();
      try {
        (void)AnalyticBrdf::preset(preset);
      } catch (const std::invalid_argument& e) {
        node["preset"].fail(e.what());
      }
    }
    BrdfSampling sampling = BrdfSampling::Adaptive;
    if (node.has("sampling")) sampling = node["sampling"].parsed(parseBrdfSampling);
    if (overrides.bsdfSampling) sampling = *overrides.bsdfSampling;
    if (sampling == BrdfSampling::Native && !file)
      node.fail("rgl sampling needs an RGL .bsdf \"file\" (a preset is tabulated in the MERL layout)");
    MerlBrdf::Interpolation interpolation = MerlBrdf::Interpolation::Nearest;
    if (node.has("interpolation")) interpolation = node["interpolation"].parsed(parseInterpolation);
    const TableSpec table = node.has("table") ? readTableOptions(node["table"]) : TableSpec{};
    const std::string where = node.path();
    spec.build = [=](SceneAssets& tables) {
      if (!file) {
        const auto model = tables.merlPreset(preset, interpolation);
        return tables.brdfSampler(model, "preset " + preset, sampling, table.forModel(*model));
      }
      try {
        const auto model = tables.measuredFile(*file, interpolation);
        return tables.brdfSampler(model, file->string(), sampling, table.forModel(*model));
      } catch (const FileError& e) {
        throw FileError(e.file(), e.problem() + " (referenced by " + where + ")");
      } catch (const std::invalid_argument& e) {  // rgl sampling of a MERL file
        throw FileError(file->string(), e.what() + std::string(" (referenced by ") + where + ")");
      }
    };
  } else if (type == "ggx-conductor") {
    node.object({"type", "preset", "alpha", "f0"});
    std::shared_ptr<const AnalyticBrdf> brdf;
    if (node.has("preset")) {
      if (node.has("alpha") || node.has("f0")) node.fail("give either \"preset\" or \"alpha\" and \"f0\"");
      try {
        brdf = std::make_shared<const AnalyticBrdf>(AnalyticBrdf::preset(node["preset"].string()));
      } catch (const std::invalid_argument& e) {
        node["preset"].fail(e.what());
      }
      if (brdf->kind() != AnalyticBrdf::Kind::Conductor) node["preset"].fail("not a conductor preset");
    } else {
      const double alpha = node["alpha"].positive();
      brdf = std::make_shared<const AnalyticBrdf>(AnalyticBrdf::conductor(alpha, node["f0"].color(1.0)));
    }
    spec.build = [brdf](SceneAssets&) { return makeBrdfSampler(brdf, BrdfSampling::Native); };
  } else {
    node["type"].fail("unknown material type \"" + type + "\" (diffuse, measured or ggx-conductor)");
  }
  return spec;
}

// The environment: its map (file or constant) and how it is placed and sampled.
struct EnvironmentSpec {
  std::optional<fs::path> file;
  std::array<double, 3> constant{1.0, 1.0, 1.0};
  EnvironmentLightOptions options;
};

EnvironmentSpec readEnvironment(const Node& node, const fs::path& baseDir) {
  EnvironmentSpec spec;
  const std::string type = node["type"].string();
  if (type == "map") {
    node.object({"type", "file", "scale", "rotation", "sampling", "epsilon", "normal_rows", "normal_columns",
                 "block_size", "portals"});
    spec.file = node["file"].existingFile(baseDir);
  } else if (type == "constant") {
    node.object({"type", "radiance", "sampling", "portals"});
    spec.constant = node["radiance"].color(1e30);
  } else {
    node["type"].fail("unknown environment type \"" + type + "\" (map or constant)");
  }
  EnvironmentLightOptions& o = spec.options;
  o.strategy = kSceneEnvironmentSampling;
  if (node.has("scale")) {
    const double scale = node["scale"].positive();
    // The light scales float radiance.
    if (!std::isfinite(static_cast<float>(scale))) node["scale"].fail("must be at most 3.4e38");
    o.scale = static_cast<float>(scale);
  }
  if (node.has("rotation")) o.worldFromMap = Rotation::aboutY(node["rotation"].number() * std::numbers::pi / 180.0);
  if (node.has("sampling")) o.strategy = node["sampling"].parsed(parseEnvironmentSampling);
  if (node.has("epsilon")) o.simplify.epsilon = node["epsilon"].number();
  if (node.has("normal_rows")) o.local.normalRows = node["normal_rows"].count(1);
  if (node.has("normal_columns")) o.local.normalColumns = node["normal_columns"].count(1);
  if (node.has("block_size")) o.local.blockSize = node["block_size"].count(1);
  if (node.has("portals")) {
    for (const Node& p : node["portals"].elements()) {
      p.object({"corner", "edge_u", "edge_v"});
      const Portal portal{p["corner"].vec3(), p["edge_u"].vec3(), p["edge_v"].vec3()};
      if (const std::optional<std::string> problem = portalProblem(portal)) p.fail(*problem);
      o.portals.push_back(portal);
    }
  }
  node.validated(o);
  return spec;
}

// The light, with the tables the calls of `pdfs` use.
std::unique_ptr<EnvironmentLight> buildEnvironment(const EnvironmentSpec& spec, LightPdfs pdfs, SceneAssets& tables,
                                                   const std::string& where) {
  std::shared_ptr<const EnvironmentMap> map;
  std::string key;
  if (spec.file) {
    try {
      map = tables.environmentMap(*spec.file);
    } catch (const FileError& e) {
      throw FileError(e.file(), e.problem() + " (referenced by " + where + ")");
    }
    key = spec.file->string();
  } else {
    // A constant as a small uniform map: every table strategy applies to it as to a real map.
    constexpr uint32_t kWidth = 16, kHeight = 8;
    std::vector<float> rgb;
    for (uint32_t i = 0; i < kWidth * kHeight; ++i)
      rgb.insert(rgb.end(), {static_cast<float>(spec.constant[0]), static_cast<float>(spec.constant[1]),
                             static_cast<float>(spec.constant[2])});
    map = std::make_shared<const EnvironmentMap>(kWidth, kHeight, std::move(rgb));
    key = fmt::format("constant ({}, {}, {})", spec.constant[0], spec.constant[1], spec.constant[2]);
  }
  auto light = std::make_unique<EnvironmentLight>(map, spec.options, pdfs,
                                                  [&](EnvironmentTableStrategy strategy, const SimplifyOptions& simplify) {
                                                    return tables.environmentTable(map, key, strategy, simplify);
                                                  });
  tables.recordPortalTables(*light, key);
  return light;
}

}  // namespace

namespace {
constexpr EnumName<MisMode> kMisModeNames[] = {
    {MisMode::Power, "power"},
    {MisMode::Balance, "balance"},
    {MisMode::BsdfOnly, "bsdf-only"},
    {MisMode::LightOnly, "light-only"},
};
constexpr EnumName<DirectLighting> kDirectLightingNames[] = {{DirectLighting::Mis, "mis"},
                                                             {DirectLighting::Product, "product"}};
constexpr EnumName<GuidingMode> kGuidingModeNames[] = {
    {GuidingMode::Off, "off"}, {GuidingMode::Light, "light"}, {GuidingMode::Paths, "paths"},
    {GuidingMode::Auto, "auto"}};
constexpr EnumName<PortalSource> kPortalSourceNames[] = {
    {PortalSource::Auto, "auto"}, {PortalSource::Declared, "declared"}, {PortalSource::None, "none"}};
constexpr EnumName<LightPathMode> kLightPathModeNames[] = {
    {LightPathMode::Auto, "auto"}, {LightPathMode::On, "on"}, {LightPathMode::Off, "off"}};
}  // namespace

std::string branchesName(uint32_t branches) {
  return branches == kAutoBranches ? "auto" : std::to_string(branches);
}

uint32_t parseBranches(std::string_view name) {
  if (name == "auto") return kAutoBranches;
  uint32_t branches = 0;
  const auto [end, error] = std::from_chars(name.data(), name.data() + name.size(), branches);
  if (error != std::errc{} || end != name.data() + name.size() || branches < 1 || branches > kMaxBranches)
    throw std::invalid_argument(fmt::format("unknown branch count '{}' (auto or an integer in [1, {}])", name,
                                            kMaxBranches));
  return branches;
}

std::string_view toString(PortalSource source) { return nameOf(kPortalSourceNames, source); }

PortalSource parsePortalSource(std::string_view name) { return valueNamed(kPortalSourceNames, name, "portal source"); }

std::string_view toString(LightPathMode mode) { return nameOf(kLightPathModeNames, mode); }

LightPathMode parseLightPathMode(std::string_view name) {
  return valueNamed(kLightPathModeNames, name, "light path mode");
}

std::string_view toString(GuidingMode mode) { return nameOf(kGuidingModeNames, mode); }

GuidingMode parseGuidingMode(std::string_view name) { return valueNamed(kGuidingModeNames, name, "guiding mode"); }

std::string_view toString(MisMode mode) { return nameOf(kMisModeNames, mode); }

MisMode parseMisMode(std::string_view name) { return valueNamed(kMisModeNames, name, "MIS mode"); }

std::string_view toString(DirectLighting direct) { return nameOf(kDirectLightingNames, direct); }

DirectLighting parseDirectLighting(std::string_view name) {
  return valueNamed(kDirectLightingNames, name, "direct lighting");
}

Scene loadScene(const fs::path& file, const SceneOverrides& overrides, SceneAssets& tables) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw FileError(file.string(), fs::exists(file, ec) ? "not a regular file" : "no such file");
  std::ifstream in(file);
  if (!in) throw FileError(file.string(), "cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  return loadSceneText(text.str(), file, overrides, tables);
}

Scene loadSceneText(const std::string& text, const fs::path& file, const SceneOverrides& overrides,
                    SceneAssets& tables) {
  const std::string name = file.string();
  const fs::path baseDir = file.parent_path();
  Json json;
  try {
    json = Json::parse(text);
  } catch (const Json::exception& e) {  // a syntax error, or a number beyond double (out_of_range 406)
    throw FileError(name, std::string("invalid JSON: ") + e.what());
  }
  const Node root(json, "$", name);
  root.object({"camera", "render", "environment", "materials", "shapes"});

  // ---- Read and check everything ----
  Scene scene;
  RenderSettings& settings = scene.settings;
  if (root.has("render")) {
    const Node r = root["render"];
    r.object({"spp", "seed", "max_depth", "roulette_depth", "mis", "branches", "sampler", "direct", "candidates",
              "bsdf_fraction", "guiding", "portals", "light_paths"});
    if (r.has("spp")) settings.spp = r["spp"].count(1);
    if (r.has("seed")) settings.seed = r["seed"].count(0);
    if (r.has("max_depth")) settings.maxDepth = r["max_depth"].count(1);
    if (r.has("roulette_depth")) settings.rouletteDepth = r["roulette_depth"].count(1);
    if (r.has("mis")) settings.mis = r["mis"].parsed(parseMisMode);
    if (r.has("branches")) {
      const Node branches = r["branches"];
      settings.branches = branches.isString() ? branches.parsed(parseBranches) : branches.count(1, kMaxBranches);
    }
    if (r.has("sampler")) settings.sampler = r["sampler"].parsed(parseSamplerKind);
    if (r.has("direct")) settings.direct = r["direct"].parsed(parseDirectLighting);
    if (r.has("candidates")) settings.product.candidates = r["candidates"].count(1);
    if (r.has("bsdf_fraction")) settings.product.bsdfFraction = r["bsdf_fraction"].number();
    if (r.has("guiding")) settings.guiding = r["guiding"].parsed(parseGuidingMode);
    if (r.has("portals")) settings.portals = r["portals"].parsed(parsePortalSource);
    if (r.has("light_paths")) settings.lightPaths = r["light_paths"].parsed(parseLightPathMode);
    r.validated(settings.product);
  }
  if (overrides.mis) settings.mis = *overrides.mis;
  if (overrides.direct) settings.direct = *overrides.direct;
  if (overrides.candidates) settings.product.candidates = *overrides.candidates;
  if (overrides.branches) settings.branches = *overrides.branches;
  if (overrides.guiding) settings.guiding = *overrides.guiding;
  if (overrides.portals) settings.portals = *overrides.portals;
  if (overrides.lightPaths) settings.lightPaths = *overrides.lightPaths;
  if (settings.guiding == GuidingMode::Light && !drawsLightSamples(settings))
    throw FileError(name, settings.direct == DirectLighting::Product
                              ? "$.render.guiding: 'light' guides light samples, which product direct lighting does "
                                "not draw (guiding 'paths', or direct 'mis')"
                              : "$.render.guiding: 'light' guides light samples, which mis 'bsdf-only' does not draw "
                                "(guiding 'paths', or another mis)");
  if (overrides.sampler) settings.sampler = *overrides.sampler;
  if (overrides.spp) settings.spp = *overrides.spp;
  if (overrides.seed) settings.seed = *overrides.seed;

  const Node cam = root["camera"];
  cam.object({"eye", "target", "up", "fov", "width", "height", "crop"});
  const uint32_t width = cam["width"].count(1), height = cam["height"].count(1);
  CropWindow crop{0, 0, width, height};
  if (cam.has("crop")) {
    const auto c = cam["crop"].elements();
    if (c.size() != 4) cam["crop"].fail("expected [x0, y0, x1, y1]");
    crop = {c[0].count(0), c[1].count(0), c[2].count(0), c[3].count(0)};
  }
  if (overrides.crop) crop = *overrides.crop;
  try {
    scene.camera = std::make_unique<Camera>(cam["eye"].vec3(), cam["target"].vec3(),
                                            cam.has("up") ? cam["up"].vec3() : Vec3d{0, 1, 0}, cam["fov"].number(),
                                            width, height, crop);
  } catch (const std::invalid_argument& e) {
    cam.fail(e.what());
  }
  // Refused before anything is allocated, rather than ending in an out-of-memory error.
  const double filmBytes = Film::bytesFor(crop.width(), crop.height()), memory = Film::physicalMemoryBytes();
  if (filmBytes > memory)
    cam.fail(fmt::format("a {} × {} film needs {:.1f} GiB, more than this machine's {:.1f} GiB of memory", crop.width(),
                         crop.height(), filmBytes / 0x1p30, memory / 0x1p30));

  EnvironmentSpec envSpec = readEnvironment(root["environment"], baseDir);
  if (overrides.envSampling) envSpec.options.strategy = *overrides.envSampling;
  if (settings.portals == PortalSource::None) envSpec.options.portals.clear();

  std::map<std::string, MaterialSpec> materialSpecs;
  for (const auto& [key, node] : root["materials"].members())
    materialSpecs.emplace(key, readMaterial(node, baseDir, overrides));

  // Shapes refer to materials by name; each used name gets an index, in order of first use.
  std::map<std::string, uint32_t> materialIndex;
  std::vector<const MaterialSpec*> used;
  auto materialOf = [&](const Node& shape) {
    const Node ref = shape["material"];
    const std::string key = ref.string();
    const auto spec = materialSpecs.find(key);
    if (spec == materialSpecs.end()) ref.fail("no material named \"" + key + "\" in $.materials");
    const auto [it, inserted] = materialIndex.emplace(key, static_cast<uint32_t>(used.size()));
    if (inserted) used.push_back(&spec->second);
    return it->second;
  };

  std::vector<Sphere> spheres;
  std::vector<TriangleMesh> meshes;
  for (const Node& shape : root["shapes"].elements()) {
    const std::string type = shape["type"].string();
    if (type == "sphere") {
      shape.object({"type", "center", "radius", "material"});
      spheres.push_back({shape["center"].vec3(), shape["radius"].positive(), materialOf(shape)});
    } else if (type == "quad") {
      shape.object({"type", "corner", "edge_u", "edge_v", "transform", "material"});
      const Transform t = shape.has("transform") ? readTransform(shape["transform"]) : Transform{};
      const Vec3d corner = shape["corner"].vec3(), u = shape["edge_u"].vec3(), v = shape["edge_v"].vec3();
      if (!(length(cross(u, v)) > 0)) shape.fail("edge_u and edge_v must span a parallelogram");
      TriangleMesh quad;
      quad.positions = {t.point(corner), t.point(corner + u), t.point(corner + u + v), t.point(corner + v)};
      quad.triangles = {{0, 1, 2}, {0, 2, 3}};
      quad.tangent = t.vector(u);
      quad.material = materialOf(shape);
      meshes.push_back(std::move(quad));
    } else if (type == "mesh") {
      shape.object({"type", "file", "transform", "material"});
      const Transform t = shape.has("transform") ? readTransform(shape["transform"]) : Transform{};
      TriangleMesh mesh = readObj(shape["file"].existingFile(baseDir), shape["file"], t);
      mesh.material = materialOf(shape);
      meshes.push_back(std::move(mesh));
    } else {
      shape["type"].fail("unknown shape type \"" + type + "\" (sphere, quad or mesh)");
    }
  }

  // ---- Build what is used ----
  for (const MaterialSpec* spec : used)
    if (spec->file) Node::requireFile(*spec->file, spec->path + ".file");
  for (const MaterialSpec* spec : used) {
    scene.bsdfSamplers.push_back(spec->build(tables));
    scene.usesMeasuredMaterial = scene.usesMeasuredMaterial || spec->measured;
  }
  try {
    scene.geometry = std::make_unique<Geometry>(std::move(spheres), std::move(meshes));
  } catch (const std::invalid_argument& e) {
    throw FileError(name, std::string("$.shapes: ") + e.what());
  }
  // Portals serve light samples: a render that draws none (bsdf-only MIS) needs no search.
  const bool samplesLight = drawsLightSamples(settings) || settings.direct == DirectLighting::Product;
  if (settings.portals == PortalSource::Auto && envSpec.options.portals.empty() && samplesLight) {
    scene.openingSearch = findOpenings(*scene.geometry, *scene.camera);
    envSpec.options.portals = scene.openingSearch->openings;
  }
  const LightPdfs lightPdfs = allowsIncompleteLightPdf(settings) ? LightPdfs::Incomplete : LightPdfs::Complete;
  scene.environment = buildEnvironment(envSpec, lightPdfs, tables, "$.environment");
  return scene;
}

}  // namespace acdf

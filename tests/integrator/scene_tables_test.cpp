// The environment tables a scene gets: the loader asks the SceneAssets only for the tables its
// light's calls use (a compensated light under MIS: the compensated table; under light-only: the
// complete, adaptive one; uniform-sphere sampling: none), and lights of one map under other
// rotations and scales share them; a local light builds its slices on first use or when asked.

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/rgl.h"
#include "acdf/brdf/rgl_synthesis.h"
#include "acdf/brdf/table_options.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/integrator/scene.h"
#include "acdf/integrator/scene_assets.h"

namespace acdf {
namespace {

nlohmann::json mapScene(const std::string& sampling, const std::string& mis, double rotation = 0, double scale = 1) {
  return {
      {"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"fov", 30}, {"width", 4}, {"height", 4}}},
      {"render", {{"mis", mis}}},
      {"environment",
       {{"type", "map"},
        {"file", "data/envmaps/sunset_1024x512.exr"},
        {"sampling", sampling},
        {"rotation", rotation},
        {"scale", scale}}},
      {"materials", {{"m", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}}}},
  };
}

Scene load(const nlohmann::json& scene, SceneAssets& tables) {
  return loadSceneText(scene.dump(), std::string(ACDF_SOURCE_DIR) + "/test-scene.json", {}, tables);
}

// The tables built, by strategy ("envmap adaptive <file>" → "adaptive").
std::vector<std::string> strategiesBuilt(const SceneAssets& tables) {
  std::vector<std::string> out;
  for (const std::string& name : tables.tablesBuilt()) out.push_back(name.substr(7, name.find(' ', 7) - 7));
  return out;
}

TEST(SceneTables, CompensatedLightsGetTheTableTheirEstimatorUses) {
  const LightSampleContext mis{.allowIncompletePdf = true}, lightOnly{.allowIncompletePdf = false};
  {
    SceneAssets tables(TableCache::disabled());
    const Scene scene = load(mapScene("compensated", "power"), tables);
    EXPECT_EQ(strategiesBuilt(tables), std::vector<std::string>{"compensated"});
    EXPECT_EQ(scene.environment->table(mis).strategy(), EnvironmentTableStrategy::Compensated);
    EXPECT_EQ(scene.environment->tableBytes(), scene.environment->table(mis).bytes());
  }
  {
    SceneAssets tables(TableCache::disabled());
    const Scene scene = load(mapScene("compensated", "light-only"), tables);
    EXPECT_EQ(strategiesBuilt(tables), std::vector<std::string>{"adaptive"});
    EXPECT_EQ(scene.environment->table(lightOnly).strategy(), EnvironmentTableStrategy::Adaptive);
    EXPECT_EQ(scene.environment->tableBytes(), scene.environment->table(lightOnly).bytes());
  }
  {
    SceneAssets tables(TableCache::disabled());
    const Scene scene = load(mapScene("uniform-sphere", "light-only"), tables);
    EXPECT_TRUE(tables.tablesBuilt().empty());
    EXPECT_EQ(scene.environment->tableBytes(), 0u);
  }
}

TEST(SceneTables, LocalSlicesAreBuiltOnFirstUseOrWhenAsked) {
  SceneAssets tables(TableCache::disabled());
  nlohmann::json json = mapScene("local", "power");
  json["environment"]["normal_rows"] = 4;
  json["environment"]["normal_columns"] = 8;
  const Scene scene = load(json, tables);
  const LocalEnvironmentTable* local = scene.environment->localTable();
  ASSERT_NE(local, nullptr);
  EXPECT_EQ(local->slicesBuilt(), 0u) << "loading builds none";
  LightSampleContext context;
  context.normal = Vec3d{0, 1, 0};
  (void)scene.environment->sample(context, 0.3f, 0.7f);
  EXPECT_EQ(local->slicesBuilt(), 1u);
  scene.buildDeferredTables();
  EXPECT_EQ(local->slicesBuilt(), 32u);
  EXPECT_EQ(scene.tableBytes().environment, scene.environment->tableBytes());
}

// A portal's table is built with its light and listed with the map's tables, with its cells and
// bytes (tableBytes counts it too).
TEST(SceneTables, PortalTablesAreListedWithTheirCellsAndBytes) {
  SceneAssets tables(TableCache::disabled());
  nlohmann::json json = mapScene("adaptive", "power");
  json["environment"]["portals"] = {{{"corner", {-0.5, -0.5, -2}}, {"edge_u", {0, 1, 0}}, {"edge_v", {1, 0, 0}}}};
  const Scene scene = load(json, tables);
  ASSERT_EQ(strategiesBuilt(tables), (std::vector<std::string>{"adaptive", "portal"}));
  const WindowedTable2D& portal = scene.environment->portalTable(0).table();
  EXPECT_EQ(tables.tablesBuilt()[1],
            fmt::format("envmap portal 0 {}/data/envmaps/sunset_1024x512.exr ({} x {} cells, {:.0f} kB)", ACDF_SOURCE_DIR,
                        portal.coarseColumns(), portal.coarseRows(), portal.bytes() / 1024.0));
  EXPECT_EQ(scene.environment->tableBytes(), scene.environment->table({}).bytes() + portal.bytes());
}

TEST(SceneTables, LightsOfOneMapShareItsTableWhateverTheirPlacement) {
  SceneAssets tables(TableCache::disabled());
  const Scene plain = load(mapScene("adaptive", "power"), tables);
  const Scene turned = load(mapScene("adaptive", "power", 90, 2.5), tables);
  EXPECT_EQ(tables.tablesBuilt().size(), 1u);
  EXPECT_EQ(&plain.environment->table({}), &turned.environment->table({}));
  // The placement is the light's own: the same direction of the map, turned and brighter.
  const Vec3d w = normalize(Vec3d{0.3, 0.5, -0.8});
  const Vec3d turnedW = turned.environment->options().worldFromMap.apply(w);
  EXPECT_EQ(turned.environment->eval(turnedW).r, 2.5f * plain.environment->eval(w).r);
  EXPECT_EQ(turned.environment->pdf({}, turnedW), plain.environment->pdf({}, w));
  // Another strategy of the same map is another table.
  (void)load(mapScene("alias", "power", 45), tables);
  EXPECT_EQ(tables.tablesBuilt().size(), 2u);
}

// A scene uses a measured material when a shape has one of "type": "measured", of either file
// format or a preset (bench-error then varies its BRDF sampling); diffuse and GGX materials are
// not, nor a measured material no shape uses.
TEST(SceneTables, MeasuredMaterialsOfEitherFormatAreMeasured) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "acdf_scene_tables_measured.bsdf";
  synthesizeRgl(AnalyticBrdf::preset("gold"), {.thetaIn = 4, .ndf = 64, .vndf = 32, .reflectance = 16}, "gold")
      .save(file);
  nlohmann::json scene = mapScene("adaptive", "power");
  scene["materials"]["rgl"] = {{"type", "measured"}, {"file", file.string()}, {"sampling", "rgl"}};
  scene["materials"]["ggx"] = {{"type", "ggx-conductor"}, {"preset", "gold"}};
  SceneAssets tables(TableCache::disabled());
  EXPECT_FALSE(load(scene, tables).usesMeasuredMaterial) << "the RGL material is not used";
  scene["shapes"][0]["material"] = "ggx";
  EXPECT_FALSE(load(scene, tables).usesMeasuredMaterial) << "GGX";
  scene["shapes"][0]["material"] = "rgl";
  EXPECT_TRUE(load(scene, tables).usesMeasuredMaterial) << "an RGL file";
  scene["materials"]["rgl"] = {{"type", "measured"}, {"preset", "gold"}, {"table", {{"layout", "isotropic"}}}};
  EXPECT_TRUE(load(scene, tables).usesMeasuredMaterial) << "a preset";
  std::filesystem::remove(file);
}

// A material's "table" takes every option of the one list (table_options.h), each as a JSON value
// of its type, and the sampler gets exactly them.
TEST(SceneTables, EveryTableOptionReachesTheSampler) {
  const nlohmann::json table = {{"layout", "isotropic"}, {"theta_out", 4},          {"phi_out", 2},
                                {"theta_half", 16},      {"phi_half", 6},           {"mirror", false},
                                {"supersampling", 1},    {"chi2_epsilon", 1.25e-4},      {"tolerance", "constant"},
                                {"slice_grouping", 0.5}, {"cosine_weight", 0.125}};
  for (const TableOption& option : tableOptionList())
    EXPECT_TRUE(table.contains(option.key)) << option.key << " is not in this test's table";
  nlohmann::json scene = mapScene("adaptive", "power");
  scene["materials"]["m"] = {{"type", "measured"}, {"preset", "gold"}, {"table", table}};
  SceneAssets tables(TableCache::disabled());
  const Scene loaded = load(scene, tables);
  ASSERT_EQ(loaded.bsdfSamplers.size(), 1u);
  const auto* sampler = dynamic_cast<const TabulatedBrdfSampler*>(loaded.bsdfSamplers[0].get());
  ASSERT_NE(sampler, nullptr);
  for (const TableOption& option : tableOptionList()) {
    const nlohmann::json& value = table[std::string(option.key)];
    const std::string text = value.is_string() ? value.get<std::string>() : value.dump();
    EXPECT_EQ(option.get(sampler->options()), text) << option.key;
  }
}

}  // namespace
}  // namespace acdf

namespace acdf {
namespace {

// A measured file is a MERL or an RGL model by content, loaded once; `rgl` sampling gets the
// file's own warps and no table, the table strategies the half-vector tables of the model.
TEST(SceneTables, MeasuredFilesOfEitherFormatAndTheirSamplers) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "acdf_scene_tables_gold.dat";
  synthesizeRgl(AnalyticBrdf::preset("gold"), {.thetaIn = 4, .ndf = 64, .vndf = 32, .reflectance = 16}, "gold")
      .save(file);
  SceneAssets tables(TableCache::disabled());
  const auto model = tables.measuredFile(file, MerlBrdf::Interpolation::Trilinear);
  ASSERT_NE(std::dynamic_pointer_cast<const RglBrdf>(model), nullptr);
  EXPECT_EQ(tables.measuredFile(file, MerlBrdf::Interpolation::Nearest), model) << "loaded once";
  EXPECT_EQ(tables.brdfSampler(model, "gold", BrdfSampling::Native, {})->name(), "rgl");
  EXPECT_EQ(tables.brdfSampler(model, "gold", BrdfSampling::Cosine, {})->name(), "cosine");
  TabulatedBrdfOptions small;
  small.layout = TabulatedBrdfOptions::Layout::Isotropic;
  small.thetaOutCells = 4;
  small.thetaHalfCells = 16;
  small.phiHalfCells = 8;
  EXPECT_EQ(tables.brdfSampler(model, "gold", BrdfSampling::Adaptive, small)->name(), "adaptive-iso");
  EXPECT_TRUE(tables.tablesFromCache().empty());
  EXPECT_EQ(tables.tablesBuilt().size(), 1u);
  const auto merl = tables.merlPreset("gold", MerlBrdf::Interpolation::Nearest);
  EXPECT_THROW(tables.brdfSampler(merl, "preset gold", BrdfSampling::Native, {}), std::invalid_argument);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace acdf

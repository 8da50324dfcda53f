// `acdf render` end to end: a small render with its JSON summary and output files, and the
// failures a user meets — bad scene files (with the JSON path of the problem), missing data
// files, unwritable outputs — each exit 2 with one line on stderr and no output file left.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acdf/envmap/image_file.h"
#include "acdf/integrator/openings.h"
#include "acdf/integrator/renderer.h"
#include "app_test_util.h"

namespace acdf {
namespace {

namespace fs = std::filesystem;
using apptest::expectOneLineFailure;
using apptest::runAcdf;

nlohmann::json tinyScene() {
  return {
      {"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"fov", 30}, {"width", 8}, {"height", 6}}},
      {"render", {{"spp", 2}}},
      {"environment", {{"type", "map"}, {"file", apptest::sourceDir() + "/data/envmaps/sunset_1024x512.exr"}}},
      {"materials",
       {{"grey", {{"type", "diffuse"}, {"albedo", 0.5}}},
        {"unused", {{"type", "measured"}, {"file", "never-loaded.binary"}}}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "grey"}}}},
  };
}

class RenderCli : public apptest::TempDirTest {
 protected:
  // The table cache in the test's directory, never the user's.
  void SetUp() override {
    apptest::TempDirTest::SetUp();
    ::setenv("XDG_CACHE_HOME", path("cache").c_str(), 1);
  }

  std::string writeScene(const nlohmann::json& scene, const std::string& name = "scene.json") {
    apptest::writeFile(path(name), scene.dump(2));
    return path(name);
  }
  // `acdf render SCENE -o OUTPUT --json` with `options`, which must succeed: its JSON summary.
  nlohmann::json renderSummary(const nlohmann::json& scene, const std::string& output,
                               const std::vector<std::string>& options = {}) {
    std::vector<std::string> args{"render", writeScene(scene), "-o", path(output), "--json"};
    args.insert(args.end(), options.begin(), options.end());
    const auto run = runAcdf(args, dir_);
    EXPECT_EQ(run.exitCode, 0) << apptest::describe(run);
    return run.exitCode == 0 ? nlohmann::json::parse(run.out) : nlohmann::json::object();
  }
  // Nothing but the scene (and what the test put there) in the directory: no partial outputs.
  void expectNoOutputs() {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name.ends_with(".json") || name.ends_with(".binary") || name == "readonly" || name == "cache" ||
                  name == "stdout.txt" || name == "stderr.txt")
          << "left behind: " << name;
    }
  }
};

TEST_F(RenderCli, RendersWithJsonSummary) {
  nlohmann::json scene = tinyScene();
  // The unused material names a file that does not exist: only what the shapes use is loaded.
  fs::create_directories(path("out"));
  const auto r = runAcdf({"render", writeScene(scene), "-o", path("out/image.exr"), "--json", "--env-sampling",
                          "uniform-sphere", "--mis", "balance", "--threads", "2"},
                         dir_);
  ASSERT_EQ(r.exitCode, 0) << apptest::describe(r);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"seconds", "setup_ms", "spp", "samples_per_second", "rays_per_second", "tables_built",
                          "tables_from_cache", "exr", "png"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["spp"], 2);
  EXPECT_EQ(j["env_sampling"], "uniform-sphere");
  EXPECT_TRUE(j["tables_built"].empty()) << "a diffuse sphere under uniform-sphere sampling needs no table";
  EXPECT_TRUE(fs::is_regular_file(path("out/image.exr")));
  const Image exr = readImage(path("out/image.exr")), png = readImage(path("out/image.png"));
  EXPECT_EQ(exr.width, 8u);
  EXPECT_EQ(exr.height, 6u);
  ASSERT_EQ(png.pixels.size(), exr.pixels.size());
  // The preview is the sRGB encoding of the clamped linear values, to 8 bits.
  for (std::size_t i = 0; i < exr.pixels.size(); ++i) {
    const double v = std::clamp(exr.pixels[i], 0.0f, 1.0f);
    const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
    EXPECT_NEAR(png.pixels[i], encoded, 0.5 / 255 + 1e-6) << i;
  }
}

TEST_F(RenderCli, RglFilesRenderWithEverySampler) {
  // A measured material's file is recognised by content (no .bsdf extension here); the RGL file's
  // own warps are one more sampling, and the tables are built only for the table strategies.
  const std::string file = path("gold.dat");
  ASSERT_EQ(runAcdf({"rgl-gen", "--preset", "gold", "--theta-i", "4", "--vndf", "32", "--reflectance", "16", "--ndf",
                     "64", "-o", file},
                    dir_)
                .exitCode,
            0);
  nlohmann::json scene = tinyScene();
  scene["materials"]["grey"] = {{"type", "measured"}, {"file", "gold.dat"}, {"table", {{"layout", "isotropic"}}}};
  for (const char* sampling : {"cosine", "uniform", "adaptive", "rgl"}) {
    SCOPED_TRACE(sampling);
    const auto r = runAcdf({"render", writeScene(scene), "-o", path("image.exr"), "--json", "--bsdf-sampling", sampling,
                            "--env-sampling", "uniform-sphere", "--no-cache"},
                           dir_);
    ASSERT_EQ(r.exitCode, 0) << apptest::describe(r);
    const auto j = nlohmann::json::parse(r.out);
    const bool table = std::string(sampling) == "uniform" || std::string(sampling) == "adaptive";
    EXPECT_EQ(j["tables_built"].size(), table ? 1u : 0u) << j["tables_built"].dump();
  }
}

TEST_F(RenderCli, RglSamplingNeedsAnRglFile) {
  nlohmann::json scene = tinyScene();
  scene["materials"]["grey"] = {{"type", "measured"}, {"preset", "gold"}, {"sampling", "rgl"}};
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_), "acdf: " + path("scene.json"),
                       "$.materials.grey: rgl sampling needs an RGL .bsdf \"file\"");
  ASSERT_EQ(runAcdf({"merl-gen", "--preset", "gold", "-o", path("gold.binary")}, dir_).exitCode, 0);
  scene["materials"]["grey"] = {{"type", "measured"}, {"file", "gold.binary"}};
  expectOneLineFailure(
      runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--bsdf-sampling", "rgl", "--no-cache"}, dir_),
      "acdf: " + path("gold.binary"), "rgl sampling needs an RGL .bsdf file");
  expectNoOutputs();
}

TEST_F(RenderCli, BuildsOnlyTheChosenEnvironmentTable) {
  const auto r =
      runAcdf({"render", writeScene(tinyScene()), "-o", path("a.exr"), "--json", "--env-sampling", "alias"}, dir_);
  ASSERT_EQ(r.exitCode, 0) << apptest::describe(r);
  const auto built = nlohmann::json::parse(r.out)["tables_built"];
  ASSERT_EQ(built.size(), 1u);
  EXPECT_EQ(built[0].get<std::string>().rfind("envmap alias ", 0), 0u) << built;
}

TEST_F(RenderCli, CachesTablesAndRebuildsACorruptFile) {
  const std::string scene = writeScene(tinyScene());
  auto run = [&](std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render", scene, "-o", path("a.exr"), "--json", "--env-sampling", "adaptive"};
    args.insert(args.end(), extra.begin(), extra.end());
    return runAcdf(args, dir_);
  };
  auto tables = [](const apptest::RunResult& r, const char* key) { return nlohmann::json::parse(r.out)[key].size(); };

  const auto first = run();
  ASSERT_EQ(first.exitCode, 0) << apptest::describe(first);
  EXPECT_EQ(tables(first, "tables_built"), 1u);
  EXPECT_EQ(tables(first, "tables_from_cache"), 0u);

  const auto second = run();
  ASSERT_EQ(second.exitCode, 0) << apptest::describe(second);
  EXPECT_EQ(tables(second, "tables_built"), 0u);
  EXPECT_EQ(tables(second, "tables_from_cache"), 1u);

  // Flip a byte in the middle of every cached file: detected, warned about, rebuilt.
  for (const auto& entry : fs::recursive_directory_iterator(path("cache"))) {
    if (!entry.is_regular_file()) continue;
    std::string bytes = apptest::readFile(entry.path().string());
    bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5a);
    apptest::writeFile(entry.path().string(), bytes);
  }
  const auto third = run();
  ASSERT_EQ(third.exitCode, 0) << apptest::describe(third);
  EXPECT_EQ(tables(third, "tables_built"), 1u);
  EXPECT_NE(third.err.find("warning"), std::string::npos) << third.err;
  EXPECT_NE(third.err.find("rebuilding"), std::string::npos) << third.err;

  // --no-cache reads nothing (the file is valid again after the rebuild).
  const auto bypass = run({"--no-cache"});
  ASSERT_EQ(bypass.exitCode, 0) << apptest::describe(bypass);
  EXPECT_EQ(tables(bypass, "tables_built"), 1u);
  EXPECT_EQ(tables(bypass, "tables_from_cache"), 0u);
}

TEST_F(RenderCli, TimeBudgetRendersProgressivePassesLikeSpp) {
  const std::string scene = writeScene(tinyScene());
  const auto timed = runAcdf({"render", scene, "-o", path("timed.exr"), "--json", "--time", "0.3"}, dir_);
  ASSERT_EQ(timed.exitCode, 0) << apptest::describe(timed);
  const auto j = nlohmann::json::parse(timed.out);
  EXPECT_GE(j["seconds"].get<double>(), 0.3);
  const auto spp = j["spp"].get<uint32_t>();
  ASSERT_GE(spp, 1u);
  // Sample s of a pixel has its own random stream: spp passes of one sample equal one --spp pass.
  const auto fixed = runAcdf({"render", scene, "-o", path("fixed.exr"), "--spp", std::to_string(spp)}, dir_);
  ASSERT_EQ(fixed.exitCode, 0) << apptest::describe(fixed);
  EXPECT_EQ(readImage(path("timed.exr")).pixels, readImage(path("fixed.exr")).pixels);
}

// --sampler chooses the sample source (the scene's render.sampler: test_integrator_sampler).
TEST_F(RenderCli, SamplerOnTheCommandLine) {
  nlohmann::json scene = tinyScene();
  scene["environment"]["sampling"] = "uniform-sphere";  // no table to build
  const auto sobol =
      runAcdf({"render", writeScene(scene), "-o", path("sobol.exr"), "--sampler", "sobol", "--json"}, dir_);
  ASSERT_EQ(sobol.exitCode, 0) << apptest::describe(sobol);
  EXPECT_EQ(nlohmann::json::parse(sobol.out)["sampler"], "sobol");
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--sampler", "halton"}, dir_),
                       "acdf: render: --sampler", "independent or sobol");
}

// --direct product --candidates M chooses product direct lighting; --json reports it.
TEST_F(RenderCli, ProductDirectLightingOnTheCommandLine) {
  nlohmann::json scene = tinyScene();
  scene["environment"]["sampling"] = "uniform-sphere";
  const auto product = runAcdf(
      {"render", writeScene(scene), "-o", path("product.exr"), "--direct", "product", "--candidates", "3", "--json"},
      dir_);
  ASSERT_EQ(product.exitCode, 0) << apptest::describe(product);
  const auto j = nlohmann::json::parse(product.out);
  EXPECT_EQ(j["direct"], "product");
  EXPECT_EQ(j["candidates"], 3);
  EXPECT_EQ(j["bsdf_fraction"], 0.5);
  const auto mis = runAcdf({"render", writeScene(scene), "-o", path("mis.exr"), "--json"}, dir_);
  ASSERT_EQ(mis.exitCode, 0) << apptest::describe(mis);
  EXPECT_EQ(nlohmann::json::parse(mis.out)["direct"], "mis");
  EXPECT_FALSE(nlohmann::json::parse(mis.out).contains("candidates"));
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--direct", "best"}, dir_),
                       "acdf: render: --direct", "mis or product");
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--candidates", "0"}, dir_),
                       "acdf: render: --candidates", "must be an integer in [1, 1024]");
}

// --guiding replaces the scene's choice; --json reports what the render learned and decided.
TEST_F(RenderCli, GuidingOnTheCommandLine) {
  nlohmann::json scene = tinyScene();
  scene["render"]["spp"] = 8;
  const auto j = renderSummary(scene, "guided.exr", {"--guiding", "light"});
  EXPECT_EQ(j["guiding"], "light");
  EXPECT_EQ(j["guided"], true);
  EXPECT_EQ(j["guiding_training_passes"], 2);  // of 1 and 2 samples; the other 5 use the second's field
  EXPECT_TRUE(j["guiding_gain"].is_null());
  EXPECT_TRUE(renderSummary(scene, "auto.exr", {"--guiding", "auto"})["guiding_gain"].is_number());
  const auto plain = renderSummary(scene, "plain.exr");
  EXPECT_EQ(plain["guiding"], "off");
  EXPECT_FALSE(plain.contains("guided"));
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--guiding", "always"}, dir_),
                       "acdf: render: --guiding", "off, light, paths or auto");
}

// --branches replaces the scene's choice (auto by default); --json reports the count rendered and,
// under auto, the rays and variances it was chosen from.
TEST_F(RenderCli, BranchesOnTheCommandLine) {
  nlohmann::json scene = tinyScene();
  scene["environment"]["sampling"] = "uniform-sphere";
  scene["render"]["spp"] = 4;
  const auto j = renderSummary(scene, "fixed.exr", {"--branches", "3"});
  EXPECT_EQ(j["branches"], "3");
  EXPECT_EQ(j["branched"], 3);
  EXPECT_FALSE(j.contains("rays_per_branch"));
  EXPECT_EQ(renderSummary(scene, "plain.exr")["branches"], "auto");
  const auto a = renderSummary(scene, "auto.exr", {"--branches", "auto"});
  EXPECT_EQ(a["branches"], "auto");
  EXPECT_TRUE(a["rays_before_branching"].is_number());
  EXPECT_TRUE(a["rays_per_branch"].is_number());
  EXPECT_GT(a["variance_per_branch"].get<double>(), 0.0);
  EXPECT_EQ(a["branched"].get<uint32_t>(),
            branchesThatPay(a["rays_before_branching"].get<double>(), a["rays_per_branch"].get<double>(),
                            a["variance_before_branching"].get<double>(), a["variance_per_branch"].get<double>()));
  for (const char* bad : {"0", "65", "many", "2.5"})
    expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--branches", bad}, dir_),
                         "acdf: render: --branches", "(auto or an integer in [1, 64])");
  EXPECT_FALSE(fs::exists(path("x.exr")));
}

// A closed box x, z in [-1, 1], y in [0, 2] with a window in its wall z = 1, under a constant sky.
nlohmann::json tinyRoom() {
  const auto quad = [](std::vector<double> corner, std::vector<double> u, std::vector<double> v) {
    return nlohmann::json{{"type", "quad"}, {"corner", corner}, {"edge_u", u}, {"edge_v", v}, {"material", "grey"}};
  };
  nlohmann::json room = tinyScene();
  room["camera"] = {{"eye", {0, 1, -0.8}}, {"target", {0, 0.8, 1}}, {"fov", 80}, {"width", 8}, {"height", 6}};
  room["environment"] = {{"type", "constant"}, {"radiance", 1}};
  room["shapes"] = {quad({-1, 0, -1}, {2, 0, 0}, {0, 0, 2}),     quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}),
                    quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}),     quad({-1, 0, -1}, {0, 0, 2}, {0, 2, 0}),
                    quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}),      quad({-1, 0, 1}, {2, 0, 0}, {0, 0.6, 0}),
                    quad({-1, 1.4, 1}, {2, 0, 0}, {0, 0.6, 0}),  quad({-1, 0.6, 1}, {0.6, 0, 0}, {0, 0.8, 0}),
                    quad({0.4, 0.6, 1}, {0.6, 0, 0}, {0, 0.8, 0})};
  return room;
}

// --portals replaces the scene's choice: by default a room that declares none gets its window
// found, and the render says so; `declared` does not look, `none` drops declared ones too.
TEST_F(RenderCli, PortalsOnTheCommandLine) {
  const auto run = [&](const nlohmann::json& scene, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", writeScene(scene), "-o", path("room.exr")};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto result = runAcdf(args, dir_);
    EXPECT_EQ(result.exitCode, 0) << apptest::describe(result);
    return result;
  };
  const auto found = nlohmann::json::parse(run(tinyRoom(), {"--json"}).out);
  const std::string foundImage = apptest::readFile(path("room.exr"));
  EXPECT_EQ(found["portals"], "auto");
  EXPECT_EQ(found["portal_count"], 1);
  EXPECT_LT(found["escaped_share"].get<double>(), kMaxEscapedShare);
  EXPECT_NE(run(tinyRoom(), {}).out.find("portals   1 found: "), std::string::npos);
  // What was found, in the scene file's form, declared: the same image.
  ASSERT_EQ(found["found_portals"].size(), 1u);
  nlohmann::json declaring = tinyRoom();
  declaring["environment"]["portals"] = found["found_portals"];
  const auto asDeclared = nlohmann::json::parse(run(declaring, {"--json"}).out);
  EXPECT_EQ(asDeclared["portal_count"], 1);
  EXPECT_FALSE(asDeclared.contains("found_portals"));
  EXPECT_TRUE(apptest::readFile(path("room.exr")) == foundImage);
  const auto open = nlohmann::json::parse(run(tinyScene(), {"--json"}).out);
  EXPECT_EQ(open["portal_count"], 0);
  EXPECT_GE(open["escaped_share"].get<double>(), kMaxEscapedShare);
  EXPECT_NE(run(tinyScene(), {}).out.find("leave the scene (an enclosure needs < 25 %)"), std::string::npos);
  const auto declared = nlohmann::json::parse(run(tinyRoom(), {"--portals", "declared", "--json"}).out);
  EXPECT_EQ(declared["portal_count"], 0);
  EXPECT_FALSE(declared.contains("escaped_share"));
  // Portals serve light samples: BSDF sampling alone does not look for them.
  const auto bsdfOnly = nlohmann::json::parse(run(tinyRoom(), {"--mis", "bsdf-only", "--json"}).out);
  EXPECT_EQ(bsdfOnly["portal_count"], 0);
  EXPECT_FALSE(bsdfOnly.contains("escaped_share"));
  nlohmann::json withPortal = tinyRoom();
  withPortal["environment"]["portals"] = {{{"corner", {-0.4, 0.6, 1}}, {"edge_u", {0, 0.8, 0}}, {"edge_v", {0.8, 0, 0}}}};
  const auto kept = nlohmann::json::parse(run(withPortal, {"--json"}).out);
  EXPECT_EQ(kept["portal_count"], 1);
  EXPECT_FALSE(kept.contains("escaped_share"));
  EXPECT_EQ(nlohmann::json::parse(run(withPortal, {"--portals", "none", "--json"}).out)["portal_count"], 0);
  expectOneLineFailure(runAcdf({"render", writeScene(tinyRoom()), "-o", path("x.exr"), "--portals", "found"}, dir_),
                       "acdf: render: --portals", "auto, declared or none");
}

// --light-paths replaces the scene's choice, and the render says what it did: `auto` measures in a
// room with portals and connects where that paid, `on` connects without measuring, `off` never
// does, and a scene with no portals has nothing to connect to.
TEST_F(RenderCli, LightPathsOnTheCommandLine) {
  const auto run = [&](const nlohmann::json& scene, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render", writeScene(scene), "-o", path("room.exr"), "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto result = runAcdf(args, dir_);
    EXPECT_EQ(result.exitCode, 0) << apptest::describe(result);
    return nlohmann::json::parse(result.out);
  };
  const auto automatic = run(tinyRoom(), {"--spp", "8"});
  EXPECT_EQ(automatic["light_paths"], "auto");
  EXPECT_TRUE(automatic["light_path_gain"].is_number());
  const auto on = run(tinyRoom(), {"--light-paths", "on"});
  EXPECT_TRUE(on["connects_light_paths"].get<bool>());
  EXPECT_TRUE(on["light_path_gain"].is_null());
  EXPECT_FALSE(run(tinyRoom(), {"--light-paths", "off"})["connects_light_paths"].get<bool>());
  const auto open = run(tinyScene(), {"--light-paths", "on"});
  EXPECT_FALSE(open["connects_light_paths"].get<bool>());
  EXPECT_TRUE(open["light_path_gain"].is_null());
  expectOneLineFailure(
      runAcdf({"render", writeScene(tinyRoom()), "-o", path("x.exr"), "--light-paths", "always"}, dir_),
      "acdf: render: --light-paths", "auto, on or off");
}

TEST_F(RenderCli, UnknownKeyNamesItsPath) {
  nlohmann::json scene = tinyScene();
  scene["shapes"][0]["radious"] = 2;
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_), "acdf: " + path("scene.json"),
                       "$.shapes[0].radious: unknown key");
  expectNoOutputs();
}

TEST_F(RenderCli, WrongTypeNamesItsPath) {
  nlohmann::json scene = tinyScene();
  scene["camera"]["fov"] = "wide";
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_), "acdf: " + path("scene.json"),
                       "$.camera.fov: expected a number, got a string");
  expectNoOutputs();
}

// A film larger than the machine's memory is refused with its size, before anything is
// allocated (it ended in "acdf: out of memory", exit 1).
TEST_F(RenderCli, FilmTooLargeForMemoryNamesItsSize) {
  nlohmann::json scene = tinyScene();
  scene["camera"]["width"] = 100000;
  scene["camera"]["height"] = 100000;
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_), "acdf: " + path("scene.json"),
                       "$.camera: a 100000 × 100000 film needs 633.3 GiB, more than this machine's");
  expectNoOutputs();
}

// A scale beyond float would make the light's radiance infinite: refused with its path, for every
// strategy (it was an internal error, exit 1, or with uniform-sphere sampling an image of Inf).
TEST_F(RenderCli, EnvironmentScaleBeyondFloatNamesItsPath) {
  nlohmann::json scene = tinyScene();
  scene["environment"]["scale"] = 1e39;
  for (const char* sampling : {"uniform-sphere", "adaptive"})
    expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr"), "--env-sampling", sampling}, dir_),
                         "acdf: " + path("scene.json"), "$.environment.scale: must be at most 3.4e38");
  expectNoOutputs();
}

// The options structs' validators judge the scene's values; the loader names the key.
TEST_F(RenderCli, RejectedOptionNamesItsKey) {
  const auto failure = [&](const nlohmann::json& scene, const std::string& message) {
    expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_),
                         "acdf: " + path("scene.json"), message);
  };
  nlohmann::json scene = tinyScene();
  scene["materials"]["unused"] = {{"type", "measured"}, {"preset", "gold"}, {"table", {{"phi_half", 7}}}};
  scene["materials"]["unused"]["table"]["layout"] = "isotropic";
  failure(scene, "$.materials.unused.table.phi_half: must be even for a mirrored isotropic table, got 7");
  scene["materials"]["unused"]["table"] = {{"layout", "iso"}};
  failure(scene, "$.materials.unused.table.layout: unknown BRDF table layout 'iso' (4d or isotropic)");
  scene["materials"]["unused"]["table"] = {{"cosine_weight", 1.5}};
  failure(scene, "$.materials.unused.table.cosine_weight: must be in [0, 1], got 1.5");
  scene["materials"]["unused"]["table"] = {{"mirror", "yes"}};
  failure(scene, "$.materials.unused.table.mirror: expected true or false, got a string");
  scene["materials"]["unused"]["table"] = {{"theta_half", 2.5}};
  failure(scene, "$.materials.unused.table.theta_half: expected an integer, got a number");
  scene["materials"]["unused"]["table"] = {{"tolerance", "loose"}};
  failure(scene, "$.materials.unused.table.tolerance: unknown");
  scene["materials"]["unused"]["table"] = {{"theta_half_cells", 64}};
  failure(scene, "$.materials.unused.table.theta_half_cells: unknown key (expected one of: layout, theta_out");
  scene = tinyScene();
  scene["environment"]["epsilon"] = -1;
  failure(scene, "$.environment.epsilon: must be finite and >= 0, got -1");
  scene = tinyScene();
  scene["environment"]["block_size"] = 5000;
  failure(scene, "$.environment.block_size: must be in [1, 4096], got 5000");
  scene = tinyScene();
  const nlohmann::json window = {{"corner", {0, 0, 2}}, {"edge_u", {0, 1, 0}}, {"edge_v", {1, 0, 0}}};
  scene["environment"]["portals"] = {window, {{"corner", {0, 0, 2}}, {"edge_u", {0, 1, 0}}, {"edge_v", {1, 1, 0}}}};
  failure(scene, "$.environment.portals[1]: edge_u and edge_v must be perpendicular");
  scene["environment"]["portals"] = {{{"corner", {0, 0, 2}}, {"edge_u", {0, 0, 0}}, {"edge_v", {1, 0, 0}}}};
  failure(scene, "$.environment.portals[0]: its edges must not be zero");
  scene["environment"]["portals"] = {{{"corner", {0, 0, 2}}, {"edge_u", {0, 1, 0}}}};
  failure(scene, "$.environment.portals[0]: missing key \"edge_v\"");
  scene["environment"]["portals"] = {{{"corner", {0, 0, 2}}, {"edge_u", {0, 1, 0}}, {"edge_v", {1, 0, 0}}, {"x", 1}}};
  failure(scene, "$.environment.portals[0].x: unknown key (expected one of: corner, edge_u, edge_v)");
  scene["environment"]["portals"] = window;
  failure(scene, "$.environment.portals: expected an array, got an object");
  scene = tinyScene();
  scene["render"] = {{"direct", "product"}, {"bsdf_fraction", 1.5}};
  failure(scene, "$.render.bsdf_fraction: must be in [0, 1], got 1.5");
  scene["render"] = {{"candidates", 2000}};
  failure(scene, "$.render.candidates: must be an integer in [1, 1024]");
  scene["render"] = {{"direct", "resampled"}};
  failure(scene, "$.render.direct: unknown direct lighting 'resampled' (mis or product)");
  scene["render"] = {{"guiding", "light"}, {"direct", "product"}};
  failure(scene,
          "$.render.guiding: 'light' guides light samples, which product direct lighting does not draw (guiding "
          "'paths', or direct 'mis')");
  scene["render"] = {{"guiding", "light"}, {"mis", "bsdf-only"}};
  failure(scene,
          "$.render.guiding: 'light' guides light samples, which mis 'bsdf-only' does not draw (guiding 'paths', or "
          "another mis)");
  scene["render"] = {{"guiding", "always"}};
  failure(scene, "$.render.guiding: unknown guiding mode 'always' (off, light, paths or auto)");
  scene["render"] = {{"portals", "found"}};
  failure(scene, "$.render.portals: unknown portal source 'found' (auto, declared or none)");
  scene["render"] = {{"branches", 0}};
  failure(scene, "$.render.branches: must be an integer in [1, 64]");
  scene["render"] = {{"branches", "some"}};
  failure(scene, "$.render.branches: unknown branch count 'some' (auto or an integer in [1, 64])");
  scene["render"] = {{"light_paths", "sometimes"}};
  failure(scene, "$.render.light_paths: unknown light path mode 'sometimes' (auto, on or off)");
  expectNoOutputs();
}

TEST_F(RenderCli, InvalidJson) {
  apptest::writeFile(path("scene.json"), "{\"camera\": ");
  expectOneLineFailure(runAcdf({"render", path("scene.json"), "-o", path("x.exr")}, dir_),
                       "acdf: " + path("scene.json"), "invalid JSON");
  // A number beyond double is nlohmann's out_of_range, not a parse_error (found by fuzz_scene; it
  // was reported as an internal error, exit 1).
  apptest::writeFile(path("scene.json"), "{\"camera\": {\"width\": 4833333333333333333333333333E3333}}");
  expectOneLineFailure(runAcdf({"render", path("scene.json"), "-o", path("x.exr")}, dir_),
                       "acdf: " + path("scene.json"), "number overflow");
}

TEST_F(RenderCli, MissingSceneFile) {
  expectOneLineFailure(runAcdf({"render", path("nope.json"), "-o", path("x.exr")}, dir_), "acdf: " + path("nope.json"),
                       "no such file");
}

TEST_F(RenderCli, MissingReferencedFileIsResolvedAgainstTheScene) {
  nlohmann::json scene = tinyScene();
  scene["materials"]["grey"] = {{"type", "measured"}, {"file", "missing.binary"}};
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_),
                       "acdf: " + path("missing.binary"), "no such file (referenced by $.materials.grey.file)");
  expectNoOutputs();
}

TEST_F(RenderCli, BrokenReferencedFile) {
  apptest::writeFile(path("broken.binary"), "not a BRDF");
  nlohmann::json scene = tinyScene();
  scene["materials"]["grey"] = {{"type", "measured"}, {"file", "broken.binary"}};
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_),
                       "acdf: " + path("broken.binary"), "referenced by $.materials.grey");
  expectNoOutputs();
}

TEST_F(RenderCli, UnknownMaterialReference) {
  nlohmann::json scene = tinyScene();
  scene["shapes"][0]["material"] = "gold";
  expectOneLineFailure(runAcdf({"render", writeScene(scene), "-o", path("x.exr")}, dir_), "acdf: " + path("scene.json"),
                       "$.shapes[0].material: no material named \"gold\"");
}

TEST_F(RenderCli, UnwritableOutputLeavesNoFile) {
  expectOneLineFailure(runAcdf({"render", writeScene(tinyScene()), "-o", path("no-such-dir/x.exr")}, dir_),
                       "acdf: " + path("no-such-dir/x.exr"), "output directory does not exist");
  fs::create_directories(path("taken.exr"));
  expectOneLineFailure(runAcdf({"render", writeScene(tinyScene()), "-o", path("taken.exr")}, dir_),
                       "acdf: " + path("taken.exr"), "is a directory");
  fs::remove(path("taken.exr"));
  expectNoOutputs();

  fs::create_directories(path("readonly"));
  fs::permissions(path("readonly"), fs::perms::owner_read | fs::perms::owner_exec);
  if (::access(path("readonly").c_str(), W_OK) == 0)
    GTEST_SKIP() << "running as a user who can write anywhere (root): no read-only directory to test";
  expectOneLineFailure(runAcdf({"render", writeScene(tinyScene()), "-o", path("readonly/x.exr")}, dir_),
                       "acdf: " + path("readonly/x.exr"), "not writable");
  EXPECT_TRUE(fs::is_empty(path("readonly")));
}

TEST_F(RenderCli, BadStrategyOnTheCommandLine) {
  expectOneLineFailure(
      runAcdf({"render", writeScene(tinyScene()), "-o", path("x.exr"), "--env-sampling", "magic"}, dir_),
      "acdf: render: --env-sampling", "uniform-sphere");
  expectOneLineFailure(runAcdf({"render", writeScene(tinyScene()), "-o", path("x.exr"), "--mis", "best"}, dir_),
                       "acdf: render: --mis", "power");
}

}  // namespace
}  // namespace acdf

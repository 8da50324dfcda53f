// Consistency: every strategy estimates the same integral, so renders of one scene with
// different strategies must agree in mean within their error bars (3 standard errors of the
// difference). A biased strategy — an adaptive table that dropped mass, an MIS weight that does
// not sum to one — shows up as a difference far beyond them.

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acdf/envmap/image_file.h"
#include "acdf/envmap/lat_long.h"
#include "render_test_util.h"

namespace acdf {
namespace {

// A sky with a broad bright lobe, written once per test process: varied enough that the tables
// matter, smooth enough that BSDF sampling alone has no heavy tail (a small sun makes rare, huge
// samples whose sample variance understates the error, and error bars mean nothing).
std::string smoothSky() {
  struct TemporaryFile {
    std::string path;
    ~TemporaryFile() { std::filesystem::remove(path); }
  };
  static const TemporaryFile sky = [] {
    TemporaryFile file{
        (std::filesystem::temp_directory_path() / ("acdf_consistency_sky_" + std::to_string(::getpid()) + ".exr"))
            .string()};
    Image image;
    image.width = 64;
    image.height = 32;
    image.channels = 3;
    const Vec3d lobe = normalize(Vec3d{1.0, 1.2, 0.6});
    for (uint32_t r = 0; r < image.height; ++r)
      for (uint32_t c = 0; c < image.width; ++c) {
        const Vec3d w = LatLongMapping::direction(std::numbers::pi * (r + 0.5) / image.height,
                                                  2.0 * std::numbers::pi * (c + 0.5) / image.width);
        const double bright = std::pow(std::max(0.0, dot(w, lobe)), 8.0);
        image.pixels.insert(image.pixels.end(),
                            {static_cast<float>(0.3 + 4.0 * bright), static_cast<float>(0.4 + 3.0 * bright),
                             static_cast<float>(0.6 + 2.0 * bright)});
      }
    writeExr(file.path, image);
    return file;
  }();
  return sky.path;
}

// A measured sphere and a diffuse sphere on a diffuse floor under the sky: direct and indirect
// light, a glossy lobe light sampling rarely finds and a bright region BSDF sampling rarely finds.
nlohmann::json skyScene(const std::string& sampling) {
  return {
      {"camera", {{"eye", {0, 1.6, 4.5}}, {"target", {0, 0.7, 0}}, {"fov", 40}, {"width", 20}, {"height", 12}}},
      {"render", {{"spp", 96}, {"seed", 3}, {"max_depth", 4}}},
      {"environment", {{"type", "map"}, {"file", smoothSky()}, {"sampling", "adaptive"}}},
      {"materials",
       {{"metal",
         {{"type", "measured"}, {"preset", "gold"}, {"sampling", sampling}, {"table", {{"layout", "isotropic"}}}}},
        {"floor", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}}}},
      {"shapes",
       {{{"type", "sphere"}, {"center", {-0.6, 0.6, 0}}, {"radius", 0.6}, {"material", "metal"}},
        {{"type", "sphere"}, {"center", {0.7, 0.5, 0.3}}, {"radius", 0.5}, {"material", "floor"}},
        {{"type", "quad"},
         {"corner", {-5, 0, -5}},
         {"edge_u", {0, 0, 10}},
         {"edge_v", {10, 0, 0}},
         {"material", "floor"}}}},
  };
}

void expectAgree(const rendertest::ImageMean& a, const rendertest::ImageMean& b, const std::string& what) {
  auto check = [&](double ma, double sa, double mb, double sb, const char* channel) {
    const double bar = 3.0 * std::sqrt(sa * sa + sb * sb);
    EXPECT_LE(std::abs(ma - mb), bar) << what << " " << channel << ": " << ma << " vs " << mb << " (3σ = " << bar
                                      << ")";
    // The bars themselves must be meaningful: a few percent, not the size of the signal.
    EXPECT_LT(bar, 0.1 * std::max(ma, mb)) << what << " " << channel;
  };
  check(a.mean.r, a.standardError.r, b.mean.r, b.standardError.r, "red");
  check(a.mean.g, a.standardError.g, b.mean.g, b.standardError.g, "green");
  check(a.mean.b, a.standardError.b, b.mean.b, b.standardError.b, "blue");
}

rendertest::ImageMean renderMean(const std::string& brdfSampling, MisMode mis, EnvironmentSampling env,
                                 SamplerKind sampler = SamplerKind::Independent) {
  SceneOverrides overrides;
  overrides.sampler = sampler;
  overrides.mis = mis;
  overrides.envSampling = env;
  return rendertest::imageMean(rendertest::renderScene(skyScene(brdfSampling), overrides).film);
}

TEST(Consistency, MisModesAgree) {
  const auto power = renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive);
  expectAgree(power, renderMean("adaptive", MisMode::Balance, EnvironmentSampling::Adaptive), "power vs balance");
  expectAgree(power, renderMean("adaptive", MisMode::BsdfOnly, EnvironmentSampling::Adaptive), "power vs bsdf-only");
  expectAgree(power, renderMean("adaptive", MisMode::LightOnly, EnvironmentSampling::Adaptive), "power vs light-only");
}

TEST(Consistency, UniformAndAdaptiveTablesAgree) {
  // BSDF sampling alone, so the BRDF table's own bias could not hide behind light sampling.
  expectAgree(renderMean("uniform", MisMode::BsdfOnly, EnvironmentSampling::Adaptive),
              renderMean("adaptive", MisMode::BsdfOnly, EnvironmentSampling::Adaptive),
              "uniform vs adaptive BRDF table");
  // Light sampling alone for the environment tables, likewise.
  expectAgree(renderMean("adaptive", MisMode::LightOnly, EnvironmentSampling::Uniform),
              renderMean("adaptive", MisMode::LightOnly, EnvironmentSampling::Adaptive),
              "uniform vs adaptive environment table");
}

TEST(Consistency, EnvironmentStrategiesAgreeUnderMis) {
  const auto adaptive = renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive);
  expectAgree(adaptive, renderMean("adaptive", MisMode::Power, EnvironmentSampling::UniformSphere),
              "adaptive vs uniform-sphere");
  expectAgree(adaptive, renderMean("adaptive", MisMode::Power, EnvironmentSampling::Alias), "adaptive vs alias");
  expectAgree(adaptive, renderMean("adaptive", MisMode::Power, EnvironmentSampling::Compensated),
              "adaptive vs compensated");
}

// Local sampling (the light drawn by L max(0, n · ω) for each vertex's normal) estimates the same
// image under MIS and alone: its pdf is positive wherever the reflected light is. So does the
// compensated local table under MIS (pdf 0 below each cell's mean, left to BSDF sampling), and
// alone, where the light answers from its complete Adaptive table.
// Blocks of 2 × 2 pixels of the 64 × 32 sky (11°) and as fine normal cells, so the cosine bound is
// tight: a sample drawn for the wrong normal would miss much of the light.
TEST(Consistency, LocalSamplingAgreesUnderMisAndAlone) {
  const auto adaptive = renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive);
  for (const std::string sampling : {"local", "local-compensated"}) {
    auto local = [&](MisMode mis) {
      nlohmann::json scene = skyScene("adaptive");
      scene["environment"]["sampling"] = sampling;
      scene["environment"]["block_size"] = 2;
      scene["environment"]["normal_rows"] = 16;
      scene["environment"]["normal_columns"] = 32;
      SceneOverrides overrides;
      overrides.mis = mis;
      return rendertest::imageMean(rendertest::renderScene(scene, overrides).film);
    };
    expectAgree(adaptive, local(MisMode::Power), "adaptive vs " + sampling);
    expectAgree(adaptive, local(MisMode::LightOnly), "power x adaptive vs light-only x " + sampling);
  }
}

// Light sampling alone cannot use the compensated table (pdf 0 where the sky is dimmer than its
// mean, most of this one): a compensated light answers it from its complete table instead.
TEST(Consistency, LightOnlyWithCompensatedSamplingIsUnbiased) {
  expectAgree(renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive),
              renderMean("adaptive", MisMode::LightOnly, EnvironmentSampling::Compensated),
              "power x adaptive vs light-only x compensated");
}

// Product direct lighting (resampled f·L·cos) estimates the same image as MIS: on the glossy scene
// with the compensated table (the BSDF candidates cover what it leaves out) and the local one, and
// on a diffuse-only variant; with candidates from both strategies, and from the light alone.
rendertest::ImageMean productMean(nlohmann::json scene, EnvironmentSampling env, double bsdfFraction,
                                  SamplerKind sampler = SamplerKind::Independent) {
  scene["render"]["direct"] = "product";
  scene["render"]["candidates"] = 4;
  scene["render"]["bsdf_fraction"] = bsdfFraction;
  SceneOverrides overrides;
  overrides.envSampling = env;
  overrides.sampler = sampler;
  return rendertest::imageMean(rendertest::renderScene(scene, overrides).film);
}

TEST(Consistency, ProductAndMisAgreeOnAGlossyScene) {
  const auto power = renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive);
  expectAgree(power, productMean(skyScene("adaptive"), EnvironmentSampling::Compensated, 0.5),
              "power vs product x compensated");
  expectAgree(power, productMean(skyScene("adaptive"), EnvironmentSampling::Local, 0.5), "power vs product x local");
  expectAgree(power, productMean(skyScene("adaptive"), EnvironmentSampling::Adaptive, 0.0),
              "power vs product of light candidates");
  expectAgree(power, productMean(skyScene("adaptive"), EnvironmentSampling::Adaptive, 0.5, SamplerKind::Sobol),
              "power vs product, sobol");
}

TEST(Consistency, ProductAndMisAgreeOnADiffuseScene) {
  nlohmann::json diffuse = skyScene("adaptive");
  diffuse["materials"]["metal"] = {{"type", "diffuse"}, {"albedo", {0.7, 0.6, 0.3}}};
  SceneOverrides overrides;
  overrides.envSampling = EnvironmentSampling::Adaptive;
  const auto mis = rendertest::imageMean(rendertest::renderScene(diffuse, overrides).film);
  expectAgree(mis, productMean(diffuse, EnvironmentSampling::Compensated, 0.5), "mis vs product, diffuse");
}

// Not a consistency check but the reason for a default: the scenes' MIS heuristic is the balance
// one, because the default environment table is compensated and MIS compensation (Karlik et al.
// 2019) is derived for it. With that table its variance per sample is lower than the power
// heuristic's on the sky scene (on the open example scenes, 2-13 %: docs/performance.md).
TEST(Consistency, DefaultMisHasLessVarianceThanPowerUnderTheCompensatedTable) {
  const auto error = [](std::optional<MisMode> mis) {
    SceneOverrides overrides;
    overrides.sampler = SamplerKind::Independent;
    overrides.envSampling = EnvironmentSampling::Compensated;
    overrides.mis = mis;
    overrides.branches = 1;  // the heuristics alone, not the branch count their probes choose
    return rendertest::imageMean(rendertest::renderScene(skyScene("adaptive"), overrides).film).standardError;
  };
  const Rgb byDefault = error(std::nullopt), power = error(MisMode::Power);
  std::printf("standard error of the image mean, default MIS vs power: %.4g vs %.4g, %.4g vs %.4g, %.4g vs %.4g\n",
              byDefault.r, power.r, byDefault.g, power.g, byDefault.b, power.b);
  EXPECT_LT(byDefault.r, power.r);
  EXPECT_LT(byDefault.g, power.g);
  EXPECT_LT(byDefault.b, power.b);
}

// Sobol samples estimate the same image: with indirect light, a glossy table and both strategies,
// and with the BRDF table alone (its samples read the stratified BSDF components). The error bars
// are those of independent samples, larger than a Sobol render's actual error.
TEST(Consistency, SobolAndIndependentSamplesAgree) {
  expectAgree(renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive),
              renderMean("adaptive", MisMode::Power, EnvironmentSampling::Adaptive, SamplerKind::Sobol),
              "independent vs sobol, power");
  expectAgree(renderMean("adaptive", MisMode::BsdfOnly, EnvironmentSampling::Adaptive),
              renderMean("adaptive", MisMode::BsdfOnly, EnvironmentSampling::Adaptive, SamplerKind::Sobol),
              "independent vs sobol, bsdf-only");
}

// A closed room (x, z in [-1, 1], y in [0, 2], diffuse) lit only through a window in its wall
// z = 1 by the sky; with `portal`, the window is declared a portal (edge_u x edge_v into the room).
nlohmann::json room(bool portal) {
  const auto quad = [](std::vector<double> corner, std::vector<double> u, std::vector<double> v) {
    return nlohmann::json{{"type", "quad"}, {"corner", corner}, {"edge_u", u}, {"edge_v", v}, {"material", "wall"}};
  };
  nlohmann::json environment = {{"type", "map"}, {"file", smoothSky()}, {"sampling", "compensated"}};
  if (portal)
    environment["portals"] = {{{"corner", {-0.4, 0.6, 1.0}}, {"edge_u", {0, 0.8, 0}}, {"edge_v", {0.8, 0, 0}}}};
  return {
      {"camera", {{"eye", {0.5, 1.2, 0.8}}, {"target", {-0.3, 0.4, -0.6}}, {"fov", 70}, {"width", 20}, {"height", 12}}},
      {"render", {{"spp", 256}, {"seed", 5}, {"max_depth", 3}}},
      {"environment", environment},
      {"materials", {{"wall", {{"type", "diffuse"}, {"albedo", {0.6, 0.6, 0.6}}}}}},
      {"shapes",
       {quad({-1, 0, -1}, {2, 0, 0}, {0, 0, 2}), quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}),
        quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}), quad({-1, 0, -1}, {0, 0, 2}, {0, 2, 0}),
        quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}), quad({-1, 0, 1}, {2, 0, 0}, {0, 0.6, 0}),
        quad({-1, 1.4, 1}, {2, 0, 0}, {0, 0.6, 0}), quad({-1, 0.6, 1}, {0.6, 0, 0}, {0, 0.8, 0}),
        quad({0.4, 0.6, 1}, {0.6, 0, 0}, {0, 0.8, 0})}},
  };
}

// Portals add a technique, not light: a room renders the same with its window declared a portal,
// and with the opening found by tracing where none is declared, as without portals, under MIS
// (with the compensated table, incomplete) and with light sampling alone (where the light
// answers from the complete table mixed with the portal's).
TEST(Consistency, PortalsAgreeUnderMisAndAlone) {
  for (MisMode mis : {MisMode::Power, MisMode::LightOnly}) {
    SceneOverrides overrides;
    overrides.sampler = SamplerKind::Independent;
    overrides.mis = mis;
    overrides.portals = PortalSource::None;
    const auto plain = rendertest::imageMean(rendertest::renderScene(room(false), overrides).film);
    overrides.portals = PortalSource::Auto;
    const rendertest::Rendered declared = rendertest::renderScene(room(true), overrides);
    const rendertest::Rendered found = rendertest::renderScene(room(false), overrides);
    EXPECT_EQ(found.portals, 1u);
    const std::string how = mis == MisMode::Power ? ", power MIS" : ", light-only";
    expectAgree(plain, rendertest::imageMean(declared.film), "declared portal vs none" + how);
    expectAgree(plain, rendertest::imageMean(found.film), "found portal vs none" + how);
  }
}

// Connections to light paths through the window add a technique, not light: the room renders the
// same with every vertex connected as with none, under both MIS heuristics (each of the three
// weights of a path through a lit point must sum to one), with the window declared or found, and
// branched (the branches' vertices weigh against the connection made before them).
TEST(Consistency, LightPathConnectionsAgreeWithNone) {
  for (MisMode mis : {MisMode::Power, MisMode::Balance})
    for (uint32_t branches : {1u, 3u}) {
      SceneOverrides overrides;
      overrides.sampler = SamplerKind::Independent;
      overrides.mis = mis;
      overrides.branches = branches;
      overrides.lightPaths = LightPathMode::Off;
      const bool declared = branches == 1;
      const auto plain = rendertest::imageMean(rendertest::renderScene(room(declared), overrides).film);
      overrides.lightPaths = LightPathMode::On;
      const rendertest::Rendered connected = rendertest::renderScene(room(declared), overrides);
      EXPECT_TRUE(connected.stats.connectsLightPaths);
      expectAgree(plain, rendertest::imageMean(connected.film),
                  "connected vs not, " + std::string(toString(mis)) + ", " + std::to_string(branches) + " branches");
    }
}

// Guiding learns where light comes from and adds none: the room renders the same guided by what
// it learned of the light, and of the paths' radiance too, under MIS (the compensated table,
// incomplete, with the window's portal found) and with light sampling alone (the learned light
// mixed with the complete table, no portal).
TEST(Consistency, GuidedRendersAgreeWithUnguided) {
  for (MisMode mis : {MisMode::Power, MisMode::LightOnly}) {
    SceneOverrides overrides;
    overrides.sampler = SamplerKind::Independent;
    overrides.mis = mis;
    overrides.portals = mis == MisMode::Power ? PortalSource::Auto : PortalSource::None;
    const auto plain = rendertest::imageMean(rendertest::renderScene(room(false), overrides).film);
    for (GuidingMode guiding : {GuidingMode::Light, GuidingMode::Paths}) {
      overrides.guiding = guiding;
      const rendertest::Rendered guided = rendertest::renderScene(room(false), overrides);
      EXPECT_TRUE(guided.stats.guiding.guided);
      EXPECT_GE(guided.stats.guiding.trainingPasses, 5u);
      expectAgree(plain, rendertest::imageMean(guided.film),
                  std::string("guided (") + std::string(toString(guiding)) + ") vs not, " + std::string(toString(mis)));
    }
  }
}

// Branching at the first vertex adds paths, not light: the sky scene renders the same with 4
// branches per camera sample as with none, with both sample sources; and so does the room guided
// by its paths' radiance (each branch records its own vertices).
TEST(Consistency, BranchedRendersAgreeWithUnbranched) {
  for (const SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
    SceneOverrides overrides;
    overrides.sampler = sampler;
    overrides.branches = 1;
    const auto plain = rendertest::imageMean(rendertest::renderScene(skyScene("adaptive"), overrides).film);
    overrides.branches = 4;
    const rendertest::Rendered branched = rendertest::renderScene(skyScene("adaptive"), overrides);
    EXPECT_EQ(branched.stats.branching.branches, 4u);
    expectAgree(plain, rendertest::imageMean(branched.film), std::string("4 branches vs 1, ") +
                                                                 std::string(toString(sampler)));
  }
  SceneOverrides overrides;
  overrides.sampler = SamplerKind::Independent;
  overrides.branches = 1;
  const auto plain = rendertest::imageMean(rendertest::renderScene(room(false), overrides).film);
  overrides.guiding = GuidingMode::Paths;
  overrides.branches = 3;
  const rendertest::Rendered guided = rendertest::renderScene(room(false), overrides);
  EXPECT_TRUE(guided.stats.guiding.guided);
  expectAgree(plain, rendertest::imageMean(guided.film), "3 branches guided by paths vs 1 unguided");
}

// What branching is for: on the sky scene the light after the first vertex (the floor's and the
// spheres' indirect light) is noisy, so 4 branches lower the image's standard error per camera
// sample. Auto's probe measures how much: the variances before and after the first vertex
// predict the ratio of the two renders' errors, and it branches as they say.
TEST(Consistency, BranchesLowerTheErrorPerCameraSample) {
  const auto render = [](uint32_t branches) {
    SceneOverrides overrides;
    overrides.sampler = SamplerKind::Independent;
    overrides.branches = branches;
    return rendertest::renderScene(skyScene("adaptive"), overrides);
  };
  const rendertest::Rendered one = render(1), four = render(4), automatic = render(kAutoBranches);
  const Rgb a = rendertest::imageMean(one.film).standardError, b = rendertest::imageMean(four.film).standardError;
  std::printf("standard error of the image mean, 1 vs 4 branches: %.4g vs %.4g, %.4g vs %.4g, %.4g vs %.4g\n", a.r, b.r,
              a.g, b.g, a.b, b.b);
  EXPECT_LT(b.r, a.r);
  EXPECT_LT(b.g, a.g);
  EXPECT_LT(b.b, a.b);
  const BranchingStats& chosen = automatic.stats.branching;
  std::printf("auto: %u branches (%.2f rays before, %.2f per branch; variance %.4g before, %.4g per branch)\n",
              chosen.branches, chosen.raysBefore.value_or(0), chosen.raysAfter.value_or(0),
              chosen.varianceBefore.value_or(0), chosen.varianceAfter.value_or(0));
  ASSERT_TRUE(chosen.varianceBefore && chosen.varianceAfter);
  const double v0 = *chosen.varianceBefore, v1 = *chosen.varianceAfter;
  EXPECT_GT(v1, 0.0);
  // Variance with 1 branch over variance with 4, predicted and observed (green: most of the
  // luminance the variances are measured in).
  const double predicted = (v0 + v1) / (v0 + v1 / 4), observed = (a.g / b.g) * (a.g / b.g);
  std::printf("error ratio squared, 1 vs 4 branches: predicted %.3f, observed %.3f\n", predicted, observed);
  EXPECT_NEAR(predicted / observed, 1.0, 0.15);
  EXPECT_EQ(chosen.branches, branchesThatPay(*chosen.raysBefore, *chosen.raysAfter, v0, v1));
  EXPECT_EQ(one.stats.branching.branches, 1u);
  EXPECT_FALSE(one.stats.branching.raysBefore);
}

// Why the probe measures 8-sample means: a pixel's Sobol points stratify each other and lower the
// variance of its mean, before and after the branches, by how much the scene decides (on the smooth
// sky scene both parts drop 5-30x). A probe of single samples sees the same variance under either
// sampler (a pixel's first point is as random as an independent one).
TEST(Consistency, AutoBranchingMeasuresTheVarianceOfItsSamplersMeans) {
  const auto measured = [](SamplerKind sampler) {
    SceneOverrides overrides;
    overrides.sampler = sampler;
    overrides.spp = 1;
    const BranchingStats chosen = rendertest::renderScene(skyScene("adaptive"), overrides).stats.branching;
    EXPECT_TRUE(chosen.varianceBefore && chosen.varianceAfter);
    std::printf("%s: V0 %.4g, V1 %.4g\n", sampler == SamplerKind::Sobol ? "sobol" : "independent",
                chosen.varianceBefore.value_or(0), chosen.varianceAfter.value_or(0));
    return chosen.varianceBefore.value_or(0) + chosen.varianceAfter.value_or(0);
  };
  EXPECT_LT(measured(SamplerKind::Sobol), 0.5 * measured(SamplerKind::Independent));
}

// Where all of a sample's light comes after its first vertex and each point of it expects the same
// (a floor far wider than the view, under the sky, lit by BSDF samples alone), the light before the
// branches varies not at all: auto measures V0 about 0 and V1 positive. (V1 taken as the drop in
// variance from 1 to 4 branches, without its factor 4/3, would leave V0 about V1 / 3.) Independent
// samples: the measure alone, without Sobol points stratifying either part.
TEST(Consistency, AutoBranchingMeasuresNoVarianceBeforeTheFirstVertexWhereThereIsNone) {
  nlohmann::json scene = {
      {"camera", {{"eye", {0, 1, 0}}, {"target", {0.01, 0, 0}}, {"fov", 60}, {"width", 64}, {"height", 48}}},
      {"render",
       {{"spp", 2}, {"seed", 5}, {"max_depth", 1}, {"mis", "bsdf-only"}, {"branches", "auto"}, {"sampler", "independent"}}},
      {"environment", {{"type", "map"}, {"file", smoothSky()}}},
      {"materials", {{"floor", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
      {"shapes",
       {{{"type", "quad"},
         {"corner", {-1000, 0, -1000}},
         {"edge_u", {0, 0, 2000}},
         {"edge_v", {2000, 0, 0}},
         {"material", "floor"}}}},
  };
  const BranchingStats chosen = rendertest::renderScene(scene, {}).stats.branching;
  ASSERT_TRUE(chosen.varianceBefore && chosen.varianceAfter);
  std::printf("variance before the branches %.4g, per branch %.4g\n", *chosen.varianceBefore, *chosen.varianceAfter);
  EXPECT_GT(*chosen.varianceAfter, 0.0);
  EXPECT_LT(std::abs(*chosen.varianceBefore), 0.15 * *chosen.varianceAfter);
}

}  // namespace
}  // namespace acdf

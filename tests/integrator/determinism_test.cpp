// Determinism: every pixel sample has its own random stream, so an image depends on the seed
// only — not on the number of threads, nor on which part of the frame (crop window) is rendered.
// Branched paths too: where each branch's values start, and how auto chooses their number.

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include "acdf/integrator/path_integrator.h"
#include "acdf/sampling/table_cache.h"
#include "render_test_util.h"

namespace acdf {
namespace {

nlohmann::json smallScene(uint64_t seed) {
  return {
      {"camera", {{"eye", {0, 1, 4}}, {"target", {0, 0.5, 0}}, {"fov", 45}, {"width", 40}, {"height", 24}}},
      {"render", {{"spp", 4}, {"seed", seed}}},
      {"environment", {{"type", "map"}, {"file", "data/envmaps/sunset_1024x512.exr"}, {"sampling", "alias"}}},
      {"materials",
       {{"metal", {{"type", "ggx-conductor"}, {"preset", "gold"}}}, {"floor", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
      {"shapes",
       {{{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}, {"material", "metal"}},
        {{"type", "quad"},
         {"corner", {-5, 0, -5}},
         {"edge_u", {0, 0, 10}},
         {"edge_v", {10, 0, 0}},
         {"material", "floor"}}}},
  };
}

Image renderWithThreads(int threads, const nlohmann::json& scene, const SceneOverrides& overrides = {}) {
  tbb::task_arena arena(threads);
  Image image;
  arena.execute([&] { image = rendertest::renderScene(scene, overrides).film.image(); });
  return image;
}

TEST(Determinism, SameImageForAnyThreadCount) {
  const Image one = renderWithThreads(1, smallScene(1));
  EXPECT_EQ(one.pixels, renderWithThreads(2, smallScene(1)).pixels);
  EXPECT_EQ(one.pixels, renderWithThreads(4, smallScene(1)).pixels);
  EXPECT_NE(one.pixels, renderWithThreads(2, smallScene(2)).pixels) << "the seed must matter";
}

// Product direct lighting draws a number of candidates per vertex from Sampler::getCandidates(): the
// same for any thread count, with either sample source.
TEST(Determinism, ProductDirectLightingIsTheSameForAnyThreadCount) {
  for (const SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
    SceneOverrides overrides;
    overrides.direct = DirectLighting::Product;
    overrides.candidates = 3;
    overrides.sampler = sampler;
    const Image one = renderWithThreads(1, smallScene(1), overrides);
    EXPECT_EQ(one.pixels, renderWithThreads(2, smallScene(1), overrides).pixels) << toString(sampler);
    EXPECT_EQ(one.pixels, renderWithThreads(4, smallScene(1), overrides).pixels) << toString(sampler);
    EXPECT_NE(one.pixels, renderWithThreads(2, smallScene(2), overrides).pixels) << "the seed must matter";
    EXPECT_NE(one.pixels, renderWithThreads(1, smallScene(1), {}).pixels) << "product must change the image";
  }
}

// Guided renders learn from records kept per tile and joined in tile order, and auto decides from
// sums made the same way: the same image for any thread count.
TEST(Determinism, GuidedRendersAreTheSameForAnyThreadCount) {
  for (const GuidingMode guiding : {GuidingMode::Paths, GuidingMode::Auto}) {
    SceneOverrides overrides;
    overrides.guiding = guiding;
    overrides.spp = 8;
    const Image one = renderWithThreads(1, smallScene(1), overrides);
    EXPECT_EQ(one.pixels, renderWithThreads(2, smallScene(1), overrides).pixels) << toString(guiding);
    EXPECT_EQ(one.pixels, renderWithThreads(4, smallScene(1), overrides).pixels) << toString(guiding);
  }
  SceneOverrides guided;
  guided.guiding = GuidingMode::Light;
  guided.spp = 8;
  SceneOverrides plain;
  plain.spp = 8;
  EXPECT_NE(renderWithThreads(2, smallScene(1), guided).pixels, renderWithThreads(2, smallScene(1), plain).pixels)
      << "guiding must change the image";
}

// Light paths are traced per sample index from its own seed, and auto decides from sums made per
// pixel: the same image for any thread count, and connections change it.
TEST(Determinism, LightPathsAreTheSameForAnyThreadCount) {
  nlohmann::json scene = smallScene(1);
  scene["environment"]["portals"] = {{{"corner", {-1, 3, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 0, 2}}}};
  for (const LightPathMode mode : {LightPathMode::On, LightPathMode::Auto}) {
    SceneOverrides overrides;
    overrides.lightPaths = mode;
    overrides.spp = 10;
    const Image one = renderWithThreads(1, scene, overrides);
    EXPECT_EQ(one.pixels, renderWithThreads(2, scene, overrides).pixels) << toString(mode);
    EXPECT_EQ(one.pixels, renderWithThreads(4, scene, overrides).pixels) << toString(mode);
    if (mode == LightPathMode::On) {
      overrides.lightPaths = LightPathMode::Off;
      EXPECT_NE(one.pixels, renderWithThreads(2, scene, overrides).pixels) << "connections must change the image";
    }
  }
}

// Branched paths read their branches' own sample points: the same image for any thread count,
// and different from an unbranched one.
TEST(Determinism, BranchedRendersAreTheSameForAnyThreadCount) {
  for (const SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
    SceneOverrides overrides;
    overrides.branches = 3;
    overrides.sampler = sampler;
    const Image one = renderWithThreads(1, smallScene(1), overrides);
    EXPECT_EQ(one.pixels, renderWithThreads(2, smallScene(1), overrides).pixels) << toString(sampler);
    EXPECT_EQ(one.pixels, renderWithThreads(4, smallScene(1), overrides).pixels) << toString(sampler);
    overrides.branches = 1;
    EXPECT_NE(one.pixels, renderWithThreads(2, smallScene(1), overrides).pixels) << "branching must change it";
  }
}

// Auto's probe (renderer.h) has its own seed and ignores the crop: the branch count it chooses is the
// scene's, the same for any thread count and seed, and the image is the one that count renders.
TEST(Determinism, AutoBranchingChoosesTheSameForAnyThreadCountAndSeed) {
  nlohmann::json scene = smallScene(1);
  scene["render"]["spp"] = 2;
  SceneOverrides overrides;
  overrides.branches = kAutoBranches;
  std::vector<BranchingStats> chosen;
  for (const int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    arena.execute([&] { chosen.push_back(rendertest::renderScene(scene, overrides).stats.branching); });
  }
  chosen.push_back(rendertest::renderScene(smallScene(2), overrides).stats.branching);
  for (const BranchingStats& b : chosen) {
    ASSERT_TRUE(b.varianceBefore && b.varianceAfter);
    EXPECT_EQ(b.branches, chosen[0].branches);
    EXPECT_EQ(*b.varianceBefore, *chosen[0].varianceBefore);
    EXPECT_EQ(*b.varianceAfter, *chosen[0].varianceAfter);
  }
  const rendertest::Rendered automatic = rendertest::renderScene(scene, overrides);
  overrides.branches = chosen[0].branches;
  EXPECT_EQ(automatic.film.image().pixels, rendertest::renderScene(scene, overrides).film.image().pixels);
}

// The calls a path makes on its sampler, in order, with the values of a Sobol sampler behind them.
class RecordingSampler final : public Sampler {
 public:
  std::vector<std::string> calls;
  void startPixelSample(uint32_t x, uint32_t y, uint32_t s) override { inner_.startPixelSample(x, y, s); }
  void startVertex(uint32_t depth) override {
    calls.push_back("vertex " + std::to_string(depth));
    inner_.startVertex(depth);
  }
  float get1D() override {
    calls.push_back("1D");
    return inner_.get1D();
  }
  std::array<float, 2> get2D() override {
    calls.push_back("2D");
    return inner_.get2D();
  }
  CandidateValues getCandidates(uint32_t count) override { return inner_.getCandidates(count); }
  std::array<float, 2> getPixel2D() override { return inner_.getPixel2D(); }
  void startBranch(uint32_t branch, uint32_t branches) override {
    calls.push_back("branch " + std::to_string(branch) + "/" + std::to_string(branches));
    inner_.startBranch(branch, branches);
  }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<RecordingSampler>(*this); }

 private:
  SobolSampler inner_{1, 40};
};

// A path counts its continuations and those that escaped (what decides whether the map's pixel is
// loaded ahead): every one from a floor under the open sky escapes, none from inside a closed box.
TEST(RayCounts, ContinuationsAndTheirEscapes) {
  SceneAssets tables(TableCache::disabled());
  nlohmann::json open = smallScene(1);
  open["shapes"].erase(0);  // the floor alone
  nlohmann::json closed = smallScene(1);
  closed["shapes"] = {{{"type", "sphere"}, {"center", {0, 1, 4}}, {"radius", 2}, {"material", "floor"}}};
  const std::string path = std::string(ACDF_SOURCE_DIR) + "/test-scene.json";
  const Ray towardsTheFloor{{0, 1, 4}, normalize(Vec3d{0.3, -1, -1})};
  for (const bool sky : {true, false}) {
    const Scene scene = loadSceneText((sky ? open : closed).dump(), path, {}, tables);
    const PathIntegrator integrator(scene);
    IndependentSampler sampler(7, 1);
    RayCounts rays;
    for (uint32_t s = 0; s < 64; ++s) {
      sampler.startPixelSample(0, 0, s);
      (void)integrator.radiance(towardsTheFloor, sampler, rays);
    }
    EXPECT_GE(rays.continuations, 64u);
    EXPECT_EQ(rays.escapes, sky ? rays.continuations : 0u);
    EXPECT_EQ(rays.escapesLikely(), sky);
  }
}

// smallScene(1)'s integrator, and a camera ray onto its floor, for tests of single paths.
struct SmallScenePaths {
  SceneAssets tables{TableCache::disabled()};
  Scene scene = loadSceneText(smallScene(1).dump(), std::string(ACDF_SOURCE_DIR) + "/test-scene.json", {}, tables);
  PathIntegrator integrator{scene};
  Ray towardsTheFloor{{0, 1, 4}, normalize(Vec3d{0.3, -1, -1})};
};

// A path with K branches starts each after its first vertex's light sample and before that
// vertex's BSDF sample, in order, so each reads its own points (sampler.h); with one it starts none.
TEST(Branching, EachBranchStartsBeforeItsFirstBsdfSample) {
  const SmallScenePaths paths;
  const PathIntegrator& integrator = paths.integrator;
  const Ray& towardsTheFloor = paths.towardsTheFloor;
  for (const uint32_t branches : {1u, 3u}) {
    RecordingSampler sampler;
    sampler.startPixelSample(0, 0, 0);
    RayCounts rays;
    (void)integrator.radiance(towardsTheFloor, sampler, rays, {}, branches);
    std::vector<std::string> started;
    for (std::size_t i = 0; i < sampler.calls.size(); ++i)
      if (sampler.calls[i].starts_with("branch")) {
        started.push_back(sampler.calls[i]);
        ASSERT_LT(i + 1, sampler.calls.size());
        EXPECT_EQ(sampler.calls[i + 1], "2D") << "the BSDF sample of vertex 0 follows " << sampler.calls[i];
      }
    if (branches == 1) {
      EXPECT_TRUE(started.empty());
    } else {
      EXPECT_EQ(started, (std::vector<std::string>{"branch 0/3", "branch 1/3", "branch 2/3"}));
      ASSERT_GE(sampler.calls.size(), 3u);
      EXPECT_EQ(sampler.calls[0], "vertex 0");
      EXPECT_EQ(sampler.calls[1], "2D") << "the light sample, shared";
      EXPECT_EQ(sampler.calls[2], "branch 0/3");
    }
    EXPECT_GT(rays.afterFirstVertex, 0u);
    EXPECT_GT(rays.total, rays.afterFirstVertex);
  }
}

// Auto branching takes the K that makes (V0 + V1 / K)(c0 + K c1) least, from the rays a camera
// sample casts before its first bounce (c0) and a branch after it (c1) and the variances measured
// before (V0) and after (V1).
TEST(Branching, AutoTakesTheCountThatMinimisesVarianceTimesCost) {
  for (const double before : {0.5, 1.0, 1.65, 2.0, 6.0}) {
    for (const double after : {0.25, 1.0, 7.7}) {
      for (const double ratio : {0.5, 1.0, 2.0, 4.0, 16.0}) {
        const uint32_t chosen = branchesThatPay(before, after, 0.1, 0.1 * ratio);
        const auto figure = [&](double k) { return (1.0 + ratio / k) * (before + k * after); };
        double best = figure(1);
        for (uint32_t k = 2; k <= kMaxAutoBranches; ++k) best = std::min(best, figure(k));
        const std::string what = std::to_string(before) + " " + std::to_string(after) + " " + std::to_string(ratio);
        if (best * kBranchingMargin <= figure(1))
          EXPECT_NEAR(figure(chosen), best, 1e-12 * best) << what;
        else
          EXPECT_EQ(chosen, 1u) << what << ": branches promise too little";
      }
    }
  }
  // Measured on the first sample of bench/peers/scenes/spheres.json, scenes/demo.json,
  // scenes/room.json and scenes/door-ajar.json (seed 1).
  EXPECT_EQ(branchesThatPay(1.65, 1.01, 0.072, 0.171), 2u);
  EXPECT_EQ(branchesThatPay(1.65, 1.35, 0.093, 0.099), 1u);
  EXPECT_EQ(branchesThatPay(1.98, 7.23, 0.192, 1.53), 1u);  // 2 would promise 1.01x
  EXPECT_EQ(branchesThatPay(2.0, 7.49, 7.27, 24.8), 1u);
  EXPECT_EQ(branchesThatPay(2.0, 0.0, 0.1, 0.0), 1u);  // nothing after the first vertex (max_depth 1 and sky)
  EXPECT_EQ(branchesThatPay(2.0, 1.0, 0.1, 0.0), 1u);  // nothing varies after it
  // All of the spread after the first vertex (the spread of neighbours, less than the branches',
  // gave a negative V0): branches cost only their own rays, so the most.
  EXPECT_EQ(branchesThatPay(2.0, 1.0, -0.05, 0.3), kMaxAutoBranches);
}

// Where paths draw no light samples (product direct lighting, bsdf-only MIS) auto has no light to
// guide: it learns nothing and renders what off renders.
TEST(Determinism, AutoWithoutLightSamplesLearnsNothing) {
  for (const bool product : {true, false}) {
    SceneOverrides overrides;
    overrides.spp = 8;
    if (product)
      overrides.direct = DirectLighting::Product;
    else
      overrides.mis = MisMode::BsdfOnly;
    const Image off = rendertest::renderScene(smallScene(1), overrides).film.image();
    overrides.guiding = GuidingMode::Auto;
    const rendertest::Rendered automatic = rendertest::renderScene(smallScene(1), overrides);
    EXPECT_EQ(automatic.stats.guiding.trainingPasses, 0u) << (product ? "product" : "bsdf-only");
    EXPECT_FALSE(automatic.stats.guiding.measuredGain.has_value());
    EXPECT_EQ(automatic.film.image().pixels, off.pixels) << (product ? "product" : "bsdf-only");
  }
}

// A black image has no relative variance to compare: auto measures no gain and stays off.
TEST(Determinism, AutoMeasuresNoGainOnABlackImage) {
  nlohmann::json scene = smallScene(1);
  scene["environment"] = {{"type", "constant"}, {"radiance", 0}};
  SceneOverrides overrides;
  overrides.guiding = GuidingMode::Auto;
  const rendertest::Rendered black = rendertest::renderScene(scene, overrides);
  ASSERT_TRUE(black.stats.guiding.measuredGain.has_value());
  EXPECT_EQ(*black.stats.guiding.measuredGain, 1.0);
  EXPECT_FALSE(black.stats.guiding.guided);
}

TEST(Determinism, CropWindowsReproduceTheirPartOfTheFrame) {
  const Image full = renderWithThreads(2, smallScene(1));
  // Two pieces a render farm could render separately: the left 15 columns and the rest.
  for (const CropWindow crop : {CropWindow{0, 0, 15, 24}, CropWindow{15, 5, 40, 24}}) {
    SceneOverrides overrides;
    overrides.crop = crop;
    const Image piece = renderWithThreads(2, smallScene(1), overrides);
    ASSERT_EQ(piece.width, crop.width());
    ASSERT_EQ(piece.height, crop.height());
    for (uint32_t y = 0; y < piece.height; ++y)
      for (uint32_t x = 0; x < piece.width; ++x)
        for (uint32_t c = 0; c < 3; ++c)
          ASSERT_EQ(piece.pixels[3 * (y * piece.width + x) + c],
                    full.pixels[3 * ((crop.y0 + y) * full.width + crop.x0 + x) + c])
              << "pixel " << crop.x0 + x << "," << crop.y0 + y;
  }
}

}  // namespace
}  // namespace acdf

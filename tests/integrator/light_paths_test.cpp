// Light paths through the portals (light_paths.h): the density the connections and the MIS weights
// use is the density the paths are traced with, and a pool depends on its seed and sample index
// alone.

#include "acdf/integrator/light_paths.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "render_test_util.h"

namespace acdf {
namespace {

// A 2 × 2 floor under a constant sky of radiance 1 seen through a 0.6 × 0.4 portal 1 above it,
// facing down: nothing else, so a light path either reaches the floor or misses it.
Scene floorUnderPortal() {
  static SceneAssets tables(TableCache::disabled());
  const nlohmann::json scene = {
      {"camera", {{"eye", {0, 3, 3}}, {"target", {0, 0, 0}}, {"fov", 40}, {"width", 8}, {"height", 6}}},
      {"environment",
       {{"type", "constant"},
        {"radiance", {1, 1, 1}},
        {"portals", {{{"corner", {-0.3, 1, -0.2}}, {"edge_u", {0.6, 0, 0}}, {"edge_v", {0, 0, 0.4}}}}}}},
      {"materials", {{"floor", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}}}}},
      {"shapes",
       {{{"type", "quad"}, {"corner", {-1, 0, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 0, 2}}, {"material", "floor"}}}},
  };
  return loadSceneText(scene.dump(), std::string(ACDF_SOURCE_DIR) + "/test-scene.json", {}, tables);
}

// Light paths estimate ∫_floor ∫_{ω through the portal} |n · ω| dω dA (each vertex's
// L |n · ω| / p_C with L = 1): the same integral as ∫_floor ∫_portal cosθ_y cosθ_p / d² dA_p dA_y,
// found here by the midpoint rule. A density off by any factor, or missing a term of its sum,
// moves the estimate by that factor.
TEST(LightPaths, DensityIsTheDensityPathsAreTracedWith) {
  const Scene scene = floorUnderPortal();
  const LightPathSource source(scene);
  ASSERT_FALSE(source.empty());
  constexpr uint32_t kAttempts = 1u << 17;
  const LightPathPool pool(source, 7, 0, kAttempts);
  double sum = 0, sumSquares = 0;
  for (const LightVertex& v : pool.vertices()) {
    const double w = v.radianceOverPdf.luminance();
    EXPECT_NEAR(w, std::abs(v.hit.normal.y * v.toLight.y) / v.density, 1e-5 * w);
    EXPECT_NEAR(v.density, source.density(v.hit.position, v.hit.normal, v.toLight), 1e-12 * v.density);
    sum += w;
    sumSquares += w * w;
  }
  EXPECT_GT(pool.successShare(), 0.1);
  const double mean = sum / kAttempts;
  const double error = std::sqrt((sumSquares / kAttempts - mean * mean) / (kAttempts - 1));

  constexpr int kFloorCells = 64, kPortalCells = 16;
  double reference = 0;
  for (int i = 0; i < kFloorCells; ++i)
    for (int j = 0; j < kFloorCells; ++j) {
      const Vec3d y{-1 + 2 * (i + 0.5) / kFloorCells, 0, -1 + 2 * (j + 0.5) / kFloorCells};
      for (int a = 0; a < kPortalCells; ++a)
        for (int b = 0; b < kPortalCells; ++b) {
          const Vec3d p{-0.3 + 0.6 * (a + 0.5) / kPortalCells, 1, -0.2 + 0.4 * (b + 0.5) / kPortalCells};
          const Vec3d d = p - y;
          const double d2 = dot(d, d);
          reference += (d.y * d.y) / (d2 * d2) * (0.6 * 0.4 / (kPortalCells * kPortalCells));
        }
    }
  reference *= 4.0 / (kFloorCells * kFloorCells);
  EXPECT_NEAR(mean, reference, 4 * error + 1e-3 * reference) << "standard error " << error;
}

// Off the portal's cone, and from behind its plane, no light path reaches a point.
TEST(LightPaths, DensityIsZeroWhereNoPathPasses) {
  const Scene scene = floorUnderPortal();
  const LightPathSource source(scene);
  const Vec3d up{0, 1, 0};
  EXPECT_GT(source.density({0, 0, 0}, up, up), 0);
  EXPECT_EQ(source.density({0.9, 0, 0}, up, up), 0);                       // straight up misses the portal
  EXPECT_EQ(source.density({0, 2, 0}, up, up), 0);                         // above it
  EXPECT_EQ(source.density({0, 0, 0}, up, normalize(Vec3d{1, -1, 0})), 0);  // downwards
}

// A pool is its seed's and sample index's: the same vertices in the same order on any thread count.
TEST(LightPaths, PoolsDependOnSeedAndSampleIndexAlone) {
  const Scene scene = floorUnderPortal();
  const LightPathSource source(scene);
  const LightPathPool a(source, 3, 5, 4096), b(source, 3, 5, 4096), c(source, 3, 6, 4096);
  ASSERT_EQ(a.vertices().size(), b.vertices().size());
  for (std::size_t i = 0; i < a.vertices().size(); ++i) {
    EXPECT_EQ(a.vertices()[i].hit.position, b.vertices()[i].hit.position);
    EXPECT_EQ(a.vertices()[i].toLight, b.vertices()[i].toLight);
  }
  EXPECT_NE(a.vertices().front().hit.position, c.vertices().front().hit.position);
}

}  // namespace
}  // namespace acdf

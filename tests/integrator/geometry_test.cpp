// Ray queries (geometry.h): rays traced in Embree's packets find what each traced alone finds —
// the same surface and side, the same point up to Embree's float distance — for full and partial
// packets and rays too few for a packet, hits and misses alike.
#include "acdf/integrator/geometry.h"

#include <gtest/gtest.h>

#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "acdf/sampling/rng.h"

namespace acdf {
namespace {

TriangleMesh quad(const Vec3d& corner, const Vec3d& u, const Vec3d& v, uint32_t material) {
  TriangleMesh mesh;
  mesh.positions = {corner, corner + u, corner + u + v, corner + v};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.material = material;
  return mesh;
}

TEST(Geometry, PacketsFindTheHitsOfSingleRays) {
  const Geometry geometry({Sphere{{0, 1, 0}, 1, 0}, Sphere{{1.5, 0.4, -1}, 0.4, 1}},
                          {quad({-5, 0, -5}, {10, 0, 0}, {0, 0, 10}, 2), quad({-3, 0, -3}, {6, 0, 0}, {0, 3, 0}, 3)});
  Pcg32 rng(11);
  // 37 rays: two full packets and a partial one; from points in front of the scene towards it, and
  // some up into the sky, which miss.
  std::vector<Ray> rays;
  for (int i = 0; i < 37; ++i) {
    const Vec3d origin{rng.nextDouble() - 0.5, 1 + rng.nextDouble(), 4};
    const Vec3d target{4 * rng.nextDouble() - 2, 3 * rng.nextDouble() - 0.5, -2 * rng.nextDouble()};
    rays.push_back({origin, normalize(i % 5 == 4 ? Vec3d{0.1, 1, 0.2} : target - origin)});
  }
  // The last 5 rays make a partial packet; without them, the last 2 are too few for one and go alone.
  std::vector<std::optional<SurfaceHit>> packed(rays.size()), fewer(34);
  geometry.intersectCoherent(rays, packed);
  geometry.intersectCoherent(std::span(rays).first(fewer.size()), fewer);
  for (std::size_t i = 0; i < fewer.size(); ++i) ASSERT_EQ(fewer[i].has_value(), packed[i].has_value()) << i;
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    SCOPED_TRACE("ray " + std::to_string(i));
    if (i < fewer.size() && fewer[i]) {
      EXPECT_EQ(fewer[i]->material, packed[i]->material);
      EXPECT_NEAR(fewer[i]->distance, packed[i]->distance, 1e-5 * packed[i]->distance);
    }
    const std::optional<SurfaceHit> single = geometry.intersect(rays[i]);
    ASSERT_EQ(packed[i].has_value(), single.has_value());
    if (!single) continue;
    ++hits;
    EXPECT_EQ(packed[i]->material, single->material);
    EXPECT_NEAR(packed[i]->distance, single->distance, 1e-5 * single->distance);
    EXPECT_NEAR(length(packed[i]->position - single->position), 0.0, 1e-5);
    EXPECT_NEAR(length(packed[i]->normal - single->normal), 0.0, 1e-6);
  }
  EXPECT_GE(hits, 20u);
  EXPECT_LE(hits, 33u);  // the rays into the sky miss
}

TEST(Geometry, PacketsNeedAHitPerRay) {
  const Geometry geometry({Sphere{{0, 0, 0}, 1, 0}}, {});
  const std::vector<Ray> rays(3, Ray{{0, 0, 5}, {0, 0, -1}});
  std::vector<std::optional<SurfaceHit>> hits(2);
  EXPECT_THROW(geometry.intersectCoherent(rays, hits), std::invalid_argument);
}

}  // namespace
}  // namespace acdf

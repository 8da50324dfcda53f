// The openings found by tracing (openings.h): a room's window becomes one portal covering it and
// facing in, two windows of one wall two, an open scene and a sealed room none, the same every
// time whatever the threads; and a scene gets them only when it declares none and lets it look.
#include "acdf/integrator/openings.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <vector>

#include "render_test_util.h"

namespace acdf {
namespace {

TriangleMesh quad(const Vec3d& corner, const Vec3d& u, const Vec3d& v) {
  TriangleMesh mesh;
  mesh.positions = {corner, corner + u, corner + u + v, corner + v};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

struct Window {
  double x0, x1, y0, y1;  // in the wall z = 2
};

// A room x, z in [-2, 2], y in [0, 2.6] whose wall z = 2 has these windows (separated along x,
// in order), the wall around them in strips.
std::vector<TriangleMesh> room(const std::vector<Window>& windows) {
  std::vector<TriangleMesh> walls = {
      quad({-2, 0, -2}, {4, 0, 0}, {0, 0, 4}),   quad({-2, 2.6, -2}, {4, 0, 0}, {0, 0, 4}),
      quad({-2, 0, -2}, {4, 0, 0}, {0, 2.6, 0}), quad({-2, 0, -2}, {0, 0, 4}, {0, 2.6, 0}),
      quad({2, 0, -2}, {0, 0, 4}, {0, 2.6, 0})};
  double x = -2;
  for (const Window& w : windows) {
    walls.push_back(quad({x, 0, 2}, {w.x0 - x, 0, 0}, {0, 2.6, 0}));
    walls.push_back(quad({w.x0, 0, 2}, {w.x1 - w.x0, 0, 0}, {0, w.y0, 0}));
    walls.push_back(quad({w.x0, w.y1, 2}, {w.x1 - w.x0, 0, 0}, {0, 2.6 - w.y1, 0}));
    x = w.x1;
  }
  walls.push_back(quad({x, 0, 2}, {2 - x, 0, 0}, {0, 2.6, 0}));
  return walls;
}

Camera inside() { return Camera({-1.5, 1.6, -1.6}, {0.5, 0.9, 1.5}, {0, 1, 0}, 75, 64, 48, {0, 0, 64, 48}); }

// The portal's extent parallel to the wall z = 2, and whether it faces into the room (-z). It lies
// in a plane just inside the wall (openings.h: never outside it, where the wall's outer face would
// see it edge-on).
struct Extent {
  double x0, x1, y0, y1;
  bool inwards;
};
Extent extentOf(const Portal& p) {
  const Vec3d far = p.corner + p.edgeU + p.edgeV;
  EXPECT_LT(p.corner.z, 2.0);
  EXPECT_GT(p.corner.z, 1.98);
  EXPECT_DOUBLE_EQ(far.z, p.corner.z);
  return {std::min(p.corner.x, far.x), std::max(p.corner.x, far.x), std::min(p.corner.y, far.y),
          std::max(p.corner.y, far.y), cross(p.edgeU, p.edgeV).z < 0};
}

// Covers the window, by at most 2 % of the wall's size beyond each edge.
void expectCovers(const Portal& portal, const Window& w) {
  const Extent e = extentOf(portal);
  EXPECT_TRUE(e.inwards);
  EXPECT_LE(e.x0, w.x0);
  EXPECT_GE(e.x0, w.x0 - 0.08);
  EXPECT_GE(e.x1, w.x1);
  EXPECT_LE(e.x1, w.x1 + 0.08);
  EXPECT_LE(e.y0, w.y0);
  EXPECT_GE(e.y0, w.y0 - 0.052);
  EXPECT_GE(e.y1, w.y1);
  EXPECT_LE(e.y1, w.y1 + 0.052);
}

TEST(Openings, AWindowBecomesOnePortalCoveringItAndFacingIn) {
  const Window window{-0.7, 0.7, 0.9, 2.0};
  const Geometry geometry({}, room({window}));
  const OpeningSearch search = findOpenings(geometry, inside());
  EXPECT_GT(search.points, 48u * 36u * 9 / 10);  // the rest see the sky through the window
  EXPECT_LE(search.points, 48u * 36u);
  EXPECT_LT(search.escapedShare(), 0.1);
  EXPECT_GE(search.escaped, 1000u);
  ASSERT_EQ(search.openings.size(), 1u);
  expectCovers(search.openings[0], window);
}

TEST(Openings, TwoWindowsOfOneWallAreTwoPortals) {
  const Window left{-1.6, -0.6, 0.9, 2.0}, right{0.6, 1.4, 1.0, 1.8};
  const Geometry geometry({}, room({left, right}));
  const OpeningSearch search = findOpenings(geometry, inside());
  ASSERT_EQ(search.openings.size(), 2u);
  const bool leftFirst = extentOf(search.openings[0]).x0 < 0;
  expectCovers(search.openings[leftFirst ? 0 : 1], left);
  expectCovers(search.openings[leftFirst ? 1 : 0], right);
}

TEST(Openings, AnOpenSceneAndASealedRoomHaveNone) {
  const Geometry open({Sphere{{0, 1, 0}, 1, 0}}, {quad({-5, 0, -5}, {10, 0, 0}, {0, 0, 10})});
  const OpeningSearch underSky =
      findOpenings(open, Camera({0, 2, 6}, {0, 1, 0}, {0, 1, 0}, 50, 64, 48, {0, 0, 64, 48}));
  EXPECT_GE(underSky.escapedShare(), kMaxEscapedShare);
  EXPECT_TRUE(underSky.openings.empty());

  std::vector<TriangleMesh> sealed = room({});
  const Geometry closed({}, std::move(sealed));
  const OpeningSearch shut = findOpenings(closed, inside());
  EXPECT_EQ(shut.escaped, 0u);
  EXPECT_GT(shut.rays, 48u * 36u * 32u);  // it kept looking, up to its last round
  EXPECT_TRUE(shut.openings.empty());

  const OpeningSearch sky = findOpenings(open, Camera({0, 20, 6}, {0, 30, 0}, {0, 1, 0}, 30, 64, 48, {0, 0, 64, 48}));
  EXPECT_EQ(sky.points, 0u);
  EXPECT_TRUE(sky.openings.empty());
}

TEST(Openings, TheSameWhateverTheThreads) {
  const Geometry geometry({}, room({{-1.6, -0.6, 0.9, 2.0}, {0.6, 1.4, 1.0, 1.8}}));
  const OpeningSearch many = findOpenings(geometry, inside());
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const OpeningSearch single = findOpenings(geometry, inside());
  EXPECT_EQ(many.rays, single.rays);
  EXPECT_EQ(many.escaped, single.escaped);
  ASSERT_EQ(many.openings.size(), single.openings.size());
  for (std::size_t i = 0; i < many.openings.size(); ++i) {
    EXPECT_EQ(many.openings[i].corner, single.openings[i].corner);
    EXPECT_EQ(many.openings[i].edgeU, single.openings[i].edgeU);
    EXPECT_EQ(many.openings[i].edgeV, single.openings[i].edgeV);
  }
}

}  // namespace
}  // namespace acdf

// The lat-long mapping against OpenEXR's own (Imf::LatLongMap, ImfEnvmap.h), the convention
// lat_long.h promises: OpenEXR's pixel centres run from pole to pole and seam to seam, acdf's sit at
// the centres of equal cells, so every acdf pixel centre must lie within half a pixel of OpenEXR's
// centre of the same pixel along each axis, and OpenEXR must map it back into that pixel.

#include <gtest/gtest.h>

#include <Imath/ImathBox.h>
#include <Imath/ImathVec.h>
#include <OpenEXR/ImfEnvmap.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "acdf/envmap/lat_long.h"

namespace {

using namespace acdf;
constexpr double kPi = std::numbers::pi;

// The angle between two unit vectors, accurate for small angles too.
double angleBetween(const Vec3d& a, const Vec3d& b) { return 2.0 * std::asin(std::min(1.0, length(a - b) / 2.0)); }

// About 128 indices spread over [0, n), the first and last included.
std::vector<uint32_t> spread(uint32_t n) {
  std::vector<uint32_t> out;
  const uint32_t step = std::max(1u, n / 128);
  for (uint32_t i = 0; i < n; i += step) out.push_back(i);
  if (out.back() != n - 1) out.push_back(n - 1);
  return out;
}

TEST(OpenExrLatLong, PixelCentresAreWithinHalfAPixelOfOpenExrs) {
  for (auto [width, height] : {std::pair{16u, 8u}, std::pair{37u, 11u}, std::pair{100u, 50u}, std::pair{1024u, 512u},
                               std::pair{4096u, 2048u}}) {
    const LatLongMapping mapping(width, height);
    const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(int(width) - 1, int(height) - 1));
    const double halfRow = kPi / (2.0 * height), halfColumn = kPi / width;
    for (uint32_t r : spread(height)) {
      for (uint32_t c : spread(width)) {
        // The centre of the pixel's (θ, φ) cell, which must be the cell pixelOf() puts it in.
        const Vec3d ours = LatLongMapping::direction(kPi * (r + 0.5) / height, 2 * kPi * (c + 0.5) / width);
        ASSERT_EQ(mapping.pixelOf(ours), (PixelIndex{r, c}));
        const Imath::V3f d = Imf::LatLongMap::direction(window, Imath::V2f(float(c), float(r)));
        const Vec3d theirs = normalize(Vec3d{d.x, d.y, d.z});
        // Along each axis within half a pixel: θ within half a row, φ within half a column (the
        // angle along the parallel is sin θ times that).
        const double theta = LatLongMapping::theta(ours);
        const double dTheta = std::abs(theta - LatLongMapping::theta(theirs));
        EXPECT_LE(dTheta, halfRow * (1 + 1e-5) + 1e-6) << width << "x" << height << " pixel " << r << "," << c;
        EXPECT_LE(angleBetween(ours, theirs), std::hypot(halfRow, std::sin(theta) * halfColumn) * (1 + 1e-5) + 1e-6)
            << width << "x" << height << " pixel " << r << "," << c;
        // OpenEXR puts our centre back into the same pixel: within (c ± ½, r ± ½) exactly, which
        // OpenEXR's float positions (resolution 2.4e-4 at x = 4095) may round to ½.
        const Imath::V2f p =
            Imf::LatLongMap::pixelPosition(window, Imath::V3f(float(ours.x), float(ours.y), float(ours.z)));
        EXPECT_LE(std::abs(p.x - float(c)), 0.5f) << width << "x" << height << " pixel " << r << "," << c;
        EXPECT_LE(std::abs(p.y - float(r)), 0.5f) << width << "x" << height << " pixel " << r << "," << c;
      }
    }
  }
}

// The axes OpenEXR documents: latitude 0, longitude 0 is +Z (the centre column); longitude π/2 is
// +X, a quarter of the way across (longitude falls from π at the left edge to −π at the right).
TEST(OpenExrLatLong, AxesAreOpenExrs) {
  const LatLongMapping mapping(1024, 512);
  const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(1023, 511));
  for (const Vec3d& axis : {Vec3d{1, 0, 0}, Vec3d{-1, 0, 0}, Vec3d{0, 0, 1}, Vec3d{0, 0, -1}, Vec3d{0, 1, 0}}) {
    const PixelIndex ours = mapping.pixelOf(axis);
    const Imath::V2f theirs =
        Imf::LatLongMap::pixelPosition(window, Imath::V3f(float(axis.x), float(axis.y), float(axis.z)));
    // OpenEXR's −Z lies on the seam (x = 0 or x = W − 1, one pixel position for both edges).
    const float dx = std::abs(theirs.x - (ours.column + 0.5f) * 1023.0f / 1024.0f);
    EXPECT_LT(std::min(dx, 1023.0f - dx), 1.0f) << axis.x << "," << axis.y << "," << axis.z;
    EXPECT_LT(std::abs(theirs.y - (ours.row + 0.5f) * 511.0f / 512.0f), 1.0f);
  }
  EXPECT_EQ(mapping.pixelOf({1, 0, 0}).column, 256u);  // +X a quarter of the way across
  EXPECT_EQ(mapping.pixelOf({0, 0, 1}).column, 512u);  // +Z in the centre column
  EXPECT_EQ(mapping.pixelOf({-1, 0, 0}).column, 768u);
}

}  // namespace

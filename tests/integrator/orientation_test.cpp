// Renders of the background show an environment map the way OpenEXR lays it out: +X a quarter of
// the way across the image (Imf::LatLongMap), the centre column +Z, and the picture unmirrored.
// The maps are written pixel by pixel from that layout, not through acdf::LatLongMapping, so the
// renderer's mapping is checked against the convention rather than against itself.

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "acdf/envmap/image_file.h"
#include "render_test_util.h"

namespace acdf {
namespace {

constexpr uint32_t kMapWidth = 64, kMapHeight = 32;

// A 64 × 32 EXR whose pixel (row, column) has colour(row, column), removed when the test ends.
class MapFile {
 public:
  explicit MapFile(const std::function<Rgb(uint32_t, uint32_t)>& colour)
      : path_((std::filesystem::temp_directory_path() /
               ("acdf_orientation_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++) + ".exr"))
                  .string()) {
    Image image;
    image.width = kMapWidth;
    image.height = kMapHeight;
    image.channels = 3;
    for (uint32_t r = 0; r < kMapHeight; ++r)
      for (uint32_t c = 0; c < kMapWidth; ++c) {
        const Rgb v = colour(r, c);
        image.pixels.insert(image.pixels.end(), {v.r, v.g, v.b});
      }
    writeExr(path_, image);
  }
  ~MapFile() { std::filesystem::remove(path_); }
  MapFile(const MapFile&) = delete;
  MapFile& operator=(const MapFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::string path_;
};

// The background alone (no shapes) seen by a camera at the origin looking at `target`, +Y up,
// under the map turned by `rotation` degrees about +Y.
Film renderBackground(const std::string& map, const Vec3d& target, uint32_t size, double fov, double rotation = 0) {
  const nlohmann::json scene = {
      {"camera",
       {{"eye", {0, 0, 0}},
        {"target", {target.x, target.y, target.z}},
        {"fov", fov},
        {"width", size},
        {"height", size}}},
      {"render", {{"spp", 4}, {"seed", 1}}},
      {"environment", {{"type", "map"}, {"file", map}, {"rotation", rotation}, {"sampling", "uniform"}}},
      {"materials", nlohmann::json::object()},
      {"shapes", nlohmann::json::array()},
  };
  return rendertest::renderScene(scene).film;
}

// A 2 × 2 pixel mark around +X: OpenEXR's longitude π/2 at latitude 0 is the corner shared by
// columns 15 and 16 (a quarter of the way across) and rows 15 and 16 (the equator).
MapFile markAtPlusX() {
  return MapFile([](uint32_t r, uint32_t c) {
    const bool mark = (r == 15 || r == 16) && (c == 15 || c == 16);
    return mark ? Rgb{1, 1, 1} : Rgb{};
  });
}

// The mark spans 11.25° each way; a 30° view over 31 pixels shows it about 12 pixels wide, centred.
void expectMarkCentred(const Film& film) {
  const uint32_t kSize = film.width();
  double sum = 0, sumX = 0, sumY = 0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const double v = film.mean(x, y).r;
      sum += v;
      sumX += v * x;
      sumY += v * y;
    }
  ASSERT_GT(sum, 0.0) << "the mark is not in view at all";
  EXPECT_GT(film.mean(kSize / 2, kSize / 2).r, 0.99) << "the centre of the view must be the mark";
  EXPECT_NEAR(sumX / sum, (kSize - 1) / 2.0, 0.5);
  EXPECT_NEAR(sumY / sum, (kSize - 1) / 2.0, 0.5);
  EXPECT_EQ(film.mean(0, 0).r, 0.0);
  EXPECT_EQ(film.mean(kSize - 1, kSize - 1).r, 0.0);
}

TEST(Orientation, MarkAtPlusXAppearsInTheCentreOfAViewAlongPlusX) {
  const MapFile map = markAtPlusX();
  expectMarkCentred(renderBackground(map.path(), {1, 0, 0}, 31, 30));
}

// The scene's rotation is right-handed about +Y (docs/scene-format.md): 90° turns +X to −Z.
TEST(Orientation, RotationTurnsTheMapCounterClockwiseSeenFromAbove) {
  const MapFile map = markAtPlusX();
  expectMarkCentred(renderBackground(map.path(), {0, 0, -1}, 31, 30, 90));
}

// Red fills the map's columns 17–30 (between +X and +Z, left of the image's centre), blue the
// columns 33–46 (right of it), both between the rows 10 and 21 around the horizon. Looking along
// +Z (the centre column), red must be on the left of the render and blue on the right, as in the
// image: a mirrored mapping swaps them.
TEST(Orientation, AnAsymmetricMapAppearsUnmirrored) {
  const MapFile map([](uint32_t r, uint32_t c) {
    if (r < 10 || r > 21) return Rgb{};
    if (c >= 17 && c <= 30) return Rgb{1, 0, 0};
    if (c >= 33 && c <= 46) return Rgb{0, 0, 1};
    return Rgb{};
  });
  constexpr uint32_t kSize = 32;
  const Film film = renderBackground(map.path(), {0, 0, 1}, kSize, 60);
  double redLeft = 0, redRight = 0, blueLeft = 0, blueRight = 0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const Rgb v = film.mean(x, y);
      (x < kSize / 2 ? redLeft : redRight) += v.r;
      (x < kSize / 2 ? blueLeft : blueRight) += v.b;
    }
  EXPECT_GT(redLeft, 0.0);
  EXPECT_EQ(redRight, 0.0) << "red (left of the map's centre) appears on the right: the view is mirrored";
  EXPECT_GT(blueRight, 0.0);
  EXPECT_EQ(blueLeft, 0.0) << "blue (right of the map's centre) appears on the left: the view is mirrored";
}

}  // namespace
}  // namespace acdf

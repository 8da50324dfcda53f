#include "envmap_test_util.h"

#include <cmath>
#include <filesystem>
#include <vector>

#include "acdf/sampling/rng.h"

namespace acdf::envmaptest {

namespace fs = std::filesystem;

std::shared_ptr<const EnvironmentMap> makeMap(uint32_t width, uint32_t height,
                                              const std::function<Rgb(uint32_t, uint32_t)>& rgb) {
  std::vector<float> values(std::size_t{width} * height * 3);
  for (uint32_t r = 0; r < height; ++r)
    for (uint32_t c = 0; c < width; ++c) {
      const Rgb v = rgb(r, c);
      float* out = &values[3 * (std::size_t{r} * width + c)];
      out[0] = v.r;
      out[1] = v.g;
      out[2] = v.b;
    }
  return std::make_shared<const EnvironmentMap>(width, height, std::move(values));
}

std::shared_ptr<const EnvironmentMap> onePixelMap(uint32_t width, uint32_t height, uint32_t row, uint32_t column,
                                                  float value) {
  return makeMap(width, height, [&](uint32_t r, uint32_t c) {
    return r == row && c == column ? Rgb{value, value, value} : Rgb{};
  });
}

std::shared_ptr<const EnvironmentMap> constantMap(uint32_t width, uint32_t height, float value) {
  return makeMap(width, height, [&](uint32_t, uint32_t) { return Rgb{value, value, value}; });
}

std::shared_ptr<const EnvironmentMap> smoothMap(uint32_t width, uint32_t height) {
  return makeMap(width, height, [&](uint32_t r, uint32_t c) {
    const double v = (r + 0.5) / height, u = (c + 0.5) / width;
    const double base = 0.2 + std::exp(-((u - 0.3) * (u - 0.3) + (v - 0.4) * (v - 0.4)) / 0.02);
    return Rgb{static_cast<float>(base * (1.0 + 0.5 * u)), static_cast<float>(base),
               static_cast<float>(base * (1.5 - v))};
  });
}

std::string sharedEnvmap(const std::string& name) {
  const fs::path path = fs::path(ACDF_SHARED_ENVMAPS) / name;
  return fs::is_regular_file(path) ? path.string() : std::string();
}

void expectSameSamples(const EnvironmentLight& a, const LightSampleContext& contextA, const EnvironmentLight& b,
                       const LightSampleContext& contextB, uint64_t seed, int count) {
  Pcg32 rng(seed);
  for (int i = 0; i < count; ++i) {
    const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
    const LightSample sa = a.sample(contextA, u0, u1), sb = b.sample(contextB, u0, u1);
    ASSERT_EQ(sa.direction, sb.direction) << "u " << u0 << ", " << u1;
    ASSERT_EQ(sa.pdf, sb.pdf) << "u " << u0 << ", " << u1;
    ASSERT_EQ(a.pdf(contextA, sa.direction), b.pdf(contextB, sa.direction)) << "u " << u0 << ", " << u1;
    ASSERT_EQ(b.pdf(contextB, sb.direction), sb.pdf) << "u " << u0 << ", " << u1;
  }
}

}  // namespace acdf::envmaptest

#include "render_test_util.h"

#include <cmath>

#ifdef ACDF_THREAD_SANITIZER
#include <tbb/global_control.h>
#endif

namespace acdf::rendertest {

#ifdef ACDF_THREAD_SANITIZER
// Under ThreadSanitizer the tables are built on the calling thread, since libtbb is not
// instrumented (see forEachTile in renderer.cpp); the renderer's tiles still run on several
// threads, as many as the task arena allows.
const tbb::global_control serialTableBuilds(tbb::global_control::max_allowed_parallelism, 1);
#endif

Rendered renderScene(const nlohmann::json& scene, const SceneOverrides& overrides) {
  // One provider for the whole test program: scenes that share a material or a map share its
  // tables, as they would within one scene.
  static SceneAssets tables(TableCache::disabled());
  const Scene loaded =
      loadSceneText(scene.dump(), std::string(ACDF_SOURCE_DIR) + "/test-scene.json", overrides, tables);
  Rendered r{makeFilm(loaded), {}, loaded.environment->options().portals.size()};
  r.stats = render(loaded, r.film);
  return r;
}

ImageMean imageMean(const Film& film) {
  double sum[3] = {0, 0, 0}, variance[3] = {0, 0, 0};
  for (uint32_t y = 0; y < film.height(); ++y)
    for (uint32_t x = 0; x < film.width(); ++x) {
      const Rgb m = film.mean(x, y), se = film.standardError(x, y);
      const float means[3] = {m.r, m.g, m.b}, errors[3] = {se.r, se.g, se.b};
      for (int c = 0; c < 3; ++c) {
        sum[c] += means[c];
        variance[c] += double(errors[c]) * errors[c];
      }
    }
  const double n = static_cast<double>(film.width()) * film.height();
  const auto channels = [n](const double* v, bool root) {
    const auto f = [&](double x) { return static_cast<float>((root ? std::sqrt(x) : x) / n); };
    return Rgb{f(v[0]), f(v[1]), f(v[2])};
  };
  return {channels(sum, false), channels(variance, true)};
}

nlohmann::json furnaceScene(const nlohmann::json& material, const Rgb& radiance, uint32_t size, uint32_t spp) {
  // The sphere subtends asin(1/3) = 19.5° from the eye; a 20° field of view (14.1° to the
  // corners) keeps every pixel on it.
  return {
      {"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"fov", 20}, {"width", size}, {"height", size}}},
      {"render", {{"spp", spp}, {"seed", 7}}},
      {"environment", {{"type", "constant"}, {"radiance", {radiance.r, radiance.g, radiance.b}}}},
      {"materials", {{"m", material}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}}}},
  };
}

}  // namespace acdf::rendertest

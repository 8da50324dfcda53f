#include "acdf/integrator/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <vector>

#include <tbb/parallel_for.h>
#ifdef ACDF_THREAD_SANITIZER
#include <thread>

#include <tbb/task_arena.h>
#endif

#include "acdf/integrator/path_integrator.h"
#include "acdf/integrator/sampler.h"

namespace acdf {

namespace {

struct Tile {
  uint32_t x0, y0, x1, y1;  // in film pixels
};

// Runs renderTile(t) for every t < tiles, on TBB's workers. Under ThreadSanitizer the same calls
// run on plain std::threads that take tile indices from an atomic counter, as many as the current
// task arena allows: libtbb is not instrumented, so TSan cannot see its scheduler's
// synchronisation and reports its reuse of task memory as races, which would bury real ones.
template <class RenderTile>
void forEachTile(std::size_t tiles, const RenderTile& renderTile) {
#ifdef ACDF_THREAD_SANITIZER
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t t = next++; t < tiles; t = next++) renderTile(t);
  };
  std::vector<std::jthread> helpers;
  for (int i = 1; i < tbb::this_task_arena::max_concurrency(); ++i) helpers.emplace_back(work);
  work();
#else
  tbb::parallel_for(std::size_t{0}, tiles, renderTile);
#endif
}

std::vector<Tile> makeTiles(const Film& film, uint32_t size) {
  std::vector<Tile> tiles;
  for (uint32_t y = 0; y < film.height(); y += size)
    for (uint32_t x = 0; x < film.width(); x += size)
      tiles.push_back({x, y, std::min(x + size, film.width()), std::min(y + size, film.height())});
  return tiles;
}

}  // namespace

Film makeFilm(const Scene& scene) { return Film(scene.camera->crop().width(), scene.camera->crop().height()); }

RenderStats render(const Scene& scene, Film& film, const RenderOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  const PathIntegrator integrator(scene);
  const Camera& camera = *scene.camera;
  const std::unique_ptr<const Sampler> samplerPrototype =
      makeSampler(scene.settings.sampler, scene.settings.seed, camera.width());
  const CropWindow& crop = camera.crop();
  const std::vector<Tile> tiles = makeTiles(film, std::max(1u, options.tileSize));
  std::atomic<uint64_t> rays{0};
  std::atomic<std::size_t> tilesDone{0};
  std::mutex progressMutex;

  // Samples [first, last) of every pixel, tile by tile.
  auto renderPass = [&](uint32_t first, uint32_t last, double doneBefore, double passShare) {
    tilesDone = 0;
    forEachTile(tiles.size(), [&](std::size_t t) {
      const Tile& tile = tiles[t];
      const std::unique_ptr<Sampler> sampler = samplerPrototype->clone();
      uint64_t tileRays = 0;
      for (uint32_t y = tile.y0; y < tile.y1; ++y)
        for (uint32_t x = tile.x0; x < tile.x1; ++x) {
          const uint32_t fx = crop.x0 + x, fy = crop.y0 + y;
          for (uint32_t s = first; s < last; ++s) {
            sampler->startPixelSample(fx, fy, s);
            const auto [jx, jy] = sampler->getPixel2D();
            const Ray ray = camera.generateRay(fx + jx, fy + jy);
            film.add(x, y, integrator.radiance(ray, *sampler, tileRays));
          }
        }
      rays += tileRays;
      const std::size_t done = ++tilesDone;
      if (options.progress) {
        // Reported from whichever thread finished a tile, one at a time.
        std::lock_guard lock(progressMutex);
        options.progress(doneBefore + passShare * static_cast<double>(done) / tiles.size());
      }
    });
  };

  RenderStats stats;
  if (options.seconds) {
    const double budget = *options.seconds;
    do {
      const double fraction = std::min(1.0, elapsed() / budget);
      renderPass(stats.spp, stats.spp + 1, fraction, 0.0);
      ++stats.spp;
      if (options.progress) options.progress(std::min(1.0, elapsed() / budget));
    } while (elapsed() < budget);
  } else {
    stats.spp = scene.settings.spp;
    renderPass(0, stats.spp, 0.0, 1.0);
  }
  stats.paths = uint64_t{film.width()} * film.height() * stats.spp;
  stats.rays = rays;
  stats.seconds = elapsed();
  return stats;
}

}  // namespace acdf

// The renderer's throughput on the demo scene (scenes/demo.json at a small resolution, its
// tables from the table cache or built once in set-up): paths and rays per second of the full
// MIS path tracer, and bare ray casting of the same kind of rays through acdf::Geometry (Embree
// plus the double-precision hit reconstruction, no shading), for the ratio: how close the
// renderer runs to the intersection limit. Needs the demo materials (`make demo` generates them
// into build/demo); skips with a message without them.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <oneapi/tbb/task_arena.h>

#include "acdf/integrator/renderer.h"
#include "acdf/integrator/scene.h"
#include "acdf/sampling/frame.h"
#include "acdf/sampling/rng.h"

namespace acdf {
namespace {

constexpr uint32_t kWidth = 120, kHeight = 50;

struct DemoScene {
  std::unique_ptr<SceneAssets> tables;
  Scene scene;
  std::string problem;  // why the scene is unavailable, if it is
};

DemoScene& demoScene() {
  static DemoScene demo = [] {
    DemoScene d;
    const std::filesystem::path file = std::filesystem::path(ACDF_SOURCE_DIR) / "scenes/demo.json";
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json json = nlohmann::json::parse(text.str());
    json["camera"]["width"] = kWidth;
    json["camera"]["height"] = kHeight;
    d.tables = std::make_unique<SceneAssets>(TableCache::atDefaultLocation());
    try {
      d.scene = loadSceneText(json.dump(), file, {}, *d.tables);
    } catch (const FileError& e) {
      d.problem = std::string(e.what()) + " (run `make demo` first)";
    }
    return d;
  }();
  return demo;
}

// The full renderer, one sample per pixel per iteration.
void BM_RenderDemo(benchmark::State& state) {
  DemoScene& demo = demoScene();
  if (!demo.problem.empty()) {
    state.SkipWithError(demo.problem.c_str());
    return;
  }
  Scene& scene = demo.scene;
  scene.settings.spp = 1;
  uint64_t paths = 0, rays = 0;
  for (auto _ : state) {
    Film film = makeFilm(scene);
    const RenderStats stats = render(scene, film);
    paths += stats.paths;
    rays += stats.rays;
    scene.settings.seed += 1;
  }
  state.counters["paths_per_second"] = benchmark::Counter(static_cast<double>(paths), benchmark::Counter::kIsRate);
  state.counters["rays_per_second"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["rays_per_path"] = static_cast<double>(rays) / static_cast<double>(paths);
}
BENCHMARK(BM_RenderDemo)->Unit(benchmark::kMillisecond)->UseRealTime();

struct RecordedRays {
  std::vector<Ray> closest;  // camera and BSDF-sampled rays
  std::vector<Ray> shadow;   // next-event rays towards the environment
};

// The rays the path tracer casts for one sample per pixel: camera rays, one shadow ray towards a
// light sample and one BSDF-sampled continuation per surface vertex, up to the scene's depth
// (no Russian roulette), with the same materials, light and frames.
RecordedRays recordRays(const Scene& scene) {
  RecordedRays rays;
  Pcg32 rng(1);
  const Camera& camera = *scene.camera;
  const LightSampleContext lightContext{.allowIncompletePdf = allowsIncompleteLightPdf(scene.settings)};
  for (uint32_t y = 0; y < camera.height(); ++y)
    for (uint32_t x = 0; x < camera.width(); ++x) {
      Ray ray = camera.generateRay(x + rng.nextFloat(), y + rng.nextFloat());
      for (uint32_t depth = 0; depth < scene.settings.maxDepth; ++depth) {
        rays.closest.push_back(ray);
        const auto hit = scene.geometry->intersect(ray);
        if (!hit) break;
        const Frame frame(hit->normal, hit->tangentHint);
        const LightSample light = scene.environment->sample(lightContext, rng.nextFloat(), rng.nextFloat());
        if (light.pdf > 0) rays.shadow.push_back({Geometry::offsetOrigin(*hit, light.direction), light.direction});
        const BrdfSample s =
            scene.bsdfSamplers[hit->material]->sample(frame.toLocal(-ray.direction), rng.nextFloat(), rng.nextFloat());
        if (!(s.pdf > 0) || s.weight.isBlack()) break;
        const Vec3d direction = normalize(frame.toWorld(s.wi));
        ray = {Geometry::offsetOrigin(*hit, direction), direction};
      }
    }
  return rays;
}

// The same kind and number of rays, cast alone (one thread, as Embree's single-ray API).
void BM_BareRayCasting(benchmark::State& state) {
  const DemoScene& demo = demoScene();
  if (!demo.problem.empty()) {
    state.SkipWithError(demo.problem.c_str());
    return;
  }
  const RecordedRays rays = recordRays(demo.scene);
  const Geometry& geometry = *demo.scene.geometry;
  uint64_t cast = 0, hits = 0;
  for (auto _ : state) {
    for (const Ray& r : rays.closest) hits += geometry.intersect(r).has_value();
    for (const Ray& r : rays.shadow) hits += geometry.occluded(r, std::numeric_limits<double>::infinity());
    cast += rays.closest.size() + rays.shadow.size();
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_second"] = benchmark::Counter(static_cast<double>(cast), benchmark::Counter::kIsRate);
  state.counters["rays"] = static_cast<double>(rays.closest.size() + rays.shadow.size());
}
BENCHMARK(BM_BareRayCasting)->Unit(benchmark::kMillisecond)->UseRealTime();

// The renderer on one thread, for a like-for-like ratio with the single-threaded casting above.
void BM_RenderDemoOneThread(benchmark::State& state) {
  tbb::task_arena arena(1);
  arena.execute([&] { BM_RenderDemo(state); });
}
BENCHMARK(BM_RenderDemoOneThread)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace acdf

BENCHMARK_MAIN();

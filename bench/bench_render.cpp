// The renderer's throughput on the demo scene (scenes/demo.json at a small resolution, its
// tables from the table cache or built once in set-up): paths and rays per second of the full
// MIS path tracer, and bare ray casting of the same kind of rays through acdf::Geometry (Embree
// plus the double-precision hit reconstruction, no shading), for the ratio: how close the
// renderer runs to the intersection limit. And the direct-light techniques' cost per shading
// point on scenes/product.json, product sampling against MIS in one run: what decides whether
// the product's lower error per sample pays at equal time. Needs the demo materials (`make demo`
// generates them into build/demo); skips with a message without them.

#include <algorithm>
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

#include "acdf/integrator/product_direct_light.h"
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

// A scene of the source tree at kWidth × kHeight.
DemoScene loadScene(const char* name, const SceneOverrides& overrides) {
  DemoScene d;
  const std::filesystem::path file = std::filesystem::path(ACDF_SOURCE_DIR) / "scenes" / name;
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json json = nlohmann::json::parse(text.str());
  json["camera"]["width"] = kWidth;
  json["camera"]["height"] = kHeight;
  d.tables = std::make_unique<SceneAssets>(TableCache::atDefaultLocation());
  try {
    d.scene = loadSceneText(json.dump(), file, overrides, *d.tables);
  } catch (const FileError& e) {
    d.problem = std::string(e.what()) + " (run `make demo` first)";
  }
  return d;
}

DemoScene& demoScene() {
  static DemoScene demo = loadScene("demo.json", {});
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

// scenes/product.json with the strategies its measurements in docs/performance.md use.
DemoScene& productScene() {
  static DemoScene product = loadScene("product.json", {.sampler = SamplerKind::Independent,
                                                        .bsdfSampling = BrdfSampling::Adaptive,
                                                        .envSampling = EnvironmentSampling::Compensated});
  return product;
}

// Where camera rays first hit the scene: the shading points of the direct-light benchmarks.
struct ShadingPoint {
  const BrdfSampler* material;
  Frame frame;
  Vec3d wo;  // local
  Vec3d normal;
};

std::vector<ShadingPoint> shadingPoints(const Scene& scene) {
  std::vector<ShadingPoint> points;
  Pcg32 rng(1);
  const Camera& camera = *scene.camera;
  for (uint32_t y = 0; y < camera.height(); ++y)
    for (uint32_t x = 0; x < camera.width(); ++x) {
      const Ray ray = camera.generateRay(x + rng.nextFloat(), y + rng.nextFloat());
      if (const auto hit = scene.geometry->intersect(ray)) {
        const Frame frame(hit->normal, hit->tangentHint);
        points.push_back({scene.bsdfSamplers[hit->material].get(), frame, frame.toLocal(-ray.direction), hit->normal});
      }
    }
  return points;
}

// The shading a path vertex does for direct light, without its rays, over the first hits of
// scenes/product.json: state.range(0) = 0 is power MIS (a light sample with f and the BSDF's pdf,
// the BSDF sample with the light's radiance and pdf, which the continuation shares), M > 0 the
// product estimator with M candidates and the continuation's BSDF sample. The counter
// per_point is the time per shading point.
void BM_DirectLightPerShadingPoint(benchmark::State& state) {
  DemoScene& product = productScene();
  if (!product.problem.empty()) {
    state.SkipWithError(product.problem.c_str());
    return;
  }
  const Scene& scene = product.scene;
  const EnvironmentLight& env = *scene.environment;
  const std::vector<ShadingPoint> points = shadingPoints(scene);
  const auto candidates = static_cast<uint32_t>(state.range(0));
  ProductSamplingOptions options = scene.settings.product;
  options.candidates = std::max(candidates, 1u);
  LightSampleContext context{.allowIncompletePdf = allowsIncompleteLightPdf(scene.settings)};
  Pcg32 rng(2);
  double sum = 0;  // every result, kept alive
  uint64_t shaded = 0;
  for (auto _ : state) {
    for (const ShadingPoint& p : points) {
      context = env.atNormal(context, p.normal);
      const BrdfVertex material = p.material->vertex(p.wo);
      if (candidates > 0) {
        CandidateValues values(Pcg32(rng.nextUint()));
        const ProductDirectLight direct(env, context, material, p.frame, options);
        if (const auto light = direct.sample(values)) sum += light->estimate.luminance();
      } else {
        const LightSample light = env.sample(context, rng.nextFloat(), rng.nextFloat());
        const Vec3d wi = p.frame.toLocal(light.direction);
        if (light.pdf > 0 && wi.z > 0) sum += material.eval(wi).luminance() * material.pdf(wi);
      }
      const BrdfSample s = material.sample(rng.nextFloat(), rng.nextFloat());
      if (candidates == 0) sum += env.evalWithPdf(context, normalize(p.frame.toWorld(s.wi))).pdf;
      sum += s.pdf;
    }
    shaded += points.size();
  }
  benchmark::DoNotOptimize(sum);
  state.counters["per_point"] =
      benchmark::Counter(static_cast<double>(shaded), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_DirectLightPerShadingPoint)->ArgName("candidates")->Arg(0)->Arg(1)->Arg(8)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace acdf

BENCHMARK_MAIN();

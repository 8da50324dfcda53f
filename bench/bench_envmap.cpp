// bench_envmap: environment lights (acdf::envmap) with the uniform, alias, adaptive and hierarchical
// tables, on a procedural 4096×2048 sun and sky (the "noon" preset) and on the real maps of the
// shared test data (../shared/data/envmaps, each benchmarked only when present).
//
// Benchmarks (names "<what>/<method>/<map>"):
//   build/*   EnvironmentLight construction: the table of luminance × ΔΩ and its distribution
//             (wall ms/op, TBB on all cores); counters: process_cpu_ms (CPU time of all threads per
//             build), peak_build_bytes (rise of the resident high-water mark, see PeakMemory),
//             bytes, bytes_vs_uniform
//   h2h/<map> sample() and pdf() of the four lights interleaved in chunks (HeadToHead): median
//             ns/op of each and the ratios vs uniform under the same machine noise (counters).
//             sample() returns the direction, radiance and pdf; pdf() takes world directions
//             sampled beforehand from the uniform light.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/sun_sky.h"
#include "bench_util.h"

namespace {

using namespace acdf;
using namespace acdf::bench;

constexpr EnvironmentSampling kMethods[] = {EnvironmentSampling::Uniform, EnvironmentSampling::Alias,
                                            EnvironmentSampling::Adaptive, EnvironmentSampling::Hierarchical};

struct MapSet {
  std::shared_ptr<const EnvironmentMap> map;
  std::vector<float> u = variates(2 * kVariates, 7);
  std::map<EnvironmentSampling, std::unique_ptr<EnvironmentLight>> lights;
  std::vector<Vec3d> directions;  // sampled from the uniform light, for pdf()

  const EnvironmentLight& light(EnvironmentSampling method) {
    auto& l = lights[method];
    if (!l) l = std::make_unique<EnvironmentLight>(map, EnvironmentLightOptions{.strategy = method});
    return *l;
  }
  const std::vector<Vec3d>& pdfDirections() {
    if (directions.empty()) {
      const EnvironmentLight& uniform = light(EnvironmentSampling::Uniform);
      const std::vector<float> v = variates(2 * kVariates, 11);
      for (std::size_t i = 0; i < kVariates; ++i)
        directions.push_back(uniform.sample({}, v[2 * i], v[2 * i + 1]).direction);
    }
    return directions;
  }
};

std::map<std::string, MapSet>& maps() {
  static std::map<std::string, MapSet> sets;
  return sets;
}

void buildLight(benchmark::State& st, const std::string& name, EnvironmentSampling method) {
  MapSet& s = maps().at(name);
  const std::size_t uniformBytes = s.light(EnvironmentSampling::Uniform).tableBytes();
  std::optional<EnvironmentLight> light;
  PeakMemory peak;
  peak.start();
  double cpuSeconds = 0;
  for (auto _ : st) {
    if (light) {
      st.PauseTiming();
      light.reset();
      st.ResumeTiming();
    }
    const double cpu0 = processCpuSeconds();
    light.emplace(s.map, EnvironmentLightOptions{.strategy = method});
    benchmark::DoNotOptimize(&*light);
    benchmark::ClobberMemory();
    cpuSeconds += processCpuSeconds() - cpu0;
  }
  st.counters["peak_build_bytes"] = peak.stopBytes();
  st.counters["process_cpu_ms"] = 1e3 * cpuSeconds / static_cast<double>(st.iterations());
  st.counters["bytes"] = static_cast<double>(light->tableBytes());
  st.counters["bytes_vs_uniform"] = static_cast<double>(light->tableBytes()) / static_cast<double>(uniformBytes);
}

constexpr std::size_t kChunk = 8192;

void headToHead(benchmark::State& st, const std::string& name) {
  MapSet& s = maps().at(name);
  const float* u = s.u.data();
  const Vec3d* w = s.pdfDirections().data();
  HeadToHead h2h(kChunk);
  for (EnvironmentSampling method : kMethods) {
    const EnvironmentLight& light = s.light(method);
    h2h.add([u, &light](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        const std::size_t i = (offset + k) & kVariateMask;
        LightSample r = light.sample({}, u[2 * i], u[2 * i + 1]);
        benchmark::DoNotOptimize(r);
      }
    });
  }
  for (EnvironmentSampling method : kMethods) {
    const EnvironmentLight& light = s.light(method);
    h2h.add([w, &light](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        double p = light.pdf({}, w[(offset + k) & kVariateMask]);
        benchmark::DoNotOptimize(p);
      }
    });
  }
  std::size_t offset = 0;
  for (auto _ : st) {
    h2h.round(offset);
    offset = (offset + kChunk) & kVariateMask;
  }
  std::vector<std::string> names;
  for (EnvironmentSampling method : kMethods) names.emplace_back(toString(method));
  h2h.reportVsUniform(st, names);
}

void registerMap(const std::string& name, std::shared_ptr<const EnvironmentMap> map) {
  maps()[name].map = std::move(map);
  for (EnvironmentSampling method : kMethods)
    benchmark::RegisterBenchmark(("build/" + std::string(toString(method)) + "/" + name).c_str(), buildLight, name,
                                 method)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(0.3)
        ->Repetitions(3)
        ->DisplayAggregatesOnly(true);
  benchmark::RegisterBenchmark(("h2h/" + name).c_str(), headToHead, name)->Iterations(40);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  registerMap("sunsky4096x2048",
              std::make_shared<const EnvironmentMap>(4096, 2048, sunSkyImage(4096, 2048, sunSkyPreset("noon")).pixels));
  for (const char* file : {"sunset_1024x512.exr", "forest_1024x512.exr", "stage_1000x500.exr"}) {
    const std::filesystem::path path = std::filesystem::path(ACDF_SHARED_ENVMAPS) / file;
    if (std::filesystem::is_regular_file(path))
      registerMap(std::string(file).substr(0, std::string(file).find('.')),
                  std::make_shared<const EnvironmentMap>(EnvironmentMap::load(path.string())));
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

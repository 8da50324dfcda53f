// bench_bilinear: Bilinear2D (the RGL warp: a bilinear density on vertices, conditioned on the
// incident angles) on tables of the RGL shapes, beside a Cascade of the same resolution.
//
// Tables (names as in the benchmarks; ../shared/data/rgl/README.md has the real files' shapes):
//   luminance-iso    32 × 32 vertices, parameters φi (1 value) × θi (8)   an isotropic .bsdf
//   luminance-aniso  32 × 32 vertices, parameters φi (8) × θi (16)         an anisotropic one
//   vndf-iso         128 × 128 vertices, φi (1) × θi (8)                   the visible-NDF warp
// Values: per slice a lobe whose centre and width follow θi and φi on a 1e-3 floor, like the
// specular part of a measured material (the real tables need the .bsdf reader).
// The comparison ("uniform"): Cascade with every dimension DimensionMethod::Uniform over
// conditioning axes φi × θi (one cell per parameter value, nearest-cell lookup) and the
// (rows − 1) × (columns − 1) patches, each cell the mean of its patch's four vertices: the
// piecewise-constant table of the same grid, pbrt's and Mitsuba's non-interpolating baseline.
//
// Benchmarks:
//   build-bilinear/<table>  construction (ms/op); counters bytes, bytes_vs_uniform (the cascade's)
// and for three contenders:
//   uniform           the cascade, at parameter points anywhere in the range
//   bilinear_grid     Bilinear2D at parameter points on grid values (one slice)
//   bilinear_between  Bilinear2D at the same points as the cascade (2 or 4 slices blended)
//   sample-bilinear/<contender>/<table>, pdf-bilinear/<contender>/<table>  one query (ns/op; the
//                 CPU time column is the one to read on a loaded machine)
//   h2h-bilinear/<table>    sample and pdf of the three interleaved in chunks (HeadToHead): median
//                 ns/op of each and the ratios to uniform (counters only)
// Variates and parameter points come from pre-generated buffers; pdf() is evaluated at points
// sampled beforehand from the bilinear table at the same parameters.

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "acdf/sampling/bilinear_2d.h"
#include "acdf/sampling/cascade.h"
#include "bench_util.h"

namespace {

using namespace acdf;
using namespace acdf::bench;

constexpr float kPi = std::numbers::pi_v<float>;

// Entry i of a buffer of pairs (variates, parameter points, coordinates).
std::span<const float> pair(const std::vector<float>& v, std::size_t i) { return {&v[2 * i], 2}; }

struct Shape {
  const char* name;
  uint32_t vertices;  // per axis
  uint32_t phiValues, thetaValues;
};
constexpr Shape kShapes[] = {{"luminance-iso", 32, 1, 8}, {"luminance-aniso", 32, 8, 16}, {"vndf-iso", 128, 1, 8}};

std::vector<float> parameterList(uint32_t count, float hi) {
  std::vector<float> v(count);
  for (uint32_t i = 0; i < count; ++i) v[i] = count == 1 ? 0.0f : hi * static_cast<float>(i) / (count - 1);
  return v;
}

struct Tables {
  explicit Tables(const Shape& shape)
      : n(shape.vertices),
        phi(parameterList(shape.phiValues, 2 * kPi)),
        theta(parameterList(shape.thetaValues, 0.5f * kPi)),
        values(lobes()),
        bilinear(values, n, n, {phi, theta}),
        cascade(patchMeans(), cascadeAxes(), uniformOptions()),
        u(variates(2 * kVariates, 0x61a5)) {
    // Parameter points: uniform over the range, and the same snapped to the nearest grid values.
    const std::vector<float> r = variates(2 * kVariates, 0x7e7a);
    for (std::size_t i = 0; i < kVariates; ++i) {
      const float p[2] = {phi.size() == 1 ? 0.0f : 2 * kPi * r[2 * i], 0.5f * kPi * r[2 * i + 1]};
      between.insert(between.end(), p, p + 2);
      grid.push_back(nearest(phi, p[0]));
      grid.push_back(nearest(theta, p[1]));
    }
    for (std::size_t i = 0; i < kVariates; ++i) {
      const SampleND s = bilinear.sample(pair(between, i), pair(u, i));
      points.push_back(s.x[0]);
      points.push_back(s.x[1]);
    }
  }

  static float nearest(const std::vector<float>& v, float x) {
    float best = v[0];
    for (float y : v)
      if (std::abs(y - x) < std::abs(best - x)) best = y;
    return best;
  }

  std::vector<float> lobes() const {
    std::vector<float> v;
    v.reserve(phi.size() * theta.size() * n * n);
    for (float p : phi)
      for (float t : theta) {
        const double cy = 0.1 + 0.8 * t / (0.5 * kPi), cx = 0.5 + 0.3 * std::sin(p), width = 0.01 + 0.05 * t;
        for (uint32_t r = 0; r < n; ++r)
          for (uint32_t c = 0; c < n; ++c) {
            const double y = double(r) / (n - 1) - cy, x = double(c) / (n - 1) - cx;
            v.push_back(static_cast<float>(std::exp(-(x * x + y * y) / width) + 1e-3));
          }
      }
    return v;
  }

  std::vector<float> patchMeans() const {
    std::vector<float> cells;
    const std::size_t slices = phi.size() * theta.size();
    for (std::size_t s = 0; s < slices; ++s)
      for (uint32_t r = 0; r + 1 < n; ++r)
        for (uint32_t c = 0; c + 1 < n; ++c) {
          const float* v = &values[(s * n + r) * n + c];
          cells.push_back(0.25f * (v[0] + v[1] + v[n] + v[n + 1]));
        }
    return cells;
  }

  std::vector<GridAxis> cascadeAxes() const {
    return {GridAxis(static_cast<uint32_t>(phi.size()), 0.0f, 2 * kPi),
            GridAxis(static_cast<uint32_t>(theta.size()), 0.0f, 0.5f * kPi), GridAxis(n - 1), GridAxis(n - 1)};
  }

  static CascadeOptions uniformOptions() {
    CascadeOptions o;
    o.conditioningDims = 2;
    o.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
    return o;
  }

  uint32_t n;
  std::vector<float> phi, theta, values;
  Bilinear2D bilinear;
  Cascade cascade;
  std::vector<float> u, between, grid, points;
};

Tables& tables(const Shape& shape) {
  static std::map<std::string, std::unique_ptr<Tables>> cache;
  auto& slot = cache[shape.name];
  if (!slot) slot = std::make_unique<Tables>(shape);
  return *slot;
}

void build(benchmark::State& st, const Shape* shape) {
  Tables& t = tables(*shape);
  std::size_t bytes = 0;
  for (auto _ : st) {
    Bilinear2D d(t.values, t.n, t.n, {t.phi, t.theta});
    bytes = d.bytes();
    benchmark::DoNotOptimize(&d);
  }
  st.counters["bytes"] = static_cast<double>(bytes);
  st.counters["bytes_vs_uniform"] = static_cast<double>(bytes) / static_cast<double>(t.cascade.bytes());
}

enum class Contender { Uniform, BilinearGrid, BilinearBetween };
constexpr Contender kContenders[] = {Contender::Uniform, Contender::BilinearGrid, Contender::BilinearBetween};
constexpr const char* kContenderName[] = {"uniform", "bilinear_grid", "bilinear_between"};

// One sample() (Pdf false) or pdf() of a contender at buffer index i.
template <bool Pdf>
void query(const Tables& t, Contender c, std::size_t i) {
  if (c == Contender::Uniform) {  // conditioned on the parameter point itself (φi, θi)
    if constexpr (Pdf)
      benchmark::DoNotOptimize(t.cascade.pdf(pair(t.between, i), pair(t.points, i)));
    else
      benchmark::DoNotOptimize(t.cascade.sample(pair(t.between, i), pair(t.u, i)));
    return;
  }
  const std::vector<float>& params = c == Contender::BilinearGrid ? t.grid : t.between;
  if constexpr (Pdf)
    benchmark::DoNotOptimize(t.bilinear.pdf(pair(params, i), pair(t.points, i)));
  else
    benchmark::DoNotOptimize(t.bilinear.sample(pair(params, i), pair(t.u, i)));
}

template <bool Pdf>
void perQuery(benchmark::State& st, const Shape* shape, Contender c) {
  const Tables& t = tables(*shape);
  std::size_t i = 0;
  for (auto _ : st) {
    query<Pdf>(t, c, i);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
}

constexpr std::size_t kChunk = 8192;

template <bool Pdf>
void addContenders(HeadToHead& h2h, const Tables& t) {
  for (Contender c : kContenders)
    h2h.add([&t, c](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) query<Pdf>(t, c, (offset + k) & kVariateMask);
    });
}

void headToHead(benchmark::State& st, const Shape* shape) {
  const Tables& t = tables(*shape);
  HeadToHead h2h(kChunk);
  addContenders<false>(h2h, t);
  addContenders<true>(h2h, t);
  std::size_t offset = 0;
  for (auto _ : st) {
    h2h.round(offset);
    offset = (offset + kChunk) & kVariateMask;
  }
  h2h.reportVsUniform(st, {kContenderName, kContenderName + 3});
  st.counters["bytes_bilinear_vs_uniform"] =
      static_cast<double>(t.bilinear.bytes()) / static_cast<double>(t.cascade.bytes());
}

}  // namespace

int main(int argc, char** argv) {
  for (const Shape& shape : kShapes) {
    benchmark::RegisterBenchmark((std::string("build-bilinear/") + shape.name).c_str(), build, &shape)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(0.3);
    for (Contender c : kContenders) {
      const std::string name = std::string(kContenderName[static_cast<int>(c)]) + "/" + shape.name;
      benchmark::RegisterBenchmark(("sample-bilinear/" + name).c_str(), perQuery<false>, &shape, c)->MinTime(0.1);
      benchmark::RegisterBenchmark(("pdf-bilinear/" + name).c_str(), perQuery<true>, &shape, c)->MinTime(0.1);
    }
    // 6 contenders × 8192 ops per round; 100 rounds ≈ 0.8M ops of each kind.
    benchmark::RegisterBenchmark((std::string("h2h-bilinear/") + shape.name).c_str(), headToHead, &shape)
        ->Iterations(100)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

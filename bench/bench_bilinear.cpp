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
//   h2h-bilinear/<table>    sample and pdf of three contenders interleaved in chunks (HeadToHead):
//                 uniform           the cascade, at parameter points anywhere in the range
//                 bilinear_grid     Bilinear2D at parameter points on grid values (one slice)
//                 bilinear_between  Bilinear2D at the same points as the cascade (2 or 4 slices
//                                   blended)
//                 median ns/op of each and the ratios to uniform (counters only). Variates and
//                 parameter points come from pre-generated buffers; pdf() is evaluated at points
//                 sampled beforehand from the bilinear table at the same parameters.

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
      const SampleND s =
          bilinear.sample(std::span<const float>(&u[2 * i], 2), std::span<const float>(&between[2 * i], 2));
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

constexpr std::size_t kChunk = 8192;

void headToHead(benchmark::State& st, const Shape* shape) {
  Tables& t = tables(*shape);
  HeadToHead h2h(kChunk);
  const auto span2 = [](const std::vector<float>& v, std::size_t i) { return std::span<const float>(&v[2 * i], 2); };
  // The cascade's condition is the parameter point itself (φi, θi), as for Bilinear2D.
  h2h.add([&](std::size_t offset) {
    for (std::size_t k = 0; k < kChunk; ++k) {
      const std::size_t i = (offset + k) & kVariateMask;
      benchmark::DoNotOptimize(t.cascade.sample(span2(t.between, i), span2(t.u, i)));
    }
  });
  for (const std::vector<float>* params : {&t.grid, &t.between}) {
    h2h.add([&t, params, span2](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        const std::size_t i = (offset + k) & kVariateMask;
        benchmark::DoNotOptimize(t.bilinear.sample(span2(t.u, i), span2(*params, i)));
      }
    });
  }
  h2h.add([&](std::size_t offset) {
    for (std::size_t k = 0; k < kChunk; ++k) {
      const std::size_t i = (offset + k) & kVariateMask;
      benchmark::DoNotOptimize(t.cascade.pdf(span2(t.between, i), span2(t.points, i)));
    }
  });
  for (const std::vector<float>* params : {&t.grid, &t.between}) {
    h2h.add([&t, params, span2](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        const std::size_t i = (offset + k) & kVariateMask;
        benchmark::DoNotOptimize(t.bilinear.pdf(span2(t.points, i), span2(*params, i)));
      }
    });
  }
  std::size_t offset = 0;
  for (auto _ : st) {
    h2h.round(offset);
    offset = (offset + kChunk) & kVariateMask;
  }
  h2h.reportVsUniform(st, {"uniform", "bilinear_grid", "bilinear_between"});
  st.counters["bytes_bilinear_vs_uniform"] =
      static_cast<double>(t.bilinear.bytes()) / static_cast<double>(t.cascade.bytes());
}

}  // namespace

int main(int argc, char** argv) {
  for (const Shape& shape : kShapes) {
    benchmark::RegisterBenchmark((std::string("build-bilinear/") + shape.name).c_str(), build, &shape)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(0.3);
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

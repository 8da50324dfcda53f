// bench_sampling_2d: environment-map sampling on the sun-and-sky fixture (acdf::fixtures::sunAndSky,
// luminance × sinθ; rows θ ∈ [0, π), columns φ ∈ [0, 2π)) at 1024×512 and 4096×2048.
//
// Three samplers of the same grid:
//   uniform   Cascade with every dimension DimensionMethod::Uniform (the pbrt/Mitsuba baseline)
//   alias     AliasGrid (one Vose table over all cells)
//   adaptive  Cascade with default options (Douglas–Peucker, vertical error, the
//             default ε and weight bound ρ of SimplifyOptions; reported as counters)
//
// Benchmarks (names are "<what>/<method>/<W>x<H>"):
//   build2d/*     construction (wall ms/op, TBB on all cores); counters: process_cpu_ms (CPU time
//                 of all threads per build), bytes, bytes_vs_uniform,
//                 peak_build_bytes (rise of the process' resident high-water mark during the build
//                 loop, see PeakMemory), chi2 / max_weight_ratio of the cell probabilities vs exact
//   simplify2d/<simplifier>-<metric>/*  the adaptive build with each simplifier: what it costs
//                 (ms, bytes, peak memory) and what it gives (chi2 divergence, max weight ratio);
//                 plus greedy-vertical-budget8: greedy refinement stopped at 8 points per 1D CDF
//   sample2d/*    one sample from 2 variates taken from a pre-generated buffer of 64K u-pairs (ns/op)
//   pdf2d/*       one pdf at 64K points pre-sampled from the exact (uniform) distribution, the same
//                 points for every method (ns/op)
//   build2d-rough/{uniform,adaptive}/4096x2048  the cascade builds on heavy-tailed noise (see
//                 fixtureValues), the hard case for the simplifier
//   h2h2d/<W>x<H> sample and pdf of all three interleaved in chunks: median ns/op of each and the
//                 ratios vs uniform measured under the same machine noise (counters only)

#include <benchmark/benchmark.h>

#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/quality.h"
#include "bench_util.h"

namespace {

using namespace acdf;
using namespace acdf::bench;

CascadeOptions uniformOptions() {
  CascadeOptions o;
  o.methods = {DimensionMethod::Uniform, DimensionMethod::Uniform};
  return o;
}

CascadeOptions simplifierOptions(Simplifier s, ErrorMetric m, uint32_t maxPoints = 0) {
  CascadeOptions o;  // every other option at its default
  o.simplify.method = s;
  o.simplify.metric = m;
  o.simplify.maxPoints = maxPoints;
  return o;
}

// Greedy refinement with a point budget per 1D CDF (ε still applies; ρ may exceed the budget).
constexpr uint32_t kGreedyBudget = 8;

enum class Fixture { SunAndSky, Rough };

// SunAndSky: the fixture. Rough: a_row^8 · b_cell^8 with a, b i.i.d. uniform
// (acdf::fixtures::random) — heavy-tailed in both axes, so the weight bound ρ splits almost
// every row and every cell: the adaptive build's worst realistic case (little to simplify, the
// simplifier still scans everything).
std::vector<float> fixtureValues(Fixture fixture, uint32_t width, uint32_t height) {
  if (fixture == Fixture::SunAndSky) return fixtures::sunAndSky(width, height);
  const uint32_t dims[] = {height, width};
  const uint32_t rowDims[] = {height};
  std::vector<float> v = fixtures::random(dims, 0x5eed);
  const std::vector<float> row = fixtures::random(rowDims, 0x7a11);
  auto pow8 = [](float x) {
    float x2 = x * x, x4 = x2 * x2;
    return x4 * x4;
  };
  for (uint32_t i = 0; i < height; ++i)
    for (uint32_t j = 0; j < width; ++j) {
      float& c = v[std::size_t{i} * width + j];
      c = pow8(row[i]) * pow8(c);
    }
  return v;
}

struct Set2D {
  Set2D(Fixture fixture, uint32_t width, uint32_t height)
      : width(width),
        height(height),
        values(fixtureValues(fixture, width, height)),
        axes{GridAxis(height, 0.0f, std::numbers::pi_v<float>),
             GridAxis(width, 0.0f, 2.0f * std::numbers::pi_v<float>)},
        u(variates(2 * kVariates, 0x2d5eed)) {}

  std::string name() const { return std::to_string(width) + "x" + std::to_string(height); }

  const Cascade& uniform() {
    if (!uniform_) uniform_.emplace(values, axes, uniformOptions());
    return *uniform_;
  }
  const Cascade& adaptive() {
    if (!adaptive_) adaptive_.emplace(values, axes);
    return *adaptive_;
  }
  const AliasGrid& alias() {
    if (!alias_) alias_.emplace(values, axes);
    return *alias_;
  }

  // Points for pdf(), sampled from the uniform cascade (= the exact distribution) with variates
  // independent of `u`.
  const std::vector<float>& points() {
    if (points_.empty()) {
      std::vector<float> v = variates(2 * kVariates, 0x9d2f);
      points_.resize(2 * kVariates);
      for (std::size_t i = 0; i < kVariates; ++i) {
        SampleND s = uniform().sample(std::span<const float>(&v[2 * i], 2));
        points_[2 * i] = s.x[0];
        points_[2 * i + 1] = s.x[1];
      }
    }
    return points_;
  }

  // Exact cell probabilities: every cell has the same (θ, φ) area, so p = value / Σ values.
  const std::vector<double>& exact() {
    if (exact_.empty()) {
      double sum = 0;
      for (float v : values) sum += v;
      exact_.resize(values.size());
      for (std::size_t i = 0; i < values.size(); ++i) exact_[i] = values[i] / sum;
    }
    return exact_;
  }

  double uniformBytes() { return static_cast<double>(uniform().bytes()); }

  uint32_t width, height;
  std::vector<float> values;
  std::vector<GridAxis> axes;
  std::vector<float> u;  // 64K u-pairs for sample()

 private:
  std::optional<Cascade> uniform_, adaptive_;
  std::optional<AliasGrid> alias_;
  std::vector<float> points_;
  std::vector<double> exact_;
};

Set2D& set2D(uint32_t width, uint32_t height, Fixture fixture = Fixture::SunAndSky) {
  static std::map<std::tuple<Fixture, uint32_t, uint32_t>, std::unique_ptr<Set2D>> cache;
  auto& slot = cache[{fixture, width, height}];
  if (!slot) slot = std::make_unique<Set2D>(fixture, width, height);
  return *slot;
}

enum class Method { Uniform, Alias, Adaptive };
constexpr const char* kMethodName[] = {"uniform", "alias", "adaptive"};

void qualityCounters(benchmark::State& st, Set2D& s, const std::vector<double>& q) {
  CompressionQuality quality = compareCellProbabilities(s.exact(), q);
  st.counters["chi2"] = quality.chi2Divergence;
  st.counters["max_weight_ratio"] = quality.maxWeightRatio;
  st.counters["unreachable_mass"] = quality.unreachableMass;
}

void sizeCounters(benchmark::State& st, Set2D& s, std::size_t bytes) {
  st.counters["bytes"] = static_cast<double>(bytes);
  st.counters["bytes_vs_uniform"] = static_cast<double>(bytes) / s.uniformBytes();
  st.counters["input_bytes"] = static_cast<double>(s.values.size() * sizeof(float));
}

void cascadeCounters(benchmark::State& st, Set2D& s, const Cascade& c) {
  sizeCounters(st, s, c.bytes());
  const SimplifyOptions& o = c.options().simplify;
  st.counters["epsilon"] = o.epsilon;
  st.counters["weight_bound"] = o.weightBound;
  st.counters["max_points"] = o.maxPoints;
  std::vector<double> intervals = c.averageIntervals();
  st.counters["avg_intervals_theta"] = intervals[0];
  st.counters["avg_intervals_phi"] = intervals[1];
  qualityCounters(st, s, c.cellProbabilities(0));
}

// Builds `Distribution(values, axes, args...)` once per iteration; the previous instance is
// destroyed with the timer paused, and the last one is kept for the counters.
template <class Distribution, class... Args>
std::optional<Distribution> timedBuilds(benchmark::State& st, Set2D& s, Args&&... args) {
  std::optional<Distribution> d;
  PeakMemory peak;
  peak.start();
  double cpuSeconds = 0;
  for (auto _ : st) {
    if (d) {
      st.PauseTiming();
      d.reset();
      st.ResumeTiming();
    }
    const double cpu0 = processCpuSeconds();
    d.emplace(s.values, s.axes, args...);
    benchmark::DoNotOptimize(&*d);
    benchmark::ClobberMemory();
    cpuSeconds += processCpuSeconds() - cpu0;
  }
  st.counters["peak_build_bytes"] = peak.stopBytes();
  // CPU time of all threads per build (ms): the work, independent of how busy the machine is.
  st.counters["process_cpu_ms"] = 1e3 * cpuSeconds / static_cast<double>(st.iterations());
  return d;
}

void buildCascadeOn(benchmark::State& st, uint32_t w, uint32_t h, CascadeOptions options, Fixture fixture) {
  Set2D& s = set2D(w, h, fixture);
  s.uniform();  // the reference for bytes_vs_uniform, built before the peak-memory probe
  s.exact();
  std::optional<Cascade> c = timedBuilds<Cascade>(st, s, options);
  cascadeCounters(st, s, *c);
}

void buildCascade(benchmark::State& st, uint32_t w, uint32_t h, CascadeOptions options) {
  buildCascadeOn(st, w, h, std::move(options), Fixture::SunAndSky);
}

void buildAlias(benchmark::State& st, uint32_t w, uint32_t h) {
  Set2D& s = set2D(w, h);
  s.uniform();
  s.exact();
  std::optional<AliasGrid> a = timedBuilds<AliasGrid>(st, s);
  sizeCounters(st, s, a->bytes());
  qualityCounters(st, s, a->cellProbabilities());
}

template <Method M>
auto& pick(Set2D& s) {
  if constexpr (M == Method::Uniform)
    return s.uniform();
  else if constexpr (M == Method::Alias)
    return s.alias();
  else
    return s.adaptive();
}

template <Method M>
void sample2d(benchmark::State& st, uint32_t w, uint32_t h) {
  Set2D& s = set2D(w, h);
  const auto& d = pick<M>(s);
  const float* u = s.u.data();
  std::size_t i = 0;
  for (auto _ : st) {
    SampleND r = d.sample(std::span<const float>(u + 2 * i, 2));
    benchmark::DoNotOptimize(r);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
  sizeCounters(st, s, d.bytes());
}

template <Method M>
void pdf2d(benchmark::State& st, uint32_t w, uint32_t h) {
  Set2D& s = set2D(w, h);
  const auto& d = pick<M>(s);
  const float* x = s.points().data();
  std::size_t i = 0;
  for (auto _ : st) {
    float p = d.pdf(std::span<const float>(x + 2 * i, 2));
    benchmark::DoNotOptimize(p);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
  sizeCounters(st, s, d.bytes());
}

constexpr std::size_t kChunk2D = 8192;

void headToHead2d(benchmark::State& st, uint32_t w, uint32_t h) {
  Set2D& s = set2D(w, h);
  const Cascade& uniform = s.uniform();
  const AliasGrid& alias = s.alias();
  const Cascade& adaptive = s.adaptive();
  const float* u = s.u.data();
  const float* x = s.points().data();
  HeadToHead h2h(kChunk2D);
  auto addSample = [&](const auto& d) {
    h2h.add([u, &d](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk2D; ++k) {
        std::size_t i = (offset + k) & kVariateMask;
        SampleND r = d.sample(std::span<const float>(u + 2 * i, 2));
        benchmark::DoNotOptimize(r);
      }
    });
  };
  auto addPdf = [&](const auto& d) {
    h2h.add([x, &d](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk2D; ++k) {
        std::size_t i = (offset + k) & kVariateMask;
        float p = d.pdf(std::span<const float>(x + 2 * i, 2));
        benchmark::DoNotOptimize(p);
      }
    });
  };
  addSample(uniform);
  addSample(alias);
  addSample(adaptive);
  addPdf(uniform);
  addPdf(alias);
  addPdf(adaptive);
  std::size_t offset = 0;
  for (auto _ : st) {
    h2h.round(offset);
    offset = (offset + kChunk2D) & kVariateMask;
  }
  h2h.reportSamplersVsUniform(st);
  double ub = static_cast<double>(uniform.bytes());
  st.counters["bytes_alias_vs_uniform"] = static_cast<double>(alias.bytes()) / ub;
  st.counters["bytes_adaptive_vs_uniform"] = static_cast<double>(adaptive.bytes()) / ub;
}

template <class F>
benchmark::internal::Benchmark* reg(const std::string& name, F f, uint32_t w, uint32_t h) {
  return benchmark::RegisterBenchmark(name.c_str(), f, w, h);
}

void registerSize(uint32_t w, uint32_t h) {
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  auto buildOpts = [](benchmark::internal::Benchmark* b) {
    b->Unit(benchmark::kMillisecond)->MinTime(0.3)->Repetitions(3)->DisplayAggregatesOnly(true);
  };
  auto queryOpts = [](benchmark::internal::Benchmark* b) {
    b->MinTime(0.1)->Repetitions(3)->DisplayAggregatesOnly(true);
  };

  buildOpts(benchmark::RegisterBenchmark(("build2d/uniform/" + size).c_str(), buildCascade, w, h, uniformOptions()));
  buildOpts(reg("build2d/alias/" + size, buildAlias, w, h));
  buildOpts(benchmark::RegisterBenchmark(("build2d/adaptive/" + size).c_str(), buildCascade, w, h, CascadeOptions{}));

  for (Simplifier sim : {Simplifier::DouglasPeucker, Simplifier::GreedyRefinement}) {
    for (ErrorMetric metric : {ErrorMetric::Vertical, ErrorMetric::Perpendicular}) {
      std::string name = std::string("simplify2d/") + (sim == Simplifier::DouglasPeucker ? "dp" : "greedy") + "-" +
                         (metric == ErrorMetric::Vertical ? "vertical" : "perpendicular") + "/" + size;
      buildOpts(benchmark::RegisterBenchmark(name.c_str(), buildCascade, w, h, simplifierOptions(sim, metric)));
    }
  }
  buildOpts(benchmark::RegisterBenchmark(
      ("simplify2d/greedy-vertical-budget" + std::to_string(kGreedyBudget) + "/" + size).c_str(), buildCascade, w, h,
      simplifierOptions(Simplifier::GreedyRefinement, ErrorMetric::Vertical, kGreedyBudget)));

  queryOpts(reg("sample2d/uniform/" + size, sample2d<Method::Uniform>, w, h));
  queryOpts(reg("sample2d/alias/" + size, sample2d<Method::Alias>, w, h));
  queryOpts(reg("sample2d/adaptive/" + size, sample2d<Method::Adaptive>, w, h));
  queryOpts(reg("pdf2d/uniform/" + size, pdf2d<Method::Uniform>, w, h));
  queryOpts(reg("pdf2d/alias/" + size, pdf2d<Method::Alias>, w, h));
  queryOpts(reg("pdf2d/adaptive/" + size, pdf2d<Method::Adaptive>, w, h));

  // 6 contenders × 8192 ops per round; 100 rounds ≈ 0.8M ops of each kind.
  reg("h2h2d/" + size, headToHead2d, w, h)->Iterations(100)->Unit(benchmark::kMillisecond);
}

}  // namespace

// The sun-and-sky map compresses extremely well; the rough fixture is the opposite (the weight
// bound keeps nearly every vertex), so it bounds the adaptive build time from the other side.
void registerRough(uint32_t w, uint32_t h) {
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  for (auto [name, options] : {std::pair{"uniform", uniformOptions()}, std::pair{"adaptive", CascadeOptions{}}}) {
    benchmark::RegisterBenchmark(("build2d-rough/" + std::string(name) + "/" + size).c_str(), buildCascadeOn, w, h,
                                 options, Fixture::Rough)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(0.3)
        ->Repetitions(3)
        ->DisplayAggregatesOnly(true);
  }
}

int main(int argc, char** argv) {
  registerSize(1024, 512);
  registerSize(4096, 2048);
  registerRough(4096, 2048);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

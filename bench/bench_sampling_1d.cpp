// bench_sampling_1d: the three 1D samplers (uniform table = PiecewiseConstant1D, Vose alias table,
// adaptive CDF) on one peaked-but-smooth function tabulated at 256 ... 1M cells.
//
// Benchmarks (names are "<what>/<method>/<cells>"):
//   build1d/*     construction from the tabulated function (µs/op); counters: bytes, bytes_vs_uniform,
//                 and for the adaptive CDF its kept points and chi2 divergence vs the exact cells
//   sample1d/*    one sample(u) with u from a pre-generated buffer of 64K variates (ns/op)
//   pdf1d/*       one pdf(x) on 64K points pre-sampled from the exact (uniform-table) distribution
//   h2h1d/<cells> sample and pdf of all three interleaved in chunks, median ns/op of each and the
//                 ratios vs uniform measured under the same noise (counters only)

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/quality.h"
#include "bench_util.h"

namespace {

using namespace acdf;
using namespace acdf::bench;

// A smooth base (a slow cosine swell) plus three narrow Gaussians of different widths and
// heights, evaluated at the cell centres of n cells over [0, 1). Deterministic. At 256 cells the
// narrowest peak (σ = 0.0015) is under a cell wide; at 1M cells every feature is resolved.
std::vector<float> peakedFunction(uint32_t n) {
  struct Peak {
    double centre, sigma, height;
  };
  constexpr Peak peaks[] = {{0.13, 0.004, 40.0}, {0.42, 0.0015, 120.0}, {0.77, 0.02, 8.0}};
  std::vector<float> f(n);
  for (uint32_t i = 0; i < n; ++i) {
    double x = (i + 0.5) / n;
    double v = 0.05 + 0.3 * 0.5 * (1.0 + std::cos(2.0 * std::numbers::pi * x));
    for (const Peak& p : peaks) {
      double z = (x - p.centre) / p.sigma;
      v += p.height * std::exp(-0.5 * z * z);
    }
    f[i] = static_cast<float>(v);
  }
  return f;
}

struct Set1D {
  explicit Set1D(uint32_t n)
      : f(peakedFunction(n)), uniform(f), alias(f), adaptive(f), u(variates(kVariates, 0x1d5eed)) {
    Pcg32 rng(0x9d1f);
    x.resize(kVariates);
    for (float& xi : x) xi = uniform.sample(rng.nextFloat()).x;

    // Exact cell probabilities vs the adaptive CDF's (mass of a kept interval spread evenly).
    double sum = 0;
    for (float v : f) sum += v;
    std::vector<double> p(n), q(n);
    for (uint32_t i = 0; i < n; ++i) p[i] = f[i] / sum;
    for (std::size_t j = 0; j + 1 < adaptive.points(); ++j) {
      uint32_t a = adaptive.vertex(j), b = adaptive.vertex(j + 1);
      double mass = static_cast<double>(adaptive.cdfAt(j + 1)) - adaptive.cdfAt(j);
      for (uint32_t c = a; c < b; ++c) q[c] = mass / (b - a);
    }
    adaptiveQuality = compareCellProbabilities(p, q);
  }

  std::vector<float> f;
  PiecewiseConstant1D uniform;
  AliasTable1D alias;
  AdaptiveCdf1D adaptive;
  std::vector<float> u;  // variates for sample()
  std::vector<float> x;  // points for pdf(), sampled from the exact distribution
  CompressionQuality adaptiveQuality;
};

const Set1D& set1D(uint32_t n) {
  static std::map<uint32_t, std::unique_ptr<Set1D>> cache;
  auto& slot = cache[n];
  if (!slot) slot = std::make_unique<Set1D>(n);
  return *slot;
}

enum class Method { Uniform, Alias, Adaptive };
constexpr const char* kMethodName[] = {"uniform", "alias", "adaptive"};

template <Method M>
const auto& pick(const Set1D& s) {
  if constexpr (M == Method::Uniform)
    return s.uniform;
  else if constexpr (M == Method::Alias)
    return s.alias;
  else
    return s.adaptive;
}

template <Method M>
void setCommonCounters(benchmark::State& st, const Set1D& s) {
  double bytes = static_cast<double>(pick<M>(s).bytes());
  st.counters["bytes"] = bytes;
  st.counters["bytes_vs_uniform"] = bytes / static_cast<double>(s.uniform.bytes());
  if constexpr (M == Method::Adaptive) {
    st.counters["points"] = static_cast<double>(s.adaptive.points());
    st.counters["chi2"] = s.adaptiveQuality.chi2Divergence;
    st.counters["max_weight_ratio"] = s.adaptiveQuality.maxWeightRatio;
    st.counters["epsilon"] = SimplifyOptions{}.epsilon;
    st.counters["weight_bound"] = SimplifyOptions{}.weightBound;
  }
}

template <Method M>
void build1d(benchmark::State& st, uint32_t n) {
  const Set1D& s = set1D(n);
  std::span<const float> f(s.f);
  using D = std::remove_cvref_t<decltype(pick<M>(s))>;
  for (auto _ : st) {
    D d(f);
    benchmark::DoNotOptimize(&d);
    benchmark::ClobberMemory();
  }
  setCommonCounters<M>(st, s);
}

template <Method M>
void sample1d(benchmark::State& st, uint32_t n) {
  const Set1D& s = set1D(n);
  const auto& d = pick<M>(s);
  const float* u = s.u.data();
  std::size_t i = 0;
  for (auto _ : st) {
    Sample1D r = d.sample(u[i]);
    benchmark::DoNotOptimize(r);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
  setCommonCounters<M>(st, s);
}

template <Method M>
void pdf1d(benchmark::State& st, uint32_t n) {
  const Set1D& s = set1D(n);
  const auto& d = pick<M>(s);
  const float* x = s.x.data();
  std::size_t i = 0;
  for (auto _ : st) {
    float p = d.pdf(x[i]);
    benchmark::DoNotOptimize(p);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
  setCommonCounters<M>(st, s);
}

void headToHead1d(benchmark::State& st, uint32_t n) {
  const Set1D& s = set1D(n);
  constexpr std::size_t kChunk = 4096;
  HeadToHead h2h(kChunk);
  auto addSample = [&](const auto& d) {
    h2h.add([&s, &d](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        Sample1D r = d.sample(s.u[(offset + k) & kVariateMask]);
        benchmark::DoNotOptimize(r);
      }
    });
  };
  auto addPdf = [&](const auto& d) {
    h2h.add([&s, &d](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        float p = d.pdf(s.x[(offset + k) & kVariateMask]);
        benchmark::DoNotOptimize(p);
      }
    });
  };
  addSample(s.uniform);
  addSample(s.alias);
  addSample(s.adaptive);
  addPdf(s.uniform);
  addPdf(s.alias);
  addPdf(s.adaptive);
  std::size_t offset = 0;
  for (auto _ : st) {
    h2h.round(offset);
    offset = (offset + kChunk) & kVariateMask;
  }
  h2h.reportSamplersVsUniform(st);
  st.counters["bytes_alias_vs_uniform"] = static_cast<double>(s.alias.bytes()) / static_cast<double>(s.uniform.bytes());
  st.counters["bytes_adaptive_vs_uniform"] =
      static_cast<double>(s.adaptive.bytes()) / static_cast<double>(s.uniform.bytes());
}

template <Method M>
void registerMethod(uint32_t n) {
  std::string tail = std::string("/") + kMethodName[static_cast<int>(M)] + "/" + std::to_string(n);
  benchmark::RegisterBenchmark(("build1d" + tail).c_str(), build1d<M>, n)
      ->Unit(benchmark::kMicrosecond)
      ->MinTime(0.1)
      ->Repetitions(3)
      ->DisplayAggregatesOnly(true);
  benchmark::RegisterBenchmark(("sample1d" + tail).c_str(), sample1d<M>, n)
      ->MinTime(0.1)
      ->Repetitions(3)
      ->DisplayAggregatesOnly(true);
  benchmark::RegisterBenchmark(("pdf1d" + tail).c_str(), pdf1d<M>, n)
      ->MinTime(0.1)
      ->Repetitions(3)
      ->DisplayAggregatesOnly(true);
}

}  // namespace

int main(int argc, char** argv) {
  for (uint32_t n : {256u, 4096u, 65536u, 1u << 20}) {
    registerMethod<Method::Uniform>(n);
    registerMethod<Method::Alias>(n);
    registerMethod<Method::Adaptive>(n);
    // 6 contenders × 4096 ops per round; 150 rounds ≈ 3.7M ops of each kind.
    benchmark::RegisterBenchmark(("h2h1d/" + std::to_string(n)).c_str(), headToHead1d, n)
        ->Iterations(150)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

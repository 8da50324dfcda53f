// bench_brdf: importance sampling of a measured BRDF (the paper's nickel, tabulated in the MERL
// layout from its bundled neural fit, data/merl-nbrdf/) with each sampler of acdf::brdf:
//   cosine        cosine-weighted hemisphere (no table)
//   uniform-4d    TabulatedBrdfSampler, uniform CDFs over (θo, φo | θh, φh)   (the paper's baseline)
//   adaptive-4d   the same, simplified adaptive CDFs                         (the paper's method)
//   uniform-iso   isotropic reduction (θo | θh, |Δφ|), uniform CDFs
//   adaptive-iso  isotropic reduction, adaptive CDFs
// All with TabulatedBrdfOptions' defaults apart from layout and method, nearest-cell evaluation.
//
// Benchmarks (names "<what>/<sampler>/nickel"):
//   brdf-build/*   construction: wall ms/op; counters tabulation_ms and build_ms (the sampler's
//                  own timers: evaluating the BRDF into the grid, then building the CDFs),
//                  process_cpu_ms (CPU time of all threads per construction), peak_build_bytes
//                  (PeakMemory around the builds), bytes and bytes_vs_uniform (same layout)
//   brdf-sample/*  one sample(ωo, u) (direction, pdf and BRDF weight, what a renderer calls), ωo
//                  cycling over 4096 pre-drawn directions with θo < 85°, u from a pre-generated
//                  buffer (ns/op)
//   brdf-pdf/*     one pdf(ωo, ωi) at 64K pairs drawn beforehand from uniform-4d, the same pairs
//                  for every sampler (ns/op)
//   brdf-eval/merl/nickel  one MerlBrdf::eval(ωo, ωi) (nearest cell) at the same pairs (ns/op)
//   brdf-h2h/nickel  sample and pdf of every sampler interleaved in chunks (HeadToHead): median
//                  ns/op of each and the ratios to uniform-4d, and iso ones to uniform-iso, under
//                  the same machine noise (counters only)

#include <benchmark/benchmark.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/nbrdf.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "bench_util.h"

#ifndef ACDF_NBRDF_WEIGHTS
#error "ACDF_NBRDF_WEIGHTS (the bundled data/merl-nbrdf/merl_nbrdf_weights.json) must be defined"
#endif

namespace {

using namespace acdf;
using namespace acdf::bench;
using Layout = TabulatedBrdfOptions::Layout;

constexpr std::size_t kDirections = 4096;  // a power of two: cycled with a mask
constexpr double kMaxThetaOut = 85.0 * std::numbers::pi / 180.0;

const std::array<const char*, 5> kSamplers = {"cosine", "uniform-4d", "adaptive-4d", "uniform-iso", "adaptive-iso"};

TabulatedBrdfOptions tableOptions(const std::string& name) {
  TabulatedBrdfOptions o;
  o.method = name.starts_with("adaptive") ? DimensionMethod::Adaptive : DimensionMethod::Uniform;
  o.layout = name.ends_with("iso") ? Layout::Isotropic : Layout::Full4D;
  return o;
}

// Nearest-cell evaluation, MerlBrdf's default.
const std::shared_ptr<const MerlBrdf>& nickel() {
  static const std::shared_ptr<const MerlBrdf> brdf = [] {
    const std::vector<double> table = NeuralBrdf::load(ACDF_NBRDF_WEIGHTS, "nickel").merlTable();
    const std::span<const double> all(table);
    return std::make_shared<const MerlBrdf>(all.subspan(0, MerlBrdf::kCells),
                                            all.subspan(MerlBrdf::kCells, MerlBrdf::kCells),
                                            all.subspan(2 * MerlBrdf::kCells, MerlBrdf::kCells));
  }();
  return brdf;
}

std::unique_ptr<BrdfSampler> makeSampler(const std::string& name) {
  if (name == "cosine") return std::make_unique<CosineBrdfSampler>(nickel());
  return std::make_unique<TabulatedBrdfSampler>(nickel(), tableOptions(name));
}

// Samplers are built once and shared by the query benchmarks.
const BrdfSampler& sampler(const std::string& name) {
  static std::map<std::string, std::unique_ptr<BrdfSampler>> samplers;
  auto& slot = samplers[name];
  if (!slot) slot = makeSampler(name);
  return *slot;
}

// Outgoing directions: uniform in solid angle over θo < 85° (where the estimators of brdf-stats
// look), from a fixed seed.
const std::vector<Vec3d>& outgoing() {
  static const std::vector<Vec3d> dirs = [] {
    const std::vector<float> u = variates(2 * kDirections, 11);
    const double cosMax = std::cos(kMaxThetaOut);
    std::vector<Vec3d> d(kDirections);
    for (std::size_t i = 0; i < kDirections; ++i) {
      const double cosTheta = 1.0 - u[2 * i] * (1.0 - cosMax);
      d[i] = sphericalDirection(std::acos(cosTheta), 2.0 * std::numbers::pi * u[2 * i + 1]);
    }
    return d;
  }();
  return dirs;
}

const std::vector<float>& sampleVariates() {
  static const std::vector<float> u = variates(2 * kVariates, 7);
  return u;
}

// kVariates (ωo, ωi) pairs drawn from uniform-4d: where a renderer's pdf queries land.
struct Pair {
  Vec3d wo, wi;
};
const std::vector<Pair>& pdfPairs() {
  static const std::vector<Pair> pairs = [] {
    const BrdfSampler& s = sampler("uniform-4d");
    const std::vector<float> u = variates(2 * kVariates, 13);
    std::vector<Pair> p(kVariates);
    for (std::size_t i = 0; i < kVariates; ++i) {
      const Vec3d& wo = outgoing()[i % kDirections];
      p[i] = {wo, s.sample(wo, u[2 * i], u[2 * i + 1]).wi};
    }
    return p;
  }();
  return pairs;
}

// The uniform table of the same layout, for bytes_vs_uniform.
std::size_t uniformBytes(const std::string& name) {
  return sampler(name.ends_with("iso") ? "uniform-iso" : "uniform-4d").bytes();
}

void buildTable(benchmark::State& st, const std::string& name) {
  const std::shared_ptr<const MerlBrdf>& brdf = nickel();
  const std::size_t reference = uniformBytes(name);  // built before the peak-memory probe
  std::optional<TabulatedBrdfSampler> s;
  double cpuSeconds = 0, tabulationMs = 0, buildMs = 0;
  PeakMemory peak;
  peak.start();
  for (auto _ : st) {
    if (s) {
      st.PauseTiming();
      s.reset();
      st.ResumeTiming();
    }
    const double cpu0 = processCpuSeconds();
    s.emplace(brdf, tableOptions(name));
    benchmark::DoNotOptimize(&*s);
    cpuSeconds += processCpuSeconds() - cpu0;
    tabulationMs += s->tabulationMs();
    buildMs += s->buildMs();
  }
  const auto n = static_cast<double>(st.iterations());
  st.counters["peak_build_bytes"] = peak.stopBytes();
  st.counters["process_cpu_ms"] = 1e3 * cpuSeconds / n;
  st.counters["tabulation_ms"] = tabulationMs / n;
  st.counters["build_ms"] = buildMs / n;
  st.counters["bytes"] = static_cast<double>(s->bytes());
  st.counters["bytes_vs_uniform"] = static_cast<double>(s->bytes()) / static_cast<double>(reference);
}

void sampleOne(benchmark::State& st, const std::string& name) {
  const BrdfSampler& s = sampler(name);
  const std::vector<Vec3d>& wo = outgoing();
  const float* u = sampleVariates().data();
  std::size_t i = 0;
  for (auto _ : st) {
    BrdfSample r = s.sample(wo[i & (kDirections - 1)], u[2 * i], u[2 * i + 1]);
    benchmark::DoNotOptimize(r);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
  st.counters["bytes"] = static_cast<double>(s.bytes());
}

void pdfOne(benchmark::State& st, const std::string& name) {
  const BrdfSampler& s = sampler(name);
  const std::vector<Pair>& pairs = pdfPairs();
  std::size_t i = 0;
  for (auto _ : st) {
    double p = s.pdf(pairs[i].wo, pairs[i].wi);
    benchmark::DoNotOptimize(p);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
}

void evalOne(benchmark::State& st) {
  const MerlBrdf& brdf = *nickel();
  const std::vector<Pair>& pairs = pdfPairs();
  std::size_t i = 0;
  for (auto _ : st) {
    Rgb f = brdf.eval(pairs[i].wo, pairs[i].wi);
    benchmark::DoNotOptimize(f);
    i = (i + 1) & kVariateMask;
  }
  st.SetItemsProcessed(st.iterations());
}

constexpr std::size_t kChunk = 4096;

void headToHead(benchmark::State& st) {
  const std::vector<Vec3d>& wo = outgoing();
  const float* u = sampleVariates().data();
  const std::vector<Pair>& pairs = pdfPairs();
  HeadToHead h2h(kChunk);
  for (const char* name : kSamplers) {
    const BrdfSampler& s = sampler(name);
    h2h.add([&s, &wo, u](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        const std::size_t i = (offset + k) & kVariateMask;
        BrdfSample r = s.sample(wo[i & (kDirections - 1)], u[2 * i], u[2 * i + 1]);
        benchmark::DoNotOptimize(r);
      }
    });
  }
  for (const char* name : kSamplers) {
    const BrdfSampler& s = sampler(name);
    h2h.add([&s, &pairs](std::size_t offset) {
      for (std::size_t k = 0; k < kChunk; ++k) {
        const Pair& p = pairs[(offset + k) & kVariateMask];
        double d = s.pdf(p.wo, p.wi);
        benchmark::DoNotOptimize(d);
      }
    });
  }
  std::size_t offset = 0;
  for (auto _ : st) {
    h2h.round(offset);
    offset = (offset + kChunk) & kVariateMask;
  }
  // Contenders: sample of kSamplers[0..4], then pdf of the same; ratios to the uniform table of
  // the same layout (cosine's to uniform-4d).
  const std::array<std::size_t, 5> reference = {1, 1, 1, 3, 3};
  const char* what[] = {"sample", "pdf"};
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < kSamplers.size(); ++i) {
      const double ns = h2h.medianNsPerOp(k * kSamplers.size() + i);
      const double uni = h2h.medianNsPerOp(k * kSamplers.size() + reference[i]);
      const std::string key = std::string(what[k]) + "_" + kSamplers[i];
      st.counters[key + "_ns"] = ns;
      if (reference[i] != i) st.counters[key + "_vs_" + kSamplers[reference[i]]] = ns / uni;
    }
}

}  // namespace

int main(int argc, char** argv) {
  for (const char* name : kSamplers) {
    if (std::string(name) != "cosine")
      benchmark::RegisterBenchmark((std::string("brdf-build/") + name + "/nickel").c_str(), buildTable,
                                   std::string(name))
          ->Unit(benchmark::kMillisecond)
          ->Iterations(1)
          ->Repetitions(3)
          ->DisplayAggregatesOnly(true);
  }
  for (const char* name : kSamplers) {
    benchmark::RegisterBenchmark((std::string("brdf-sample/") + name + "/nickel").c_str(), sampleOne, std::string(name))
        ->MinTime(0.2)
        ->Repetitions(3)
        ->DisplayAggregatesOnly(true);
    benchmark::RegisterBenchmark((std::string("brdf-pdf/") + name + "/nickel").c_str(), pdfOne, std::string(name))
        ->MinTime(0.2)
        ->Repetitions(3)
        ->DisplayAggregatesOnly(true);
  }
  benchmark::RegisterBenchmark("brdf-eval/merl/nickel", evalOne)
      ->MinTime(0.2)
      ->Repetitions(3)
      ->DisplayAggregatesOnly(true);
  // 10 contenders × 4096 ops per round; 100 rounds ≈ 0.4M ops of each.
  benchmark::RegisterBenchmark("brdf-h2h/nickel", headToHead)->Iterations(100)->Unit(benchmark::kMillisecond);

  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

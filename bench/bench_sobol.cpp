// bench_sobol: the Owen-scrambled Sobol generator (sobol.h) against the independent sampler,
// Pcg32::nextFloat, in ns per 1D and per 2D sample.
//
// Every Sobol call gets the arguments a renderer's sampler gives it: the pixel's sample number
// (0 … 1023) as the index, the call site's dimension (0 … 15) and a per-pixel seed; the loop walks
// 16 dimensions of one sample, then the next sample. Benchmarks (ns/op):
// (each iteration is a chunk of 4096 operations; the counter per_op is the CPU time of one)
//   sobol/pcg32_1d, sobol/pcg32_2d         one and two nextFloat() calls
//   sobol/unscrambled_1d                   bitsToUnitFloat(sobolBits(index, dimension))
//   sobol/scrambled_1d                     sobolSample(index, dimension, seed)
//   sobol/padded_1d, sobol/padded_2d       paddedSobol1D / paddedSobol2D(index, dimension, seed)
//   sobol/h2h                              all of them interleaved in chunks: median ns/op of each
//                                          and its ratio to pcg32 (1D to one nextFloat, 2D to two),
//                                          measured under the same noise (counters only)

#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "acdf/sampling/rng.h"
#include "acdf/sampling/sobol.h"
#include "bench_util.h"

namespace {

using namespace acdf;
using namespace acdf::bench;

constexpr uint64_t kPixelSeed = 0x3c6ef372fe94f82bull;

// Operation k of the loop: dimension k mod 16 of sample k / 16 (mod 1024).
constexpr uint32_t indexOf(uint64_t k) { return static_cast<uint32_t>(k >> 4) & 1023u; }
constexpr uint32_t dimensionOf(uint64_t k) { return static_cast<uint32_t>(k) & 15u; }

struct Contender {
  const char* name;
  int dims;  // 1 or 2: compared with one or two nextFloat() calls
  void (*run)(Pcg32& rng, uint64_t first, std::size_t ops);
};

template <class F>
void loop(uint64_t first, std::size_t ops, F f) {
  for (uint64_t k = first; k < first + ops; ++k) benchmark::DoNotOptimize(f(indexOf(k), dimensionOf(k)));
}

const Contender kContenders[] = {
    {"pcg32_1d", 1,
     [](Pcg32& rng, uint64_t, std::size_t ops) {
       for (std::size_t k = 0; k < ops; ++k) benchmark::DoNotOptimize(rng.nextFloat());
     }},
    {"pcg32_2d", 2,
     [](Pcg32& rng, uint64_t, std::size_t ops) {
       for (std::size_t k = 0; k < ops; ++k) {
         const std::array<float, 2> u{rng.nextFloat(), rng.nextFloat()};
         benchmark::DoNotOptimize(u);
       }
     }},
    {"unscrambled_1d", 1,
     [](Pcg32&, uint64_t first, std::size_t ops) {
       loop(first, ops, [](uint32_t i, uint32_t d) { return bitsToUnitFloat(sobolBits(i, d)); });
     }},
    {"scrambled_1d", 1,
     [](Pcg32&, uint64_t first, std::size_t ops) {
       loop(first, ops, [](uint32_t i, uint32_t d) { return sobolSample(i, d, kPixelSeed); });
     }},
    {"padded_1d", 1,
     [](Pcg32&, uint64_t first, std::size_t ops) {
       loop(first, ops, [](uint32_t i, uint32_t d) { return paddedSobol1D(i, d, kPixelSeed); });
     }},
    {"padded_2d", 2,
     [](Pcg32&, uint64_t first, std::size_t ops) {
       loop(first, ops, [](uint32_t i, uint32_t d) { return paddedSobol2D(i, d, kPixelSeed); });
     }},
};

constexpr std::size_t kChunk = 4096;

void single(benchmark::State& st, const Contender& c) {
  Pcg32 rng(7);
  uint64_t first = 0;
  for (auto _ : st) {
    c.run(rng, first, kChunk);
    first += kChunk;
  }
  // CPU seconds per operation (Google Benchmark divides rates by CPU time).
  st.counters["per_op"] =
      benchmark::Counter(double(st.iterations()) * kChunk, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void headToHead(benchmark::State& st) {
  HeadToHead h2h(kChunk);
  Pcg32 rng(7);
  for (const Contender& c : kContenders) h2h.add([&rng, &c](std::size_t first) { c.run(rng, first, kChunk); });
  std::size_t first = 0;
  for (auto _ : st) {
    h2h.round(first);
    first += kChunk;
  }
  const double pcg[] = {0, h2h.medianNsPerOp(0), h2h.medianNsPerOp(1)};
  for (std::size_t i = 0; i < std::size(kContenders); ++i) {
    const Contender& c = kContenders[i];
    const double ns = h2h.medianNsPerOp(i);
    st.counters[std::string("ns_") + c.name] = ns;
    st.counters[std::string(c.name) + "_vs_pcg32"] = ns / pcg[c.dims];
  }
}

}  // namespace

int main(int argc, char** argv) {
  for (const Contender& c : kContenders)
    benchmark::RegisterBenchmark((std::string("sobol/") + c.name).c_str(), single, c)
        ->Unit(benchmark::kMicrosecond)
        ->MinTime(0.1)
        ->Repetitions(3)
        ->DisplayAggregatesOnly(true);
  // 6 contenders × 4096 ops per round; 400 rounds ≈ 1.6M ops of each.
  benchmark::RegisterBenchmark("sobol/h2h", headToHead)->Iterations(400)->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

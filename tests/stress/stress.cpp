// acdf_stress: the numerical stress program (`make stress`). Draws many samples (default 1e8) from
// every distribution on adversarial inputs and checks the numerical contract sample by sample:
// no NaN or Inf, every sample inside its domain, pdf finite and > 0, pdf(x) equal to the
// returned pdf (the worst relative mismatch is reported). Then it measures two precision limits:
// float vs double accumulation of a 4096 × 2048 map's CDF, and the alias method's acceptance
// quantisation (one float variate for both slot and acceptance: exact lattice probabilities and a
// chi-square test; two variates: a chi-square test).
//
// Variates: a share of every run walks the 2^-24 lattice next to 0 and next to 1 (down from the
// largest float below 1), on one axis while the other is random and on both at once; the rest are
// Pcg32 floats. Work is split into fixed blocks, each with its own generator stream, so results do
// not depend on the thread count.
//
// Output: a table on stdout, JSON with --json FILE. Exit status 1 if any invariant broke.

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/envmap/environment_light.h"
#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/hierarchical_warp_2d.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/rng.h"

namespace {

using namespace acdf;

// ---------------------------------------------------------------------------------------------
// Adversarial inputs

struct Input {
  std::string name;
  uint32_t width, height;  // 2D shape (rows = height); 1D distributions use the first cells1D values
  std::vector<float> values;
  uint32_t cells1D;
};

// Most cells a 1D distribution on [0, 1) can hold (GridAxis needs 3 float ulps per cell near 1).
constexpr uint32_t kMax1DCells = 1u << 21;

float unitHash(uint64_t i) {
  Pcg32 rng(i, 0x9e3779b97f4a7c15ULL);
  return rng.nextFloat();
}

Input makeInput(const std::string& name, uint32_t width, uint32_t height, const std::function<float(uint64_t)>& f) {
  Input in{name, width, height, std::vector<float>(std::size_t{width} * height), 0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in.values.size()), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) in.values[i] = f(i);
  });
  in.cells1D = static_cast<uint32_t>(std::min<std::size_t>(in.values.size(), kMax1DCells));
  return in;
}

std::vector<Input> adversarialInputs() {
  std::vector<Input> inputs;
  // Log-uniform over 60 decades.
  inputs.push_back(makeInput("range 1e-30..1e30", 1024, 512, [](uint64_t i) {
    return static_cast<float>(std::pow(10.0, -30.0 + 60.0 * unitHash(i)));
  }));
  // One lit cell in 4096 × 2048, inside the first kMax1DCells values (the 1D tables see it too).
  constexpr uint64_t kLit = 311ull * 4096 + 3071;
  inputs.push_back(makeInput("one lit cell 4096x2048", 4096, 2048, [](uint64_t i) { return i == kLit ? 1.0f : 0.0f; }));
  // Denormals only: every bit pattern below the smallest normal float.
  inputs.push_back(makeInput("denormals only", 1024, 512, [](uint64_t i) {
    const uint32_t bits = 1 + static_cast<uint32_t>(unitHash(i) * 0x7ffffe);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }));
  inputs.push_back(
      makeInput("alternating zeros", 1024, 512, [](uint64_t i) { return (i + i / 1024) % 2 ? 0.0f : 1.0f; }));
  inputs.push_back(makeInput("1e6 equal cells", 1000, 1000, [](uint64_t) { return 1.0f; }));
  return inputs;
}

// ---------------------------------------------------------------------------------------------
// Per-sample checks, reduced over blocks

struct Stats {
  uint64_t samples = 0;
  uint64_t nonFinite = 0;    // NaN / Inf coordinate
  uint64_t outside = 0;      // coordinate outside the domain
  uint64_t badPdf = 0;       // returned pdf not finite or <= 0
  uint64_t mismatches = 0;   // pdf(x) != returned pdf
  uint64_t skipped = 0;      // samples of a distribution that has nothing to sample (a black light)
  double worstMismatch = 0;  // max |pdf(x) − pdf| / pdf

  void merge(const Stats& o) {
    samples += o.samples;
    nonFinite += o.nonFinite;
    outside += o.outside;
    badPdf += o.badPdf;
    mismatches += o.mismatches;
    skipped += o.skipped;
    worstMismatch = std::max(worstMismatch, o.worstMismatch);
  }
  bool ok() const { return nonFinite == 0 && outside == 0 && badPdf == 0; }

  void check(bool finite, bool inside, double pdf, double pdfAtX) {
    ++samples;
    if (!finite) ++nonFinite;
    if (!inside) ++outside;
    if (!(std::isfinite(pdf) && pdf > 0.0)) {
      ++badPdf;
      return;
    }
    if (pdfAtX != pdf) {
      ++mismatches;
      worstMismatch = std::max(worstMismatch, std::fabs(pdfAtX - pdf) / pdf);
    }
  }
};

constexpr uint64_t kBlock = 1 << 16;
constexpr uint64_t kLattice = 1 << 16;  // lattice steps walked next to 0 and next to 1

float nearZero(uint64_t k) { return static_cast<float>(k) * 0x1p-24f; }
float nearOne(uint64_t k) { return kOneMinusEpsilon - static_cast<float>(k) * 0x1p-24f; }

// The variates of sample i: six lattice patterns of kLattice samples each first (u0 next to 0 or 1
// with u1 random, the same for u1, and both at opposite ends), then random.
std::array<float, 2> variates(uint64_t i, uint64_t total, Pcg32& rng) {
  const float r0 = rng.nextFloat(), r1 = rng.nextFloat();
  const uint64_t pattern = i / kLattice, k = i % kLattice;
  if (total < 6 * kLattice * 2) return {r0, r1};  // too few samples: random only
  switch (pattern) {
    case 0: return {nearZero(k), r1};
    case 1: return {nearOne(k), r1};
    case 2: return {r0, nearZero(k)};
    case 3: return {r0, nearOne(k)};
    case 4: return {nearZero(k), nearOne(k)};
    case 5: return {nearOne(k), nearZero(k)};
    default: return {r0, r1};
  }
}

// Runs check(u0, u1, stats) for `total` samples in parallel blocks.
Stats runSamples(uint64_t total, const std::function<void(float, float, Stats&)>& check) {
  const uint64_t blocks = (total + kBlock - 1) / kBlock;
  return tbb::parallel_reduce(
      tbb::blocked_range<uint64_t>(0, blocks), Stats{},
      [&](const tbb::blocked_range<uint64_t>& r, Stats s) {
        for (uint64_t b = r.begin(); b != r.end(); ++b) {
          Pcg32 rng(0x5eed, b);
          for (uint64_t i = b * kBlock; i < std::min(total, (b + 1) * kBlock); ++i) {
            const auto u = variates(i, total, rng);
            check(u[0], u[1], s);
          }
        }
        return s;
      },
      [](Stats a, const Stats& b) {
        a.merge(b);
        return a;
      });
}

template <class Distribution>
Stats stress1D(const Distribution& d, uint64_t samples) {
  return runSamples(samples, [&](float u0, float, Stats& s) {
    const Sample1D x = d.sample(u0);
    s.check(std::isfinite(x.x), d.axis().contains(x.x), x.pdf, d.pdf(x.x));
  });
}

template <class Distribution>
Stats stress2D(const Distribution& d, const std::vector<GridAxis>& axes, uint64_t samples) {
  return runSamples(samples, [&](float u0, float u1, Stats& s) {
    const float u[2] = {u0, u1};
    const SampleND x = d.sample(u);
    const bool finite = std::isfinite(x.x[0]) && std::isfinite(x.x[1]);
    s.check(finite, axes[0].contains(x.x[0]) && axes[1].contains(x.x[1]), x.pdf, d.pdf(x.point()));
  });
}

// Directions have no grid domain: "inside" means unit length. pdf(ω) is recomputed from the
// direction, whose pixel lookup may land in a neighbour at a pixel edge: the mismatch measures it.
// The light's own strategy's table is stressed (compensated: the compensated one).
Stats stressLight(const EnvironmentLight& light, uint64_t samples) {
  constexpr LightSampleContext context{.allowIncompletePdf = true};
  return runSamples(samples, [&](float u0, float u1, Stats& s) {
    const LightSample e = light.sample(context, u0, u1);
    if (light.emitsNothing()) {
      ++s.skipped;
      if (e.pdf != 0.0) ++s.badPdf;
      return;
    }
    const Vec3d& w = e.direction;
    const bool finite = std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z);
    const double length = std::sqrt(dot(w, w));
    s.check(finite, std::fabs(length - 1.0) < 1e-6, e.pdf, light.pdf(context, w));
  });
}

struct Row {
  std::string distribution, input;
  std::string note;  // e.g. a constructor's exception
  double buildSeconds = 0;
  Stats stats;
};

template <class Build, class Stress>
Row measure(const std::string& distribution, const std::string& input, Build build, Stress stress) {
  Row row;
  row.distribution = distribution;
  row.input = input;
  const auto start = std::chrono::steady_clock::now();
  try {
    const auto d = build();
    row.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    row.stats = stress(*d);
  } catch (const std::invalid_argument& e) {
    row.note = std::string("rejected: ") + e.what();
  }
  std::printf("  %-29s %-24s %9.3g samples  %s\n", distribution.c_str(), input.c_str(),
              static_cast<double>(row.stats.samples), row.note.c_str());
  std::fflush(stdout);
  return row;
}

std::vector<Row> stressDistributions(const std::vector<Input>& inputs, uint64_t samples) {
  std::vector<Row> rows;
  for (const Input& in : inputs) {
    const std::span<const float> flat(in.values.data(), in.cells1D);
    const std::vector<GridAxis> axes = {GridAxis(in.height), GridAxis(in.width)};
    rows.push_back(measure(
        "PiecewiseConstant1D", in.name, [&] { return std::make_unique<PiecewiseConstant1D>(flat); },
        [&](const auto& d) { return stress1D(d, samples); }));
    rows.push_back(measure(
        "AdaptiveCdf1D", in.name, [&] { return std::make_unique<AdaptiveCdf1D>(flat); },
        [&](const auto& d) { return stress1D(d, samples); }));
    rows.push_back(measure(
        "AliasTable1D", in.name, [&] { return std::make_unique<AliasTable1D>(flat); },
        [&](const auto& d) { return stress1D(d, samples); }));
    rows.push_back(measure(
        "AliasGrid", in.name, [&] { return std::make_unique<AliasGrid>(in.values, axes); },
        [&](const auto& d) { return stress2D(d, axes, samples); }));
    rows.push_back(measure(
        "HierarchicalWarp2D", in.name, [&] { return std::make_unique<HierarchicalWarp2D>(in.values, axes); },
        [&](const auto& d) { return stress2D(d, axes, samples); }));
    for (auto method : {DimensionMethod::Adaptive, DimensionMethod::Uniform}) {
      const bool adaptive = method == DimensionMethod::Adaptive;
      rows.push_back(measure(
          adaptive ? "Cascade 2D adaptive" : "Cascade 2D uniform", in.name,
          [&] {
            CascadeOptions options;
            options.methods = {method, method};
            return std::make_unique<Cascade>(in.values, axes, options);
          },
          [&](const auto& d) { return stress2D(d, axes, samples); }));
    }
    // The light sees the input as a gray map's radiance.
    std::vector<float> rgb(3 * in.values.size());
    for (std::size_t i = 0; i < in.values.size(); ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = in.values[i];
    const auto map = std::make_shared<const EnvironmentMap>(in.width, in.height, std::move(rgb));
    for (auto strategy : {EnvironmentSampling::Uniform, EnvironmentSampling::Alias, EnvironmentSampling::Adaptive,
                          EnvironmentSampling::Compensated, EnvironmentSampling::Hierarchical}) {
      rows.push_back(measure(
          "EnvironmentLight " + std::string(toString(strategy)), in.name,
          [&] { return std::make_unique<EnvironmentLight>(map, EnvironmentLightOptions{.strategy = strategy}); },
          [&](const auto& d) { return stressLight(d, samples); }));
    }
  }
  return rows;
}

// ---------------------------------------------------------------------------------------------
// Float vs double accumulation of a 4096 × 2048 map's CDF

struct Accumulation {
  std::string type;
  double totalRelativeError = 0;  // |Σ − reference| / reference
  double worstCdfError = 0;       // max over k of |F(k) − F_ref(k)|, F normalised to end at 1
};

// A sky-like map: noisy radiance times sin θ (the solid angle of each row), with a sun 1e4 times
// brighter than the sky in a few hundred pixels.
std::vector<float> skyMap(uint32_t width, uint32_t height) {
  std::vector<float> v(std::size_t{width} * height);
  tbb::parallel_for(uint32_t{0}, height, [&](uint32_t row) {
    const double sinTheta = std::sin((row + 0.5) / height * 3.141592653589793);
    for (uint32_t col = 0; col < width; ++col) {
      const double dr = (row - height * 0.3) / 6.0, dc = (col - width * 0.6) / 6.0;
      const double sun = 1e4 * std::exp(-(dr * dr + dc * dc));
      v[std::size_t{row} * width + col] =
          static_cast<float>((0.5 + unitHash(std::size_t{row} * width + col) + sun) * sinTheta);
    }
  });
  return v;
}

template <class T>
Accumulation accumulate(const std::string& type, std::span<const float> values,
                        const std::vector<long double>& reference) {
  // Sequential prefix sums, as a CDF table is built; the reference is the same in long double.
  std::vector<T> prefix(values.size() + 1);
  T sum = 0;
  for (std::size_t i = 0; i < values.size(); ++i) prefix[i + 1] = sum += static_cast<T>(values[i]);
  const long double refTotal = reference.back();
  Accumulation a{type};
  a.totalRelativeError = static_cast<double>(std::fabs(static_cast<long double>(sum) - refTotal) / refTotal);
  for (std::size_t k = 0; k < prefix.size(); ++k) {
    const long double f = static_cast<long double>(prefix[k] / sum), ref = reference[k] / refTotal;
    a.worstCdfError = std::max(a.worstCdfError, static_cast<double>(std::fabs(f - ref)));
  }
  return a;
}

std::vector<Accumulation> compareAccumulation() {
  const std::vector<float> map = skyMap(4096, 2048);
  std::vector<long double> reference(map.size() + 1);
  long double sum = 0;
  for (std::size_t i = 0; i < map.size(); ++i) reference[i + 1] = sum += map[i];
  return {accumulate<float>("float", map, reference), accumulate<double>("double", map, reference)};
}

// ---------------------------------------------------------------------------------------------
// Alias-method acceptance quantisation

struct AliasQuantisation {
  uint32_t log2Cells = 0;
  uint32_t acceptanceBits = 0;      // 24 − log2(cells): what a float variate leaves for acceptance
  double worstRelativeError = 0;    // max over cells of |P_lattice − P| / P, exact over all 2^24 variates
  double totalVariation = 0;        // ½ Σ |P_lattice − P|
  ChiSquareResult chi2;             // sampled cell counts against P, one variate
  ChiSquareResult chi2TwoVariates;  // the same with sample(uCell, uAccept)
  uint64_t samples = 0;
};

AliasQuantisation aliasQuantisation(uint32_t log2Cells, uint64_t samples) {
  const uint32_t n = 1u << log2Cells;
  std::vector<float> weights(n);
  for (uint32_t i = 0; i < n; ++i) weights[i] = 0.5f + unitHash(i);  // within a factor 3 of each other
  const AliasTable table(weights);
  // Exact: every float variate a [0,1) generator on the 2^-24 lattice can return, once.
  std::vector<std::atomic<uint32_t>> lattice(n);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, 1u << 24), [&](const auto& r) {
    for (uint32_t m = r.begin(); m != r.end(); ++m)
      lattice[table.sample(static_cast<float>(m) * 0x1p-24f).index].fetch_add(1, std::memory_order_relaxed);
  });
  AliasQuantisation q;
  q.log2Cells = log2Cells;
  q.acceptanceBits = 24 - log2Cells;
  double sum = 0;
  for (float w : weights) sum += w;
  for (uint32_t i = 0; i < n; ++i) {
    const double p = weights[i] / sum, pLattice = lattice[i].load() * 0x1p-24;
    q.worstRelativeError = std::max(q.worstRelativeError, std::fabs(pLattice - p) / p);
    q.totalVariation += 0.5 * std::fabs(pLattice - p);
  }
  // Sampled, as a renderer would: Pcg32 floats.
  std::vector<double> expected(n);
  for (uint32_t i = 0; i < n; ++i) expected[i] = static_cast<double>(samples) * weights[i] / sum;
  auto chiSquare = [&](bool twoVariates) {
    std::vector<std::atomic<uint32_t>> counts(n);
    const uint64_t blocks = (samples + kBlock - 1) / kBlock;
    tbb::parallel_for(uint64_t{0}, blocks, [&](uint64_t b) {
      Pcg32 rng(0xa11a5, b);
      for (uint64_t i = b * kBlock; i < std::min(samples, (b + 1) * kBlock); ++i) {
        const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
        const uint32_t cell = twoVariates ? table.sample(u0, u1).index : table.sample(u0).index;
        counts[cell].fetch_add(1, std::memory_order_relaxed);
      }
    });
    std::vector<double> observed(n);
    for (uint32_t i = 0; i < n; ++i) observed[i] = counts[i].load();
    return chiSquareTest(observed, expected);
  };
  q.chi2 = chiSquare(false);
  q.chi2TwoVariates = chiSquare(true);
  q.samples = samples;
  return q;
}

// ---------------------------------------------------------------------------------------------

nlohmann::json toJson(const Row& r) {
  return {{"distribution", r.distribution},
          {"input", r.input},
          {"note", r.note},
          {"build_s", r.buildSeconds},
          {"samples", r.stats.samples},
          {"non_finite", r.stats.nonFinite},
          {"outside_domain", r.stats.outside},
          {"bad_pdf", r.stats.badPdf},
          {"pdf_mismatches", r.stats.mismatches},
          {"worst_relative_pdf_mismatch", r.stats.worstMismatch},
          {"skipped_emits_nothing", r.stats.skipped},
          {"ok", r.stats.ok()}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"acdf_stress: numerical stress test of every distribution on adversarial inputs"};
  double samples = 1e8;
  double chiSamples = 1e7;
  std::string jsonPath;
  bool contractOnly = false;
  app.add_option("--samples", samples, "samples per distribution and input")->check(CLI::PositiveNumber);
  app.add_option("--chi-samples", chiSamples, "samples per alias-quantisation chi-square test")
      ->check(CLI::PositiveNumber);
  app.add_option("--json", jsonPath, "write the results as JSON to this file");
  app.add_flag("--contract-only", contractOnly, "only the per-sample checks, not the precision studies (the ctest)");
  CLI11_PARSE(app, argc, argv);
  const auto n = static_cast<uint64_t>(samples);

  std::printf("acdf_stress: %.3g samples per distribution and input\n", samples);
  auto seconds = [start = std::chrono::steady_clock::now()] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const std::vector<Row> rows = stressDistributions(adversarialInputs(), n);
  const double distributionSeconds = seconds();
  std::vector<Accumulation> accumulation;
  std::vector<AliasQuantisation> alias;
  if (!contractOnly) {
    accumulation = compareAccumulation();
    for (uint32_t k : {12u, 16u, 19u, 21u, 23u})
      alias.push_back(aliasQuantisation(k, static_cast<uint64_t>(chiSamples)));
  }
  std::printf("\n%.1f s for the distributions, %.1f s for the precision studies\n", distributionSeconds,
              seconds() - distributionSeconds);

  bool ok = true;
  std::printf("\n%-29s %-24s %10s %7s %7s %7s %9s %12s %8s\n", "distribution", "input", "samples", "nonfin", "outside",
              "badpdf", "mismatch", "worst rel", "build s");
  for (const Row& r : rows) {
    ok = ok && r.stats.ok();
    std::printf("%-29s %-24s %10.3g %7llu %7llu %7llu %9llu %12.3g %8.2f %s\n", r.distribution.c_str(), r.input.c_str(),
                static_cast<double>(r.stats.samples), static_cast<unsigned long long>(r.stats.nonFinite),
                static_cast<unsigned long long>(r.stats.outside), static_cast<unsigned long long>(r.stats.badPdf),
                static_cast<unsigned long long>(r.stats.mismatches), r.stats.worstMismatch, r.buildSeconds,
                r.stats.skipped ? "(emits nothing: no samples)" : r.note.c_str());
  }
  std::printf("\nCDF accumulation over a 4096 x 2048 sky map (reference: long double)\n%-8s %16s %16s\n", "type",
              "total rel err", "worst CDF err");
  for (const Accumulation& a : accumulation)
    std::printf("%-8s %16.3g %16.3g\n", a.type.c_str(), a.totalRelativeError, a.worstCdfError);
  std::printf(
      "\nAlias acceptance quantisation: one float variate for slot and acceptance (exact over the 2^-24\n"
      "lattice, and chi-square), and two variates (chi-square)\n%6s %5s %14s %12s %12s %14s %10s\n",
      "cells", "bits", "worst rel err", "TV distance", "chi2 p", "chi2 p (two)", "samples");
  for (const AliasQuantisation& q : alias)
    std::printf("2^%-4u %5u %14.3g %12.3g %12.3g %14.3g %10.3g\n", q.log2Cells, q.acceptanceBits, q.worstRelativeError,
                q.totalVariation, q.chi2.pvalue, q.chi2TwoVariates.pvalue, static_cast<double>(q.samples));

  if (!jsonPath.empty()) {
    nlohmann::json j;
    j["samples_per_distribution"] = n;
    for (const Row& r : rows) j["distributions"].push_back(toJson(r));
    for (const Accumulation& a : accumulation)
      j["accumulation"].push_back(
          {{"type", a.type}, {"total_relative_error", a.totalRelativeError}, {"worst_cdf_error", a.worstCdfError}});
    for (const AliasQuantisation& q : alias)
      j["alias_quantisation"].push_back({{"log2_cells", q.log2Cells},
                                         {"acceptance_bits", q.acceptanceBits},
                                         {"worst_relative_error", q.worstRelativeError},
                                         {"total_variation", q.totalVariation},
                                         {"chi2_statistic", q.chi2.statistic},
                                         {"chi2_dof", q.chi2.dof},
                                         {"chi2_pvalue", q.chi2.pvalue},
                                         {"chi2_two_variates_statistic", q.chi2TwoVariates.statistic},
                                         {"chi2_two_variates_pvalue", q.chi2TwoVariates.pvalue},
                                         {"samples", q.samples}});
    j["ok"] = ok;
    std::ofstream(jsonPath) << j.dump(2) << "\n";
  }
  std::printf("\n%s\n", ok ? "acdf_stress: every sample kept the contract" : "acdf_stress: INVARIANT BROKEN");
  return ok ? 0 : 1;
}

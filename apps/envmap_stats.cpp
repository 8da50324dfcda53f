#include "envmap_stats.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/envmap/environment_light.h"
#include "acdf/sampling/frame.h"
#include "acdf/sampling/quality.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sphere.h"
#include "errors.h"
#include "image.h"
#include "options.h"

namespace acdf::app {

namespace {

// The fixed estimator: irradiance E(n) = ∫ Y(L(ω)) max(0, n·ω) dω at kNormals normals spread
// evenly over the sphere (a Fibonacci lattice), kSamplesPerNormal one-sample estimates each,
// variates from Pcg32(kSeed). The stratified variant spends the same samples per normal on
// kStratifiedTrials estimates, each the mean over a jittered kStrata × kStrata set of variates.
constexpr uint32_t kNormals = 64;
constexpr uint32_t kSamplesPerNormal = 4096;
constexpr uint64_t kSeed = 1;
constexpr uint32_t kStrata = 16;
constexpr uint32_t kStratifiedTrials = kSamplesPerNormal / (kStrata * kStrata);

struct EnvmapStatsArgs {
  std::string input;
  double epsilon = SimplifyOptions{}.epsilon;
  bool sanitize = false;
  bool json = false;
};

std::vector<Vec3d> fibonacciNormals() {
  std::vector<Vec3d> normals;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (uint32_t k = 0; k < kNormals; ++k) {
    const double y = 1.0 - (2.0 * k + 1.0) / kNormals;
    const double r = std::sqrt(1.0 - y * y);
    normals.push_back({r * std::cos(golden * k), y, r * std::sin(golden * k)});
  }
  return normals;
}

// E(n) of the map as it is sampled (radiance constant per pixel), by the pixel-centre rule.
std::vector<double> exactIrradiance(const EnvironmentMap& map, const std::vector<Vec3d>& normals) {
  std::vector<double> irradiance(normals.size(), 0.0);
  for (uint32_t r = 0; r < map.height(); ++r) {
    const double solidAngle = map.mapping().pixelSolidAngle(r);
    for (uint32_t c = 0; c < map.width(); ++c) {
      const double L = map.radiance(PixelIndex{r, c}).luminance();
      if (L == 0) continue;
      const Vec3d w = map.mapping().directionInPixel({r, c}, 0.5, 0.5);
      for (std::size_t k = 0; k < normals.size(); ++k)
        irradiance[k] += L * solidAngle * std::max(0.0, dot(normals[k], w));
    }
  }
  return irradiance;
}

// One estimate of E(n): a direction and its pdf, weighted.
using Estimate = std::function<double(const Vec3d& normal, float u0, float u1)>;

struct StrategyCost {
  double variance = 0;  // mean over the normals of E[(X − E)²] / E², normals with E > 0
  // The same for n · (mean of n = kStrata² jittered samples − E)²: equals `variance` when
  // stratification gains nothing, and is lower by the factor it gains. Measured for the map's
  // own samplers only: uniform_sphere's and cosine's weights are heavy-tailed (a sun hit is rare
  // and huge), which kStratifiedTrials estimates per normal cannot average.
  std::optional<double> stratifiedVariance;
  double nsPerSample = 0;
  double efficiency = 0;  // 1 / (variance × seconds per sample)
};

StrategyCost measure(const Estimate& estimate, const std::vector<Vec3d>& normals, const std::vector<double>& exact,
                     bool stratified) {
  StrategyCost cost;
  Pcg32 rng(kSeed);
  double relativeVariance = 0;
  uint32_t lit = 0;
  const auto start = Clock::now();
  for (std::size_t k = 0; k < normals.size(); ++k) {
    double squaredError = 0;
    for (uint32_t i = 0; i < kSamplesPerNormal; ++i) {
      const double x = estimate(normals[k], rng.nextFloat(), rng.nextFloat());
      squaredError += (x - exact[k]) * (x - exact[k]);
    }
    if (exact[k] > 0) {
      relativeVariance += squaredError / kSamplesPerNormal / (exact[k] * exact[k]);
      ++lit;
    }
  }
  cost.nsPerSample = std::chrono::duration<double, std::nano>(Clock::now() - start).count() /
                     (static_cast<double>(normals.size()) * kSamplesPerNormal);
  cost.variance = lit > 0 ? relativeVariance / lit : 0.0;
  cost.efficiency = cost.variance > 0 ? 1.0 / (cost.variance * cost.nsPerSample * 1e-9) : 0.0;
  if (!stratified) return cost;

  constexpr double kPerTrial = kStrata * kStrata;
  relativeVariance = 0;
  for (std::size_t k = 0; k < normals.size(); ++k) {
    if (!(exact[k] > 0)) continue;
    double squaredError = 0;
    for (uint32_t t = 0; t < kStratifiedTrials; ++t) {
      double sum = 0;
      for (uint32_t i = 0; i < kStrata; ++i)
        for (uint32_t j = 0; j < kStrata; ++j) {
          const float u0 = (static_cast<float>(i) + rng.nextFloat()) / kStrata;
          const float u1 = (static_cast<float>(j) + rng.nextFloat()) / kStrata;
          sum += estimate(normals[k], u0, u1);
        }
      squaredError += (sum / kPerTrial - exact[k]) * (sum / kPerTrial - exact[k]);
    }
    relativeVariance += kPerTrial * squaredError / kStratifiedTrials / (exact[k] * exact[k]);
  }
  cost.stratifiedVariance = lit > 0 ? relativeVariance / lit : 0.0;
  return cost;
}

struct Table {
  std::unique_ptr<EnvironmentLight> light;
  double buildMs = 0;
};

Table build(const std::shared_ptr<const EnvironmentMap>& map, EnvironmentSampling strategy, double epsilon) {
  EnvironmentLightOptions options;
  options.strategy = strategy;
  options.simplify.epsilon = epsilon;
  const auto start = Clock::now();
  Table t;
  t.light = std::make_unique<EnvironmentLight>(map, options);
  t.buildMs = millisecondsSince(start);
  return t;
}

int runEnvmapStats(const EnvmapStatsArgs& args) {
  if (!(args.epsilon >= 0)) throw UsageError("envmap-stats: --epsilon must be >= 0");
  const std::shared_ptr<const EnvironmentMap> map = readEnvironmentMap(args.input, args.sanitize);
  if (map->isBlack())
    throw FileError(args.input, "the map is black everywhere: a light that emits nothing has no table to report on");

  const Table uniform = build(map, EnvironmentSampling::Uniform, args.epsilon);
  const Table alias = build(map, EnvironmentSampling::Alias, args.epsilon);
  const Table adaptive = build(map, EnvironmentSampling::Adaptive, args.epsilon);
  const Table hierarchical = build(map, EnvironmentSampling::Hierarchical, args.epsilon);

  const EnvironmentTable& adaptiveTable = adaptive.light->table({});
  std::vector<double> exact(adaptiveTable.tabulated().begin(), adaptiveTable.tabulated().end());
  double total = 0;
  for (double v : exact) total += v;
  for (double& v : exact) v /= total;
  const CompressionQuality quality = compareCellProbabilities(exact, adaptiveTable.pixelProbabilities());
  // The uniform table is the exact distribution up to its float CDFs: its divergence is the
  // relative variance of L/pdf, which would be 0 with exact probabilities.
  const CompressionQuality uniformQuality =
      compareCellProbabilities(exact, uniform.light->table({}).pixelProbabilities());
  exact = {};

  const std::vector<Vec3d> normals = fibonacciNormals();
  const std::vector<double> irradiance = exactIrradiance(*map, normals);
  const EnvironmentLight& anyLight = *uniform.light;  // eval() does not depend on the strategy
  auto lightSampling = [](const EnvironmentLight& light) -> Estimate {
    return [&light](const Vec3d& n, float u0, float u1) {
      const LightSample s = light.sample({}, u0, u1);
      return s.radiance.luminance() * std::max(0.0, dot(n, s.direction)) / s.pdf;
    };
  };
  struct Named {
    const char* name;
    Estimate estimate;
    bool mapSampler;
    StrategyCost cost;
  };
  std::vector<Named> strategies = {
      {"uniform_sphere",
       [&](const Vec3d& n, float u0, float u1) {
         const Vec3d w = sampleUniformSphere(u0, u1);
         return anyLight.eval(w).luminance() * std::max(0.0, dot(n, w)) / kUniformSpherePdf;
       },
       false,
       {}},
      {"cosine",
       [&](const Vec3d& n, float u0, float u1) {
         const Vec3d w = Frame(n).toWorld(sampleCosineHemisphere(u0, u1));
         // Y(L) cos θ / (cos θ / π)
         return anyLight.eval(w).luminance() * std::numbers::pi;
       },
       false,
       {}},
      {"uniform", lightSampling(*uniform.light), true, {}},
      {"alias", lightSampling(*alias.light), true, {}},
      {"adaptive", lightSampling(*adaptive.light), true, {}},
      {"hierarchical", lightSampling(*hierarchical.light), true, {}},
  };
  for (Named& s : strategies) s.cost = measure(s.estimate, normals, irradiance, s.mapSampler);

  const double compression = static_cast<double>(uniform.light->tableBytes()) / adaptive.light->tableBytes();
  if (args.json) {
    nlohmann::ordered_json j;
    j["width"] = map->width();
    j["height"] = map->height();
    j["uniform_bytes"] = uniform.light->tableBytes();
    j["alias_bytes"] = alias.light->tableBytes();
    j["adaptive_bytes"] = adaptive.light->tableBytes();
    j["hierarchical_bytes"] = hierarchical.light->tableBytes();
    j["compression"] = compression;
    j["chi2_divergence"] = quality.chi2Divergence;
    j["max_weight_ratio"] = quality.maxWeightRatio;
    j["unreachable_mass"] = quality.unreachableMass;
    j["uniform_chi2_divergence"] = uniformQuality.chi2Divergence;
    j["uniform_unreachable_mass"] = uniformQuality.unreachableMass;
    j["negative_pixels_clamped"] = map->negativePixelsClamped();
    if (args.sanitize) j["nonfinite_pixels_replaced"] = map->nonFiniteReplaced();
    j["build_ms"] = {{"uniform", uniform.buildMs},
                     {"alias", alias.buildMs},
                     {"adaptive", adaptive.buildMs},
                     {"hierarchical", hierarchical.buildMs}};
    for (const Named& s : strategies) {
      j[s.name] = {
          {"variance", s.cost.variance}, {"ns_per_sample", s.cost.nsPerSample}, {"efficiency", s.cost.efficiency}};
      if (s.cost.stratifiedVariance) j[s.name]["stratified_variance"] = *s.cost.stratifiedVariance;
    }
    std::puts(j.dump(2).c_str());
  } else {
    std::string out;
    out += fmt::format("input              {} ({} x {})\n", args.input, map->width(), map->height());
    out +=
        fmt::format("negative clamped   {} pixels had a negative channel (set to 0)\n", map->negativePixelsClamped());
    if (args.sanitize)
      out += fmt::format("non-finite         {} channel values replaced with 0\n", map->nonFiniteReplaced());
    out += fmt::format("\n{:<18} {:>14} {:>14} {:>14} {:>14}\n", "", "uniform", "alias", "adaptive", "hierarchical");
    out += fmt::format("{:<18} {:>14} {:>14} {:>14} {:>14}\n", "bytes", uniform.light->tableBytes(),
                       alias.light->tableBytes(), adaptive.light->tableBytes(), hierarchical.light->tableBytes());
    out += fmt::format("{:<18} {:>14.2f} {:>14.2f} {:>14.2f} {:>14.2f}\n", "build ms", uniform.buildMs, alias.buildMs,
                       adaptive.buildMs, hierarchical.buildMs);
    out += fmt::format("\ncompression        {:.2f}x (uniform bytes / adaptive bytes), epsilon {:g}\n", compression,
                       args.epsilon);
    out += fmt::format("chi2 divergence    {:.6g} (variance added by the compression; 0 = exact)\n",
                       quality.chi2Divergence);
    out += fmt::format("max weight ratio   {:.6g}\n", quality.maxWeightRatio);
    out += fmt::format("unreachable mass   {:.6g} (adaptive), {:.6g} (uniform): lit pixels of pdf 0\n",
                       quality.unreachableMass, uniformQuality.unreachableMass);
    out += fmt::format("uniform divergence {:.6g} (its float CDFs' variance of L/pdf; 0 = exact)\n",
                       uniformQuality.chi2Divergence);
    out += fmt::format(
        "\nirradiance at {} normals, {} samples each (relative variance per sample; stratified: {} x {} "
        "jittered variates per estimate):\n",
        kNormals, kSamplesPerNormal, kStrata, kStrata);
    out += fmt::format("{:<18} {:>14} {:>14} {:>14} {:>14}\n", "strategy", "variance", "ns/sample", "efficiency",
                       "stratified");
    for (const Named& s : strategies)
      out += fmt::format("{:<18} {:>14.6g} {:>14.1f} {:>14.4g} {:>14}\n", s.name, s.cost.variance, s.cost.nsPerSample,
                         s.cost.efficiency,
                         s.cost.stratifiedVariance ? fmt::format("{:.6g}", *s.cost.stratifiedVariance) : "-");
    std::fputs(out.c_str(), stdout);
  }
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command addEnvmapStats(CLI::App& parent) {
  auto args = std::make_shared<EnvmapStatsArgs>();
  CLI::App* app = parent.add_subcommand(
      "envmap-stats",
      "Build the uniform, alias, adaptive and hierarchical sampling tables of an environment map and compare their "
      "size, "
      "build time, accuracy and the variance of an irradiance estimator with each.");
  app->footer(fmt::format(
      "FILE: an equirectangular environment map OpenImageIO reads (subimage 0, MIP level 0; +Y up, see\n"
      "README). Negative channels are clamped to 0 and counted; NaN/Inf is an error unless --sanitize.\n"
      "The tables sample pixels with probability proportional to luminance x solid angle.\n"
      "chi2_divergence / max_weight_ratio / unreachable_mass: the adaptive table's pixel probabilities against\n"
      "the exact ones (unreachable_mass: the exact probability of pixels the table gives pdf 0; always 0).\n"
      "uniform_chi2_divergence / uniform_unreachable_mass: the same for the uniform table, whose float CDFs\n"
      "round the exact probabilities: its divergence is the relative variance of L/pdf (0 if exact).\n"
      "\n"
      "Estimator: irradiance E(n) = integral of Y(L) max(0, n.w) dw at {} normals (a Fibonacci lattice),\n"
      "{} one-sample estimates X each with variates from PCG32 seed {}. variance = mean over the normals\n"
      "(with E > 0) of E[(X - E)^2] / E^2, E computed exactly from the pixels; efficiency = 1 / (variance x\n"
      "seconds per sample). uniform_sphere and cosine sample directions without the map (cosine: about n).\n"
      "stratified_variance (the map's samplers): {} estimates per normal, each the mean of n = {} x {}\n"
      "jittered variates; n x E[(mean - E)^2] / E^2 averaged like variance: lower than variance by the\n"
      "factor stratification gains.\n"
      "\n"
      "Exit status: 0 success, 2 bad input file (also a black map) or command line, 1 internal error.",
      kNormals, kSamplesPerNormal, kSeed, kStratifiedTrials, kStrata, kStrata));
  app->add_option("FILE", args->input, "Environment map (any image OpenImageIO reads)")->required();
  app->add_option("--epsilon", args->epsilon, "Largest CDF error the adaptive simplifier leaves (>= 0)")
      ->capture_default_str();
  app->add_flag("--sanitize", args->sanitize, "Replace NaN/Inf channel values with 0 (and count them)");
  app->add_flag("--json", args->json, "Print one JSON object instead of the table");
  return Command{app, [args] { return runEnvmapStats(*args); }};
}

}  // namespace acdf::app

#include "envmap_stats.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/irradiance_estimator.h"
#include "acdf/sampling/quality.h"
#include "errors.h"
#include "image.h"
#include "options.h"

namespace acdf::app {

namespace {

std::string chromaticitiesText(const std::optional<Chromaticities>& declared) {
  if (!declared) return "none declared (Rec. 709 primaries, D65 white assumed)";
  if (sameChromaticities(*declared, kRec709)) return "declared " + toString(*declared) + " (Rec. 709 / D65)";
  return "declared " + toString(*declared) + ", converted to Rec. 709 / D65 (through XYZ, no chromatic adaptation)";
}

// The fixed estimator of the strategies (acdf/envmap/irradiance_estimator.h), at its defaults.
const IrradianceEstimatorOptions kEstimator;

struct EnvmapStatsArgs {
  std::string input;
  double epsilon = SimplifyOptions{}.epsilon;
  bool sanitize = false;
  bool json = false;
  bool local = false;               // also local sampling (a table per normal cell)
  std::vector<uint32_t> normalRes;  // --normal-res R,C: its normal grid
};

// The local sampling options --normal-res gives (the defaults without it).
LocalEnvironmentOptions localOptions(const EnvmapStatsArgs& args) {
  LocalEnvironmentOptions options;
  if (args.normalRes.empty()) return options;
  if (args.normalRes.size() != 2) throw UsageError("envmap-stats: --normal-res takes ROWS,COLUMNS");
  options.normalRows = args.normalRes[0];
  options.normalColumns = args.normalRes[1];
  try {
    validate(options);
  } catch (const OptionError& e) {
    throw UsageError("envmap-stats: --normal-res " + e.problem());
  }
  return options;
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
  EnvironmentLightOptions options;
  options.simplify.epsilon = args.epsilon;
  validateFlags(options, "envmap-stats: ");
  options.local = localOptions(args);
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

  const IrradianceEstimator estimator(*map, kEstimator);
  const EnvironmentLight& anyLight = *uniform.light;  // eval() does not depend on the strategy
  struct Named {
    const char* name;
    IrradianceSampler sampler;
    bool mapSampler;
    IrradianceCost cost;
  };
  std::vector<Named> strategies = {
      {"uniform_sphere", uniformSphereEstimator(anyLight), false, {}},
      {"cosine", cosineEstimator(anyLight), false, {}},
      {"uniform", lightSamplingEstimator(*uniform.light), true, {}},
      {"alias", lightSamplingEstimator(*alias.light), true, {}},
      {"adaptive", lightSamplingEstimator(*adaptive.light), true, {}},
      {"hierarchical", lightSamplingEstimator(*hierarchical.light), true, {}},
  };
  for (Named& s : strategies) s.cost = estimator.measure(s.sampler, s.mapSampler);

  // Local sampling: the light (with its adaptive table for calls without a normal, not counted)
  // and every slice, built in parallel; the estimator then samples each normal's own slice.
  std::unique_ptr<EnvironmentLight> local;
  double localBuildMs = 0;
  IrradianceCost localCost;
  if (args.local) {
    const auto start = Clock::now();
    local = std::make_unique<EnvironmentLight>(
        map, EnvironmentLightOptions{
                 .strategy = EnvironmentSampling::Local, .simplify = options.simplify, .local = options.local});
    local->localTable()->buildAll();
    localBuildMs = millisecondsSince(start);
    localCost = estimator.measure(lightSamplingEstimator(*local), true);
  }
  const double adaptiveVariance = std::find_if(strategies.begin(), strategies.end(), [](const Named& s) {
                                    return s.name == std::string_view("adaptive");
                                  })->cost.variance;

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
    if (const auto& c = map->declaredChromaticities())
      j["declared_chromaticities"] = {{"red", c->red},
                                      {"green", c->green},
                                      {"blue", c->blue},
                                      {"white", c->white},
                                      {"converted_to_rec709", !sameChromaticities(*c, kRec709)}};
    else
      j["declared_chromaticities"] = nullptr;
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
    if (local) {
      const LocalEnvironmentTable& t = *local->localTable();
      j["local"] = {{"normal_rows", t.options().normalRows},
                    {"normal_columns", t.options().normalColumns},
                    {"block_size", t.options().blockSize},
                    {"bytes", t.bytes()},
                    {"dense_bytes", t.denseBytes()},
                    {"slices_built", t.slicesBuilt()},
                    {"build_ms", localBuildMs},
                    {"variance", localCost.variance},
                    {"ns_per_sample", localCost.nsPerSample},
                    {"efficiency", localCost.efficiency},
                    {"stratified_variance", *localCost.stratifiedVariance},
                    {"adaptive_variance_ratio", adaptiveVariance / localCost.variance}};
    }
    std::puts(j.dump(2).c_str());
  } else {
    std::string out;
    out += fmt::format("input              {} ({} x {})\n", args.input, map->width(), map->height());
    out += "chromaticities     " + chromaticitiesText(map->declaredChromaticities()) + "\n";
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
        kEstimator.normals, kEstimator.samplesPerNormal, kEstimator.strata, kEstimator.strata);
    out += fmt::format("{:<18} {:>14} {:>14} {:>14} {:>14}\n", "strategy", "variance", "ns/sample", "efficiency",
                       "stratified");
    for (const Named& s : strategies)
      out += fmt::format("{:<18} {:>14.6g} {:>14.1f} {:>14.4g} {:>14}\n", s.name, s.cost.variance, s.cost.nsPerSample,
                         s.cost.efficiency,
                         s.cost.stratifiedVariance ? fmt::format("{:.6g}", *s.cost.stratifiedVariance) : "-");
    if (local) {
      const LocalEnvironmentTable& t = *local->localTable();
      out += fmt::format("{:<18} {:>14.6g} {:>14.1f} {:>14.4g} {:>14.6g}\n", "local", localCost.variance,
                         localCost.nsPerSample, localCost.efficiency, *localCost.stratifiedVariance);
      out += fmt::format(
          "\nlocal sampling     {} x {} normal cells, blocks of {} x {} pixels: {} slices in {:.1f} ms, {} bytes\n"
          "                   ({:.1f}x smaller than the dense 4D table's {} bytes); irradiance variance\n"
          "                   {:.3g}x lower than adaptive's\n",
          t.options().normalRows, t.options().normalColumns, t.options().blockSize, t.options().blockSize,
          t.slicesBuilt(), localBuildMs, t.bytes(), static_cast<double>(t.denseBytes()) / t.bytes(), t.denseBytes(),
          adaptiveVariance / localCost.variance);
    }
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
      "FILE: an equirectangular environment map, OpenEXR or (built with OpenImageIO) any image it reads\n"
      "(subimage 0, MIP level 0; +Y up, see README). Negative channels are clamped to 0 and counted;\n"
      "NaN/Inf is an error unless --sanitize.\n"
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
      "--local: local sampling (the map x max(0, n.w), LocalEnvironmentTable) for each estimator normal's own\n"
      "cell of a --normal-res grid over 16 x 16-pixel blocks, every slice built (build_ms, in parallel);\n"
      "bytes: its tables (not the adaptive one its light keeps for calls without a normal); dense_bytes: a\n"
      "uniform float table per normal cell (computed, not allocated); adaptive_variance_ratio: adaptive's\n"
      "irradiance variance over local's.\n"
      "\n"
      "Exit status: 0 success, 2 bad input file (also a black map) or command line, 1 internal error.",
      kEstimator.normals, kEstimator.samplesPerNormal, kEstimator.seed, kEstimator.stratifiedTrials(),
      kEstimator.strata, kEstimator.strata));
  app->add_option("FILE", args->input, "Environment map (OpenEXR, or any image OpenImageIO reads)")->required();
  app->add_option("--epsilon", args->epsilon, "Largest CDF error the adaptive simplifier leaves (>= 0)")
      ->capture_default_str();
  app->add_flag("--sanitize", args->sanitize, "Replace NaN/Inf channel values with 0 (and count them)");
  app->add_flag("--json", args->json, "Print one JSON object instead of the table");
  CLI::Option* local =
      app->add_flag("--local", args->local, "Also local sampling: a table per normal cell (the map x max(0, n.w))");
  app->add_option("--normal-res", args->normalRes, "--local: normal cells ROWS,COLUMNS in theta, phi (default 32,64)")
      ->delimiter(',')
      ->needs(local);
  return Command{app, [args] { return runEnvmapStats(*args); }};
}

}  // namespace acdf::app

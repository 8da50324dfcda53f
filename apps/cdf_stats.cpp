#include "cdf_stats.h"

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/grid_axis.h"
#include "acdf/sampling/quality.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/sampling/simplify.h"
#include "errors.h"
#include "input.h"
#include "options.h"

namespace acdf::app {

namespace {

constexpr std::size_t kTimingSamples = 1'000'000;

struct CdfStatsArgs {
  std::string input;
  double epsilon = SimplifyOptions{}.epsilon;
  uint32_t maxPoints = 0;
  double weightBound = SimplifyOptions{}.weightBound;
  std::string simplifier;  // "" (not given), "douglas-peucker" or "greedy"
  std::string metric = "vertical";
  uint64_t samples = 1'000'000;
  uint64_t seed = 1;
  bool json = false;

  CLI::Option* maxPointsOption = nullptr;
};

// The flags as engine options; throws UsageError on combinations that make no sense.
SimplifyOptions simplifyOptions(const CdfStatsArgs& args) {
  SimplifyOptions o;
  const bool budget = args.maxPointsOption->count() > 0;
  if (budget && !args.simplifier.empty() && parseSimplifier(args.simplifier) == Simplifier::DouglasPeucker)
    throw UsageError(
        "--max-points needs the greedy simplifier; it cannot be combined with --simplifier douglas-peucker");
  o.method = budget || (!args.simplifier.empty() && parseSimplifier(args.simplifier) == Simplifier::GreedyRefinement)
                 ? Simplifier::GreedyRefinement
                 : Simplifier::DouglasPeucker;
  o.metric = parseErrorMetric(args.metric);
  o.epsilon = args.epsilon;
  o.maxPoints = budget ? args.maxPoints : 0;
  o.weightBound = args.weightBound;
  validateFlags(o);
  return o;
}

// Defeats dead-code elimination of the timed loops.
volatile float g_sink = 0;

struct Cost {
  double buildMs = 0;
  double nsPerSample = 0;
  double nsPerPdf = 0;
  std::size_t bytes = 0;
};

// Times `dist.sample(u)` over the pre-drawn variates and `dist.pdf(x)` over the points sampled.
template <class Distribution>
void timeSampling(const Distribution& dist, std::span<const float> variates, std::size_t dims, Cost& cost) {
  const std::size_t n = variates.size() / dims;
  std::vector<float> points(n * dims);
  // Untimed pass: records the points for the pdf loop and warms the caches.
  for (std::size_t i = 0; i < n; ++i) {
    const SampleND s = dist.sample(variates.subspan(i * dims, dims));
    for (std::size_t d = 0; d < dims; ++d) points[i * dims + d] = s.x[d];
  }

  float acc = 0;
  auto start = Clock::now();
  for (std::size_t i = 0; i < n; ++i) acc += dist.sample(variates.subspan(i * dims, dims)).pdf;
  double ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count();
  g_sink = g_sink + acc;
  cost.nsPerSample = ns / static_cast<double>(n);

  const std::span<const float> pointSpan(points);
  acc = 0;
  start = Clock::now();
  for (std::size_t i = 0; i < n; ++i) acc += dist.pdf(pointSpan.subspan(i * dims, dims));
  ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count();
  g_sink = g_sink + acc;
  cost.nsPerPdf = ns / static_cast<double>(n);
}

// Engine constructor failures that survive the checks done before are still the input's fault
// (e.g. a shape the engine cannot hold); report them against the file.
template <class Build>
auto buildFor(const std::string& path, Build&& build) {
  try {
    return build();
  } catch (const std::invalid_argument& e) {
    throw FileError(path, e.what());
  } catch (const std::length_error& e) {
    throw FileError(path, e.what());
  }
}

struct Report {
  const InputGrid* grid = nullptr;
  std::size_t cells = 0;
  Cost uniform, alias, adaptive;
  std::vector<std::size_t> points;
  std::vector<double> averageIntervals;
  CompressionQuality quality;
  std::optional<ChiSquareResult> chi2;
  SimplifyOptions options;
  const CdfStatsArgs* args = nullptr;
  bool uniformFallback = false;
};

// Keys in the documented order (ordered_json keeps insertion order).
nlohmann::ordered_json toJson(const Report& r) {
  using json = nlohmann::ordered_json;
  auto perDistribution = [&](double Cost::*member) {
    return json{{"uniform", r.uniform.*member}, {"alias", r.alias.*member}, {"adaptive", r.adaptive.*member}};
  };
  json j;
  j["input"] = r.grid->path;
  j["input_kind"] = kindName(r.grid->kind);
  j["dims"] = r.grid->dims;
  j["cells"] = r.cells;
  j["uniform_bytes"] = r.uniform.bytes;
  j["alias_bytes"] = r.alias.bytes;
  j["adaptive_bytes"] = r.adaptive.bytes;
  j["compression"] = static_cast<double>(r.uniform.bytes) / static_cast<double>(r.adaptive.bytes);
  j["points"] = r.points;
  j["average_intervals"] = r.averageIntervals;
  j["chi2_divergence"] = r.quality.chi2Divergence;
  j["max_weight_ratio"] = r.quality.maxWeightRatio;
  j["unreachable_mass"] = r.quality.unreachableMass;
  if (r.chi2) {
    j["chi2_test_pvalue"] = r.chi2->pvalue;
    j["chi2_test"] = json{{"statistic", r.chi2->statistic},
                          {"dof", r.chi2->dof},
                          {"pooled_cells", r.chi2->pooledCells},
                          {"samples", r.args->samples},
                          {"seed", r.args->seed}};
  } else {
    j["chi2_test_pvalue"] = nullptr;
    j["chi2_test"] = nullptr;
  }
  j["ns_per_sample"] = perDistribution(&Cost::nsPerSample);
  j["ns_per_pdf"] = perDistribution(&Cost::nsPerPdf);
  j["build_ms"] = perDistribution(&Cost::buildMs);
  j["options"] = json{{"epsilon", r.options.epsilon},
                      {"max_points", r.options.maxPoints},
                      {"weight_bound", r.options.weightBound},
                      {"simplifier", std::string(toString(r.options.method))},
                      {"metric", std::string(toString(r.options.metric))},
                      {"samples", r.args->samples},
                      {"seed", r.args->seed}};
  j["negative_values_clamped"] = r.grid->negativeClamped;
  j["negative_channel_pixels"] = r.grid->negativeChannelPixels;
  j["uniform_fallback"] = r.uniformFallback;
  return j;
}

void printTable(const Report& r) {
  const InputGrid& g = *r.grid;
  std::string out;
  auto line = [&out](const std::string& s) {
    out += s;
    out += '\n';
  };
  line(fmt::format("input              {} ({}, {} cells, axes [0,1) each)", g.path, fmt::join(g.dims, " x "), r.cells));
  if (g.kind == InputGrid::Kind::Image)
    line(fmt::format("negative clamped   {} pixel luminances set to 0 ({} pixels have a negative channel)",
                     g.negativeClamped, g.negativeChannelPixels));
  if (r.uniformFallback) line("uniform fallback   yes: the input is all zero, every distribution is uniform");
  line(fmt::format("options            epsilon {:g}, simplifier {}, metric {}, weight bound {:g}, max points {}",
                   r.options.epsilon, toString(r.options.method), toString(r.options.metric), r.options.weightBound,
                   r.options.maxPoints == 0 ? std::string("none") : std::to_string(r.options.maxPoints)));
  line("");
  line(fmt::format("{:<18} {:>14} {:>14} {:>14}", "", "uniform", "alias", "adaptive"));
  line(fmt::format("{:<18} {:>14} {:>14} {:>14}", "bytes", r.uniform.bytes, r.alias.bytes, r.adaptive.bytes));
  line(fmt::format("{:<18} {:>14.2f} {:>14.2f} {:>14.2f}", "build ms", r.uniform.buildMs, r.alias.buildMs,
                   r.adaptive.buildMs));
  line(fmt::format("{:<18} {:>14.1f} {:>14.1f} {:>14.1f}", "ns per sample", r.uniform.nsPerSample, r.alias.nsPerSample,
                   r.adaptive.nsPerSample));
  line(fmt::format("{:<18} {:>14.1f} {:>14.1f} {:>14.1f}", "ns per pdf", r.uniform.nsPerPdf, r.alias.nsPerPdf,
                   r.adaptive.nsPerPdf));
  line("");
  line(fmt::format("compression        {:.2f}x (uniform bytes / adaptive bytes)",
                   static_cast<double>(r.uniform.bytes) / static_cast<double>(r.adaptive.bytes)));
  line(fmt::format("points             [{}] (kept CDF points per axis, summed over its 1D CDFs)",
                   fmt::join(r.points, ", ")));
  line(fmt::format("average intervals  [{:.2f}]", fmt::join(r.averageIntervals, ", ")));
  line(fmt::format("chi2 divergence    {:.6g} (variance added by the compression; 0 = exact)",
                   r.quality.chi2Divergence));
  line(fmt::format("max weight ratio   {:.6g} (largest p_exact / p_adaptive over cells)", r.quality.maxWeightRatio));
  line(fmt::format("unreachable mass   {:.6g}", r.quality.unreachableMass));
  if (r.chi2)
    line(fmt::format("chi2 test          p = {:.4g} (statistic {:.6g}, {} dof, {} samples, seed {})", r.chi2->pvalue,
                     r.chi2->statistic, r.chi2->dof, r.args->samples, r.args->seed));
  else
    line("chi2 test          skipped (--samples 0)");
  std::fputs(out.c_str(), stdout);
}

int runCdfStats(const CdfStatsArgs& args) {
  Report report;
  report.args = &args;
  report.options = simplifyOptions(args);

  const InputGrid grid = readInputGrid(args.input);
  report.grid = &grid;
  const std::vector<GridAxis> axes = unitAxes(grid);
  checkValues(grid, axes);
  const std::size_t dims = axes.size();
  report.cells = grid.values.size();

  // Build the three distributions.
  CascadeOptions uniformOptions;
  uniformOptions.methods.assign(dims, DimensionMethod::Uniform);
  auto start = Clock::now();
  const Cascade uniform = buildFor(grid.path, [&] { return Cascade(grid.values, axes, uniformOptions); });
  report.uniform.buildMs = millisecondsSince(start);

  start = Clock::now();
  const AliasGrid alias = buildFor(grid.path, [&] { return AliasGrid(grid.values, axes); });
  report.alias.buildMs = millisecondsSince(start);

  CascadeOptions adaptiveOptions;
  adaptiveOptions.simplify = report.options;
  start = Clock::now();
  const Cascade adaptive = buildFor(grid.path, [&] { return Cascade(grid.values, axes, adaptiveOptions); });
  report.adaptive.buildMs = millisecondsSince(start);

  report.uniform.bytes = uniform.bytes();
  report.alias.bytes = alias.bytes();
  report.adaptive.bytes = adaptive.bytes();
  report.points = adaptive.pointsPerDimension();
  report.averageIntervals = adaptive.averageIntervals();
  report.uniformFallback = adaptive.isUniformFallback(0);

  // Accuracy: exact cell probabilities against the adaptive cascade's. An all-zero input has no
  // distribution of its own; the engine samples it uniformly, so that is the reference.
  std::vector<double> adaptiveCells = adaptive.cellProbabilities(0);
  {
    std::vector<double> exact(grid.values.size());
    double total = 0;
    for (float v : grid.values) total += v;
    if (total > 0) {
      for (std::size_t i = 0; i < exact.size(); ++i) exact[i] = grid.values[i] / total;
    } else {
      std::fill(exact.begin(), exact.end(), 1.0 / static_cast<double>(exact.size()));
    }
    report.quality = compareCellProbabilities(exact, adaptiveCells);
  }

  // Chi-square goodness of fit of the adaptive sampler against its own cell probabilities.
  if (args.samples > 0) {
    std::vector<double> observed(grid.values.size(), 0.0);
    Pcg32 rng(args.seed);
    std::vector<float> u(dims);
    for (uint64_t n = 0; n < args.samples; ++n) {
      for (auto& v : u) v = rng.nextFloat();
      const SampleND s = adaptive.sample(u);
      std::size_t cell = 0;
      for (std::size_t d = 0; d < dims; ++d) cell = cell * axes[d].cells() + axes[d].cellOf(s.x[d]);
      observed[cell] += 1;
    }
    for (double& p : adaptiveCells) p *= static_cast<double>(args.samples);  // now the expected counts
    report.chi2 = chiSquareTest(observed, adaptiveCells);
  }
  adaptiveCells = {};

  // Sampling cost: the same pre-drawn variates for every distribution.
  {
    std::vector<float> variates(kTimingSamples * dims);
    Pcg32 rng(args.seed, 0x5bd1e995u);
    for (float& v : variates) v = rng.nextFloat();
    timeSampling(uniform, variates, dims, report.uniform);
    timeSampling(alias, variates, dims, report.alias);
    timeSampling(adaptive, variates, dims, report.adaptive);
  }

  if (args.json) {
    const std::string text = toJson(report).dump(2);
    std::fputs(text.c_str(), stdout);
    std::fputc('\n', stdout);
  } else {
    printTable(report);
  }
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command addCdfStats(CLI::App& parent) {
  auto args = std::make_shared<CdfStatsArgs>();
  CLI::App* app = parent.add_subcommand(
      "cdf-stats",
      "Build the uniform, alias and adaptive distributions of a tabulated function and report their "
      "size, build time, sampling and pdf cost, and the adaptive one's accuracy.");
  app->footer(
      "INPUT is a .npy array (float32 '<f4' or float64 '<f8', 1 to 4 dimensions, C order; values must be\n"
      "finite and >= 0) or an image (OpenEXR; other formats where built with OpenImageIO), used as a\n"
      "height x width grid of luminance 0.2126 R + 0.7152 G + 0.0722 B (one-channel images: that\n"
      "channel; subimage 0, MIP level 0; negative luminances are clamped to 0 and counted, NaN/Inf is\n"
      "an error).\n"
      "Every axis spans [0,1) with one grid cell per array entry / pixel (no spherical mapping).\n"
      "\n"
      "Distributions: uniform = cascade of full-resolution 1D CDFs; alias = one alias table over all\n"
      "cells; adaptive = cascade of simplified 1D CDFs (--epsilon, --simplifier, --metric, --max-points,\n"
      "--weight-bound). chi2_divergence / max_weight_ratio compare the adaptive cell probabilities with\n"
      "the exact ones (value / sum); chi2_test_pvalue is a chi-square goodness-of-fit test of the adaptive\n"
      "sampler against its own pdf with --samples samples. Timings use 1e6 pre-drawn variates.\n"
      "\n"
      "Exit status: 0 success, 2 bad input file or command line, 1 internal error.");

  app->add_option("INPUT", args->input, "Input .npy array or image file")->required();
  app->add_option("--epsilon", args->epsilon, "Largest CDF error the simplifier leaves (>= 0)")->capture_default_str();
  args->maxPointsOption =
      app->add_option("--max-points", args->maxPoints, "Point budget per 1D CDF (>= 2); implies --simplifier greedy")
          ->transform(nonNegativeInteger());
  app->add_option("--weight-bound", args->weightBound,
                  "Weight bound rho: no grid cell gets less than 1/rho of its exact probability, so sample\n"
                  "weights stay within rho of the uniform table's (0 = off, else >= 1)")
      ->capture_default_str();
  app->add_option("--simplifier", args->simplifier,
                  "Curve simplifier: douglas-peucker (default) or greedy (global refinement)")
      ->check(CLI::IsMember(std::vector<std::string>{std::string(toString(Simplifier::DouglasPeucker)),
                                                     std::string(toString(Simplifier::GreedyRefinement))}));
  app->add_option("--metric", args->metric,
                  "Simplification error metric: vertical, perpendicular or chi-square (each interval's\n"
                  "contribution to the chi2 divergence; its epsilon is in divergence, e.g. 1e-4)")
      ->check(CLI::IsMember(std::vector<std::string>{std::string(toString(ErrorMetric::Vertical)),
                                                     std::string(toString(ErrorMetric::Perpendicular)),
                                                     std::string(toString(ErrorMetric::ChiSquare))}))
      ->capture_default_str();
  app->add_option("--samples", args->samples,
                  "Samples for the chi-square test of the adaptive sampler (0 skips the test)")
      ->transform(nonNegativeInteger())
      ->capture_default_str();
  app->add_option("--seed", args->seed, "Seed of the chi-square test and timing variates")
      ->transform(nonNegativeInteger())
      ->capture_default_str();
  app->add_flag("--json", args->json, "Print one JSON object instead of the table");

  return Command{app, [args] { return runCdfStats(*args); }};
}

}  // namespace acdf::app

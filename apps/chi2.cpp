#include "chi2.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/brdf/brdf_chi_square.h"
#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/brdf_sampler_factory.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/light_chi_square.h"
#include "acdf/sampling/sphere_chi_square.h"
#include "brdf_stats.h"
#include "errors.h"
#include "image.h"
#include "options.h"

namespace acdf::app {

namespace {

constexpr double kAlpha = 0.01;

struct Chi2Args {
  // The mode: exactly one kind of sampler is tested (mutually exclusive options).
  std::string envmap;
  std::string brdf;
  std::string sampler;
  double thetaOutDegrees = 0;  // --brdf: the outgoing direction's θo (φo = 0)
  std::vector<double> normal;  // --envmap --sampler local: the surface normal (map frame)
  BrdfTableArgs table;         // --brdf: the tabulated samplers' table
  uint64_t samples = 1'000'000;
  uint64_t seed = 1;
  bool sanitize = false;
  bool json = false;
};

// --envmap FILE: the environment light's sampler (lat-long map, +Y up) with strategy --sampler.
SphereChiSquareReport testEnvmap(const Chi2Args& args) {
  EnvironmentLightOptions options;
  try {
    options.strategy = parseEnvironmentSampling(args.sampler);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("chi2 --envmap: ") + e.what());
  }
  LightChiSquareOptions test{.samples = args.samples, .seed = args.seed, .alpha = kAlpha};
  const bool local = !tableStrategyOf(options.strategy);
  if (local != !args.normal.empty())
    throw UsageError(local ? "chi2 --envmap --sampler " + args.sampler +
                                 ": give the surface normal with --normal X,Y,Z"
                           : "chi2 --envmap: --normal applies to the local strategies only");
  if (local) {
    const Vec3d n{args.normal.size() == 3 ? args.normal[0] : 0, args.normal.size() == 3 ? args.normal[1] : 0,
                  args.normal.size() == 3 ? args.normal[2] : 0};
    if (!(dot(n, n) > 0) || !std::isfinite(dot(n, n)))
      throw UsageError("chi2 --envmap: --normal takes three finite numbers X,Y,Z, not all 0");
    test.context.normal = normalize(n);
  }
  const auto map = readEnvironmentMap(args.envmap, args.sanitize);
  if (map->isBlack()) throw FileError(args.envmap, "the map is black everywhere: nothing to sample");
  const EnvironmentLight light(map, options);
  return lightChiSquareTest(light, test);
}

// --brdf FILE --theta-o DEG: the BRDF sampler --sampler (cosine, or the table brdf-stats builds
// from the same flags) for ωo = (θo, φo = 0).
SphereChiSquareReport testBrdf(const Chi2Args& args) {
  const BrdfSampling sampling = parseOption("chi2 --brdf", "--sampler", args.sampler, parseBrdfSampling);
  if (!(args.thetaOutDegrees >= 0 && args.thetaOutDegrees < 90))
    throw UsageError(fmt::format("chi2 --brdf: --theta-o must be in [0, 90) degrees, got {}", args.thetaOutDegrees));
  // Flag errors before the slow part (reading the file, tabulating).
  const TabulatedBrdfOptions table = brdfTableOptions(args.table, DimensionMethod::Uniform);
  const std::shared_ptr<const BrdfModel> brdf = loadMeasuredBrdf(args.brdf, args.table);
  std::shared_ptr<const BrdfSampler> sampler;
  try {
    sampler = makeBrdfSampler(brdf, sampling, table);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("chi2 --brdf: --sampler {}: {}", args.sampler, e.what()));
  }
  const Vec3d wo = sphericalDirection(args.thetaOutDegrees * std::numbers::pi / 180.0, 0.0);
  // Expected counts integrated in the sampler's own half-vector cells (brdf_chi_square.h), with
  // the tests' resolution: 32 × 64 equal-area bins, 32² sub-cells per table cell.
  SphereChiSquareOptions options;
  options.samples = args.samples;
  options.seed = args.seed;
  options.thetaBins = 32;
  options.phiBins = 64;
  options.subPoints = 32;
  options.alpha = kAlpha;
  return brdfChiSquareTest(*sampler, wo, options);
}

int runChi2(const Chi2Args& args, const CLI::Option& thetaOut) {
  if (args.envmap.empty() && args.brdf.empty())
    throw UsageError("chi2: give the sampler to test with --envmap FILE or --brdf FILE");
  if (!args.brdf.empty() && thetaOut.count() == 0)
    throw UsageError("chi2 --brdf: give the outgoing direction with --theta-o DEG");
  if (args.samples == 0) throw UsageError("chi2: --samples must be >= 1");
  const SphereChiSquareReport report = args.brdf.empty() ? testEnvmap(args) : testBrdf(args);
  const bool passed = report.passed();
  if (args.json) {
    nlohmann::ordered_json j;
    j["pvalue"] = report.chi2.pvalue;
    j["passed"] = passed;
    j["samples"] = report.samples;
    j["dof"] = report.chi2.dof;
    std::puts(j.dump(2).c_str());
  } else {
    std::printf("%s: p = %.4g (statistic %.6g, %u dof, %llu samples, alpha %g)%s\n", passed ? "passed" : "FAILED",
                report.chi2.pvalue, report.chi2.statistic, report.chi2.dof,
                static_cast<unsigned long long>(report.samples), kAlpha,
                report.samplesValid() ? "" : fmt::format("; invalid samples: {}", report.firstProblem).c_str());
  }
  if (std::fflush(stdout) != 0) return 1;
  return passed ? 0 : 1;
}

}  // namespace

Command addChi2(CLI::App& parent) {
  auto args = std::make_shared<Chi2Args>();
  CLI::App* app = parent.add_subcommand(
      "chi2", "Chi-square goodness-of-fit test of a sampler against its own pdf (exit 0 pass, 1 fail).");
  app->footer(fmt::format(
      "--envmap FILE --sampler {}: the\n"
      "environment light of FILE (a lat-long map: OpenEXR, or any image OpenImageIO reads) sampled with that\n"
      "strategy (compensated: its own table, the one MIS uses; local and local-compensated: for the surface\n"
      "normal --normal X,Y,Z, in the map's frame, +Y up). "
      "Directions are histogrammed on (theta, phi) bins aligned to blocks of pixels\n"
      "(at most 10000 bins); expected counts integrate the light's pdf\n"
      "over each bin exactly. Pools of expected count >= 5, level alpha = {:g}. Every sample is also checked (unit\n"
      "direction, finite positive pdf equal to pdf(direction)); passed needs both.\n"
      "\n"
      "--brdf FILE --theta-o DEG --sampler cosine|uniform|adaptive|rgl: a measured BRDF's (MERL .binary or RGL\n"
      ".bsdf, told apart by content; rgl: the .bsdf file's own warps) sampler of incident\n"
      "directions for the outgoing direction (theta_o = DEG, phi_o = 0): cosine-weighted, or the uniform or\n"
      "adaptive tabulated CDF that brdf-stats builds from the same --table, --res, --chi2-epsilon and\n"
      "--interpolation. 32 x 64 equal-area bins over the sphere; each bin's expected count integrates the\n"
      "sampler's half-vector density over its own table cells (32 x 32 jittered sub-cells each, reflected\n"
      "to the incident direction) and the cosine part in closed form.\n"
      "\n"
      "Exit status: 0 the test passes, 1 it fails (or an internal error), 2 bad input file or command line.",
      environmentSamplingNames("|"), kAlpha));
  CLI::Option* envmap = app->add_option("--envmap", args->envmap, "Environment map to test");
  CLI::Option* brdf =
      app->add_option("--brdf", args->brdf, "Measured BRDF to test (MERL .binary or RGL .bsdf)")->excludes(envmap);
  CLI::Option* thetaOut =
      app->add_option("--theta-o", args->thetaOutDegrees, "--brdf: outgoing theta in degrees, in [0, 90)")->needs(brdf);
  for (CLI::Option* option : addBrdfTableOptions(*app, args->table)) option->needs(brdf);
  app->add_option("--normal", args->normal, "--envmap --sampler local: the surface normal X,Y,Z (map frame)")
      ->delimiter(',')
      ->needs(envmap);
  app->add_option("--sampler", args->sampler, "Sampling strategy (see below)")->required();
  app->add_option("--samples", args->samples, "Number of samples (>= 1)")
      ->transform(nonNegativeInteger())
      ->capture_default_str();
  app->add_option("--seed", args->seed, "Seed of the variates")->transform(nonNegativeInteger())->capture_default_str();
  app->add_flag("--sanitize", args->sanitize, "Replace NaN/Inf channel values with 0 instead of failing")
      ->excludes(brdf);
  app->add_flag("--json", args->json, "Print one JSON object (pvalue, passed, samples, dof)");
  return Command{app, [args, thetaOut] { return runChi2(*args, *thetaOut); }};
}

}  // namespace acdf::app

#include "chi2.h"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/light_chi_square.h"
#include "errors.h"
#include "image.h"
#include "options.h"

namespace acdf::app {

namespace {

constexpr double kAlpha = 0.01;

struct Chi2Args {
  // The mode: exactly one kind of sampler is tested (mutually exclusive options).
  std::string envmap;
  std::string sampler;
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
  const auto map = readEnvironmentMap(args.envmap, args.sanitize);
  if (map->isBlack()) throw InputError(args.envmap, "the map is black everywhere: nothing to sample");
  const EnvironmentLight light(map, options);
  return lightChiSquareTest(light, {.samples = args.samples, .seed = args.seed, .alpha = kAlpha});
}

int runChi2(const Chi2Args& args) {
  if (args.envmap.empty()) throw UsageError("chi2: give the sampler to test with --envmap FILE");
  if (args.samples == 0) throw UsageError("chi2: --samples must be >= 1");
  const SphereChiSquareReport report = testEnvmap(args);
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
      "--envmap FILE --sampler uniform|alias|adaptive|compensated: the environment light of FILE (a lat-long\n"
      "map OpenImageIO reads) sampled with that strategy. Directions are histogrammed on (theta, phi) bins\n"
      "aligned to blocks of pixels (at most 10000 bins); expected counts integrate the light's pdf over each\n"
      "bin exactly. Pools of expected count >= 5, level alpha = {:g}. Every sample is also checked (unit\n"
      "direction, finite positive pdf equal to pdf(direction)); passed needs both.\n"
      "\n"
      "Exit status: 0 the test passes, 1 it fails (or an internal error), 2 bad input file or command line.",
      kAlpha));
  app->add_option("--envmap", args->envmap, "Environment map to test");
  app->add_option("--sampler", args->sampler, "Sampling strategy (see below)")->required();
  app->add_option("--samples", args->samples, "Number of samples (>= 1)")
      ->transform(nonNegativeInteger())
      ->capture_default_str();
  app->add_option("--seed", args->seed, "Seed of the variates")->transform(nonNegativeInteger())->capture_default_str();
  app->add_flag("--sanitize", args->sanitize, "Replace NaN/Inf channel values with 0 instead of failing");
  app->add_flag("--json", args->json, "Print one JSON object (pvalue, passed, samples, dof)");
  return Command{app, [args] { return runChi2(*args); }};
}

}  // namespace acdf::app

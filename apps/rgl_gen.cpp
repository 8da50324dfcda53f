#include "rgl_gen.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/rgl_synthesis.h"
#include "errors.h"

namespace acdf::app {

namespace {

struct RglGenArgs {
  std::string preset;
  std::string output;
  RglSynthesisOptions options;
};

int runRglGen(const RglGenArgs& args) {
  if (args.output.empty()) throw UsageError("rgl-gen: give the output file with -o OUT.bsdf");
  const auto start = std::chrono::steady_clock::now();
  TensorFile file;
  try {
    file = synthesizeRgl(AnalyticBrdf::preset(args.preset), args.options, "acdf rgl-gen preset " + args.preset);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("rgl-gen: ") + e.what());
  }
  file.save(args.output);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const RglSynthesisOptions& o = args.options;
  std::printf("%s: preset '%s', %u theta_i, vndf %u x %u, %s %u x %u, ndf %u, %.2f s\n", args.output.c_str(),
              args.preset.c_str(), o.thetaIn, o.vndf, o.vndf, o.spectral ? "spectra" : "rgb", o.reflectance,
              o.reflectance, o.ndf, seconds);
  return 0;
}

}  // namespace

Command addRglGen(CLI::App& parent) {
  auto args = std::make_shared<RglGenArgs>();
  CLI::App* app = parent.add_subcommand(
      "rgl-gen", "Write an RGL .bsdf file (Dupuy & Jakob 2018) of an analytic GGX preset, in the paper's tables.");
  std::string presets;
  for (const std::string& name : AnalyticBrdf::presetNames())
    presets += "  " + name + ": " + AnalyticBrdf::presetDescription(name) + "\n";
  app->footer(
      "Tables (rows over phi, columns over theta on u = sqrt(theta / (pi/2))): ndf and sigma (GGX's D and\n"
      "projected area, 2 x --ndf vertices), the visible-NDF warp (--vndf^2 vertices per theta_i), and the\n"
      "reflectance rho = f 4 sigma cos(theta_i) / D with its luminance warp (--reflectance^2 vertices) at the\n"
      "points the visible-NDF warp maps its vertices to; --theta-i incident angles 0 to 90 deg, jacobian = 1.\n"
      "With --spectral, grey spectra (the luminance of rho at 360..830 nm) replace rgb. The defaults are the\n"
      "real RGL files' resolution; `--theta-i 3 --vndf 16 --reflectance 8 --ndf 16` makes a 5 KiB file.\n"
      "Written to a temporary file and renamed into place: a failure leaves no partial file.\n"
      "\n"
      "Presets:\n" +
      presets +
      "\n"
      "Exit status: 0 success, 2 bad output file or command line, 1 internal error.");
  app->add_option("--preset", args->preset, "Analytic preset (see below)")
      ->required()
      ->check(CLI::IsMember(AnalyticBrdf::presetNames()));
  app->add_option("-o,--output", args->output, "Output .bsdf file");
  app->add_option("--theta-i", args->options.thetaIn, "Incident angles tabulated")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  app->add_option("--vndf", args->options.vndf, "Vertices per axis of the visible-NDF warp")
      ->check(CLI::Range(2u, 4096u))
      ->capture_default_str();
  app->add_option("--reflectance", args->options.reflectance, "Vertices per axis of the rgb and luminance tables")
      ->check(CLI::Range(2u, 4096u))
      ->capture_default_str();
  app->add_option("--ndf", args->options.ndf, "Vertices along theta of the ndf and sigma tables")
      ->check(CLI::Range(2u, 65536u))
      ->capture_default_str();
  app->add_flag("--spectral", args->options.spectral, "Write spectra + wavelengths instead of rgb");
  return Command{app, [args] { return runRglGen(*args); }};
}

}  // namespace acdf::app

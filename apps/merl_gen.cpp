#include "merl_gen.h"

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/nbrdf.h"
#include "errors.h"
#include "files.h"

#ifndef ACDF_NBRDF_WEIGHTS
#error "ACDF_NBRDF_WEIGHTS (the bundled data/merl-nbrdf/merl_nbrdf_weights.json) must be defined"
#endif

namespace acdf::app {

namespace {

struct MerlGenArgs {
  std::string material;
  std::string preset;
  std::string weights = bundledFile("merl_nbrdf_weights.json", ACDF_NBRDF_WEIGHTS);
  std::string output;
  bool list = false;
};

int runMerlGen(const MerlGenArgs& args) {
  if (args.list) {
    if (!args.material.empty() || !args.preset.empty() || !args.output.empty())
      throw UsageError("merl-gen: --list cannot be combined with --nbrdf, --preset or -o");
    for (const std::string& name : NeuralBrdf::materials(args.weights)) std::printf("%s\n", name.c_str());
    return 0;
  }
  if (!args.material.empty() && !args.preset.empty())
    throw UsageError("merl-gen: give either --nbrdf MATERIAL or --preset NAME, not both");
  if (args.material.empty() && args.preset.empty())
    throw UsageError("merl-gen: give --nbrdf MATERIAL or --preset NAME (or --list)");
  if (args.output.empty()) throw UsageError("merl-gen: give the output file with -o OUT.binary");

  const auto start = std::chrono::steady_clock::now();
  std::vector<double> table;
  std::string what;
  if (!args.preset.empty()) {
    try {
      table = AnalyticBrdf::preset(args.preset).merlTable();
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("merl-gen: ") + e.what());
    }
    what = "preset '" + args.preset + "'";
  } else {
    table = NeuralBrdf::load(args.weights, args.material).merlTable();
    what = "neural fit of '" + args.material + "'";
  }
  std::size_t below = 0;
  for (std::size_t i = 0; i < MerlBrdf::kCells; ++i) below += table[i] == -1.0;
  MerlBrdf::saveRaw(args.output, table);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: %s, %zu cells (%zu below the horizon, -1), %.2f s\n", args.output.c_str(), what.c_str(),
              MerlBrdf::kCells, below, seconds);
  return 0;
}

}  // namespace

Command addMerlGen(CLI::App& parent) {
  auto args = std::make_shared<MerlGenArgs>();
  CLI::App* app = parent.add_subcommand(
      "merl-gen", "Write a MERL-format .binary BRDF table generated from a neural fit of a MERL material.");
  std::string presets;
  for (const std::string& name : AnalyticBrdf::presetNames())
    presets += "  " + name + ": " + AnalyticBrdf::presetDescription(name) + "\n";
  app->footer(
      "The neural fits (Sztrajman et al., \"Neural BRDF Representation and Importance Sampling\", CGF 2021,\n"
      "MIT licence) of the 100 MERL materials are bundled in data/merl-nbrdf/. The table is evaluated at\n"
      "MERL's cell coordinates theta_h = (i/90)^2 pi/2, theta_d = j/90 pi/2, phi_d = k/180 pi and written in\n"
      "MERL's layout (int32 90 90 180, then R, G, B float64 blocks divided by the channel scales 1/1500,\n"
      "1.15/1500, 1.66/1500); cells with either direction below the horizon hold -1, as in measured files.\n"
      "Same values as the fits' reference script (nbrdf_to_merl.py). The output is written to a temporary file\n"
      "and renamed into place: a failure leaves no partial file.\n"
      "\n"
      "Analytic presets (--preset NAME), tabulated the same way; GGX distribution, Smith separable\n"
      "shadowing, Schlick Fresnel at cos theta_d; coated: + (1 - F(theta_i))(1 - F(theta_o)) albedo/pi:\n" +
      presets +
      "\n"
      "Exit status: 0 success, 2 bad input file, output file or command line, 1 internal error.");
  app->add_option("--nbrdf", args->material, "MERL material whose neural fit to tabulate (see --list)");
  app->add_option("--preset", args->preset, "Analytic preset to tabulate instead (see the list below)");
  app->add_option("--weights", args->weights, "Neural BRDF weights file (JSON)")->capture_default_str();
  app->add_option("-o,--output", args->output, "Output .binary file");
  app->add_flag("--list", args->list, "List the materials in the weights file and exit");
  return Command{app, [args] { return runMerlGen(*args); }};
}

}  // namespace acdf::app

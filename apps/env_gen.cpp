#include "env_gen.h"

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "acdf/envmap/image_file.h"
#include "acdf/envmap/sun_sky.h"
#include "errors.h"
#include "options.h"

namespace acdf::app {

namespace {

struct EnvGenArgs {
  std::string preset = "noon";
  uint32_t width = 1024;
  std::optional<uint32_t> height;  // default: width / 2
  std::optional<double> sunElevation, sunAzimuth, sunRadius, sunIntensity;
  std::string output;
};

std::string describe(const SunSkyParameters& p) {
  if (p.sunIntensity == 0 || p.sunRadiusDeg == 0)
    return fmt::format("no sun; zenith ({:g}, {:g}, {:g}), horizon ({:g}, {:g}, {:g})", p.zenith.r, p.zenith.g,
                       p.zenith.b, p.horizon.r, p.horizon.g, p.horizon.b);
  return fmt::format(
      "sun {:g} deg high at azimuth {:g} deg, radius {:g} deg, intensity {:g} x colour ({:g}, {:g}, "
      "{:g}); zenith ({:g}, {:g}, {:g}), horizon ({:g}, {:g}, {:g})",
      p.sunElevationDeg, p.sunAzimuthDeg, p.sunRadiusDeg, p.sunIntensity, p.sunColor.r, p.sunColor.g, p.sunColor.b,
      p.zenith.r, p.zenith.g, p.zenith.b, p.horizon.r, p.horizon.g, p.horizon.b);
}

int runEnvGen(const EnvGenArgs& args) {
  SunSkyParameters p;
  try {
    p = sunSkyPreset(args.preset);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("env-gen: ") + e.what());
  }
  if (args.sunElevation) p.sunElevationDeg = *args.sunElevation;
  if (args.sunAzimuth) p.sunAzimuthDeg = *args.sunAzimuth;
  if (args.sunRadius) p.sunRadiusDeg = *args.sunRadius;
  if (args.sunIntensity) p.sunIntensity = *args.sunIntensity;
  const uint32_t height = args.height.value_or(args.width / 2);
  if (args.width == 0 || height == 0) throw UsageError("env-gen: --width and --height must be >= 1");

  const auto start = Clock::now();
  Image image;
  try {
    image = sunSkyImage(args.width, height, p);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("env-gen: ") + e.what());
  }
  writeExr(args.output, image);
  std::printf("%s: %u x %u sun and sky (%s), %.0f ms\n", args.output.c_str(), args.width, height, describe(p).c_str(),
              millisecondsSince(start));
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command addEnvGen(CLI::App& parent) {
  auto args = std::make_shared<EnvGenArgs>();
  CLI::App* app = parent.add_subcommand(
      "env-gen", "Write a procedural sun-and-sky environment map (lat-long, +Y up) as a float OpenEXR file.");
  std::string presets;
  for (const std::string& name : sunSkyPresetNames())
    presets += "  " + name + ": " + describe(sunSkyPreset(name)) + "\n";
  app->footer(
      "The map is equirectangular: row 0 is the zenith (+Y), column 0 looks along -Z, azimuth (phi) grows\n"
      "to the right, through +X at 90 degrees (OpenEXR's LatLong layout). Sky: horizon + (zenith - horizon)\n"
      "* cos(theta)^gradient plus a glow around the sun; ground: a constant colour; sun: a disk of the given\n"
      "angular radius, its pixels supersampled so that a sun smaller than a pixel covers the right fraction of it.\n"
      "The --sun-* options override the preset's values. Written to a temporary file renamed into place:\n"
      "a failure leaves no partial file.\n"
      "\n"
      "Presets:\n" +
      presets +
      "\n"
      "Exit status: 0 success, 2 bad output file or command line, 1 internal error.");
  app->add_option("-o,--output", args->output, "Output .exr file")->required();
  app->add_option("--preset", args->preset, "Preset (see below)")->capture_default_str();
  app->add_option("--width", args->width, "Width in pixels")->capture_default_str();
  app->add_option("--height", args->height, "Height in pixels (default: width / 2)");
  app->add_option("--sun-elevation", args->sunElevation, "Sun elevation above the horizon, degrees [-90, 90]");
  app->add_option("--sun-azimuth", args->sunAzimuth, "Sun azimuth phi, degrees (0: the left edge, -Z; 90: +X)");
  app->add_option("--sun-radius", args->sunRadius, "Sun angular radius, degrees (0: no sun)");
  app->add_option("--sun-intensity", args->sunIntensity, "Sun radiance as a multiple of its colour (0: no sun)");
  return Command{app, [args] { return runEnvGen(*args); }};
}

}  // namespace acdf::app

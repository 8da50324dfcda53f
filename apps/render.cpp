#include "render.h"

#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/integrator/renderer.h"
#include "acdf/integrator/scene.h"
#include "errors.h"
#include "options.h"
#include "scene_cli.h"

namespace acdf::app {

namespace {

namespace fs = std::filesystem;

struct RenderArgs {
  std::string scene;
  std::string output;
  std::string png;  // default: the output with .png
  bool noPng = false;
  std::optional<uint32_t> spp;
  std::optional<double> seconds;
  std::optional<uint64_t> seed;
  std::string mis, sampler, bsdfSampling, envSampling, direct, guiding, portals, lightPaths;
  std::optional<uint32_t> candidates;
  std::string branches;
  std::vector<uint32_t> crop;
  uint32_t threads = 0;
  bool noCache = false;
  bool json = false;
};

int runRender(const RenderArgs& args) {
  SceneOverrides overrides;
  if (!args.mis.empty()) overrides.mis = parseOption("render", "--mis", args.mis, parseMisMode);
  if (!args.direct.empty()) overrides.direct = parseOption("render", "--direct", args.direct, parseDirectLighting);
  if (args.candidates) {
    try {
      validate(ProductSamplingOptions{.candidates = *args.candidates});
    } catch (const OptionError& e) {
      throw UsageError("render: --candidates " + e.problem());
    }
    overrides.candidates = args.candidates;
  }
  if (!args.branches.empty()) overrides.branches = parseOption("render", "--branches", args.branches, parseBranches);
  if (!args.guiding.empty()) overrides.guiding = parseOption("render", "--guiding", args.guiding, parseGuidingMode);
  if (!args.portals.empty()) overrides.portals = parseOption("render", "--portals", args.portals, parsePortalSource);
  if (!args.lightPaths.empty())
    overrides.lightPaths = parseOption("render", "--light-paths", args.lightPaths, parseLightPathMode);
  if (!args.sampler.empty()) overrides.sampler = parseOption("render", "--sampler", args.sampler, parseSamplerKind);
  if (!args.bsdfSampling.empty())
    overrides.bsdfSampling = parseOption("render", "--bsdf-sampling", args.bsdfSampling, parseBrdfSampling);
  if (!args.envSampling.empty())
    overrides.envSampling = parseOption("render", "--env-sampling", args.envSampling, parseEnvironmentSampling);
  overrides.spp = args.spp;
  overrides.seed = args.seed;
  if (!args.crop.empty()) {
    if (args.crop.size() != 4) throw UsageError("render: --crop takes x0,y0,x1,y1");
    overrides.crop = CropWindow{args.crop[0], args.crop[1], args.crop[2], args.crop[3]};
  }
  if (args.seconds && !(*args.seconds > 0)) throw UsageError("render: --time must be positive");

  const std::string png = args.noPng          ? ""
                          : !args.png.empty() ? args.png
                                              : fs::path(args.output).replace_extension(".png").string();
  checkOutputPath(args.output);
  if (!png.empty()) checkOutputPath(png);

  std::optional<tbb::global_control> threads;
  if (args.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, args.threads);

  const auto setupStart = Clock::now();
  SceneAssets tables(commandTableCache(args.noCache));
  const Scene scene = loadScene(args.scene, overrides, tables);
  const double setupMs = millisecondsSince(setupStart);

  Film film = makeFilm(scene);
  const RenderStats stats = renderWithProgress(scene, film, args.seconds);

  film.write(args.output, png);

  const double samplesPerSecond = stats.seconds > 0 ? stats.paths / stats.seconds : 0.0;
  const double raysPerSecond = stats.seconds > 0 ? stats.rays / stats.seconds : 0.0;
  if (args.json) {
    nlohmann::ordered_json j;
    j["scene"] = args.scene;
    j["width"] = film.width();
    j["height"] = film.height();
    j["spp"] = stats.spp;
    j["seconds"] = stats.seconds;
    j["setup_ms"] = setupMs;
    j["samples_per_second"] = samplesPerSecond;
    j["rays_per_second"] = raysPerSecond;
    j["rays"] = stats.rays;
    j["mis"] = toString(scene.settings.mis);
    j["branches"] = branchesName(scene.settings.branches);
    j["branched"] = stats.branching.branches;
    if (stats.branching.raysBefore) {
      j["rays_before_branching"] = *stats.branching.raysBefore;
      j["rays_per_branch"] = *stats.branching.raysAfter;
      if (stats.branching.varianceBefore) j["variance_before_branching"] = *stats.branching.varianceBefore;
      if (stats.branching.varianceAfter) j["variance_per_branch"] = *stats.branching.varianceAfter;
    }
    j["direct"] = toString(scene.settings.direct);
    if (scene.settings.direct == DirectLighting::Product) {
      j["candidates"] = scene.settings.product.candidates;
      j["bsdf_fraction"] = scene.settings.product.bsdfFraction;
    }
    j["guiding"] = toString(scene.settings.guiding);
    if (scene.settings.guiding != GuidingMode::Off) {
      const GuidingStats& g = stats.guiding;
      j["guided"] = g.guided;
      j["guiding_training_passes"] = g.trainingPasses;
      j["guiding_gain"] = g.measuredGain ? nlohmann::json(*g.measuredGain) : nlohmann::json();
      j["guiding_spatial_leaves"] = g.spatialLeaves;
      j["guiding_field_bytes"] = g.fieldBytes;
      j["guiding_field_seconds"] = g.fieldSeconds;
    }
    j["portals"] = toString(scene.settings.portals);
    j["portal_count"] = scene.environment->options().portals.size();
    j["light_paths"] = toString(scene.settings.lightPaths);
    j["connects_light_paths"] = stats.connectsLightPaths;
    j["light_path_gain"] = stats.lightPathGain ? nlohmann::json(*stats.lightPathGain) : nlohmann::json();
    if (scene.openingSearch) {
      j["escaped_share"] = scene.openingSearch->escapedShare();
      j["found_portals"] = nlohmann::json::array();
      for (const Portal& p : scene.openingSearch->openings)
        j["found_portals"].push_back({{"corner", {p.corner.x, p.corner.y, p.corner.z}},
                                      {"edge_u", {p.edgeU.x, p.edgeU.y, p.edgeU.z}},
                                      {"edge_v", {p.edgeV.x, p.edgeV.y, p.edgeV.z}}});
    }
    j["sampler"] = toString(scene.settings.sampler);
    j["env_sampling"] = toString(scene.environment->options().strategy);
    j["tables_built"] = tables.tablesBuilt();
    j["tables_from_cache"] = tables.tablesFromCache();
    j["exr"] = args.output;
    j["png"] = png.empty() ? nlohmann::json() : nlohmann::json(png);
    std::puts(j.dump(2).c_str());
  } else {
    std::string out;
    out += fmt::format("rendered  {} ({} x {}, {} spp) in {:.2f} s, set-up {:.0f} ms\n", args.scene, film.width(),
                       film.height(), stats.spp, stats.seconds, setupMs);
    out += fmt::format("speed     {:.3g} samples/s, {:.3g} rays/s\n", samplesPerSecond, raysPerSecond);
    constexpr double unmeasured = std::numeric_limits<double>::quiet_NaN();
    if (const BranchingStats& b = stats.branching; b.branches > 1 || b.raysBefore)
      out += fmt::format("branches  {} per camera sample from its first vertex on{}\n", b.branches,
                         b.raysBefore ? fmt::format(" (auto: {:.2f} rays per camera sample before, {:.2f} per branch;"
                                                    " relative variance {:.3g} before, {:.3g} per branch)",
                                                    *b.raysBefore, *b.raysAfter, b.varianceBefore.value_or(unmeasured),
                                                    b.varianceAfter.value_or(unmeasured))
                                      : "");
    if (scene.settings.guiding != GuidingMode::Off) {
      const GuidingStats& g = stats.guiding;
      out += fmt::format("guiding   {} ({}){}: {} training passes, last fields {} leaves, {:.0f} kB, built in {:.2f}"
                         " s\n",
                         g.guided ? "on" : "off", toString(scene.settings.guiding),
                         g.measuredGain ? fmt::format(", measured gain {:.2f} (needs {:.2f})", *g.measuredGain,
                                                      kAutoGuidingGain)
                                        : "",
                         g.trainingPasses, g.spatialLeaves, g.fieldBytes / 1e3, g.fieldSeconds);
    }
    if (const auto& search = scene.openingSearch) {
      out += fmt::format("portals   {} found: {:.1f} % of {} directions from {} visible points leave the scene{}\n",
                         search->openings.size(), 100.0 * search->escapedShare(), search->rays, search->points,
                         search->escapedShare() >= kMaxEscapedShare
                             ? fmt::format(" (an enclosure needs < {:.0f} %)", 100.0 * kMaxEscapedShare)
                             : "");
      // As a scene file declares them: to keep, or to give a renderer that cannot look (Mitsuba).
      for (const Portal& p : search->openings)
        out += fmt::format("          {{\"corner\": [{:.4g}, {:.4g}, {:.4g}], \"edge_u\": [{:.4g}, {:.4g}, {:.4g}], "
                           "\"edge_v\": [{:.4g}, {:.4g}, {:.4g}]}}\n",
                           p.corner.x, p.corner.y, p.corner.z, p.edgeU.x, p.edgeU.y, p.edgeU.z, p.edgeV.x, p.edgeV.y,
                           p.edgeV.z);
    }
    out += fmt::format("tables    {} built, {} from the cache\n", tables.tablesBuilt().size(),
                       tables.tablesFromCache().size());
    for (const std::string& t : tables.tablesBuilt()) out += fmt::format("          built       {}\n", t);
    for (const std::string& t : tables.tablesFromCache()) out += fmt::format("          from cache  {}\n", t);
    out += fmt::format("wrote     {}{}\n", args.output, png.empty() ? "" : " and " + png);
    std::fputs(out.c_str(), stdout);
  }
  return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace

Command addRender(CLI::App& parent) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* app =
      parent.add_subcommand("render", "Render a scene with the MIS path tracer (measured BRDFs, environment light).");
  app->footer(
      "SCENE: a JSON scene file (docs/scene-format.md). The strategy options replace the scene's choices:\n"
      "  --bsdf-sampling  cosine | uniform | adaptive | rgl    (every measured material)\n"
      "  --env-sampling   " + environmentSamplingNames(" | ") + "\n"
      "  --mis            power | balance | bsdf-only | light-only\n"
      "  --direct         mis | product  (product: resampled f·L·cos, --candidates M of them)\n"
      "  --branches       auto | N  (paths per camera sample from its first vertex on; 1: plain path\n"
      "                   tracing; auto: the N its first samples measure pays)\n"
      "  --sampler        independent | sobol  (Owen-scrambled Sobol, per-pixel deterministic)\n"
      "  --guiding        off | light | paths | auto  (learned in doubling passes: the light each place\n"
      "                   sees; paths: also the radiance paths carry; auto: light where it pays)\n"
      "  --portals        auto | declared | none  (auto: the scene's portals, or where it declares none\n"
      "                   the openings found by tracing from what the camera sees)\n"
      "  --light-paths    auto | on | off  (where the light has portals, every vertex connects to a light\n"
      "                   path entering through them; auto: where the first 8 samples measure that it\n"
      "                   pays; not under guiding, product direct lighting or one-technique MIS)\n"
      "Outputs: a linear float EXR and an sRGB PNG preview (clamped, no tone mapping), each written to a\n"
      "temporary file and renamed. A progress bar is drawn on a terminal only.\n"
      "Sampling tables are cached in $XDG_CACHE_HOME/acdf (else ~/.cache/acdf; docs/table-cache.md):\n"
      "a corrupt or stale file is rebuilt with a warning; --no-cache bypasses the cache.\n"
      "--json keys: seconds, setup_ms, spp, samples_per_second, rays_per_second, tables_built,\n"
      "tables_from_cache, exr, png (and scene, width, height, rays, mis, branches, branched, direct,\n"
      "guiding, portals, portal_count, light_paths, connects_light_paths, sampler, env_sampling; rays_before_branching, rays_per_branch,\n"
      "variance_before_branching and variance_per_branch under auto branching; escaped_share and\n"
      "found_portals, in the scene file's form, when openings were looked for; candidates and\n"
      "bsdf_fraction under product direct lighting;\n"
      "guided, guiding_training_passes, guiding_gain, guiding_spatial_leaves, guiding_field_bytes and\n"
      "guiding_field_seconds unless guiding is off).\n"
      "\n"
      "Exit status: 0 success, 2 bad scene / data file / output path or command line, 1 internal error.");
  app->add_option("SCENE", args->scene, "Scene file (JSON)")->required();
  app->add_option("-o,--output", args->output, "Output image (linear float OpenEXR)")->required();
  app->add_option("--png", args->png, "sRGB PNG preview (default: the output with .png)");
  app->add_flag("--no-png", args->noPng, "Write no PNG preview");
  auto* spp =
      app->add_option("--spp", args->spp, "Samples per pixel (replaces the scene's)")->check(CLI::Range(1u, 1u << 30));
  app->add_option("--time", args->seconds, "Render progressive passes for this many seconds instead")->excludes(spp);
  app->add_option("--seed", args->seed, "Random seed (replaces the scene's)");
  app->add_option("--mis", args->mis, "power | balance | bsdf-only | light-only");
  app->add_option("--direct", args->direct, "mis | product (direct lighting technique)");
  app->add_option("--candidates", args->candidates, "Product sampling's candidates per vertex (replaces the scene's)")
      ->transform(nonNegativeInteger());
  app->add_option("--branches", args->branches, "auto | N (paths per camera sample from its first vertex on)");
  app->add_option("--sampler", args->sampler, "independent | sobol (the sample source)");
  app->add_option("--guiding", args->guiding, "off | light | paths | auto (guiding learned as it renders)");
  app->add_option("--portals", args->portals, "auto | declared | none (the environment's portals)");
  app->add_option("--light-paths", args->lightPaths, "auto | on | off (connections to light paths through the portals)");
  app->add_option("--bsdf-sampling", args->bsdfSampling, "cosine | uniform | adaptive | rgl");
  app->add_option("--env-sampling", args->envSampling, environmentSamplingNames(" | "));
  app->add_option("--crop", args->crop, "Render only pixels x0,y0,x1,y1 of the frame (x1, y1 exclusive)")
      ->delimiter(',');
  app->add_option("--threads", args->threads, "Worker threads (0 = all cores)");
  app->add_flag("--no-cache", args->noCache, "Neither read nor store tables in the table cache");
  app->add_flag("--json", args->json, "Print a JSON summary");
  return Command{app, [args] { return runRender(*args); }};
}

}  // namespace acdf::app

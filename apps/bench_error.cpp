#include "bench_error.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "acdf/experiments/error_benchmark.h"
#include "errors.h"
#include "files.h"
#include "options.h"
#include "scene_cli.h"

#ifndef ACDF_BENCH_ERROR_SCRIPT
#define ACDF_BENCH_ERROR_SCRIPT "bench/error_report.py"
#endif

namespace acdf::app {

namespace {

namespace fs = std::filesystem;

// Exit status when every row is in results.csv / results.json but the plots could not be drawn.
constexpr int kExitPlotFailed = 3;
struct BenchErrorArgs {
  std::string scene, reference, out = "bench-error";
  std::vector<double> budgets;  // seconds
  std::vector<uint32_t> sppBudgets;
  std::vector<std::string> bsdf, env, mis, samplers, direct;
  uint32_t referenceSpp = 1024;
  double targetRelMse = 0;  // 0: the least relMSE of any strategy at the smallest budget
  uint32_t seeds = 4;
  std::string shard;               // "K/N", empty: every row
  std::vector<std::string> merge;  // shard output directories to join
  uint32_t threads = 0;
  bool noCache = false, noPlot = false;
  std::string plotScript = bundledFile("error_report.py", ACDF_BENCH_ERROR_SCRIPT), python = "/usr/bin/python3";
};

// The names parsed, repeats dropped (none given: empty, i.e. every strategy).
template <class T, class Parse>
std::vector<T> parseList(const std::vector<std::string>& names, const std::string& option, Parse parse) {
  std::vector<T> out;
  for (const std::string& name : names) {
    const T value = parseOption("bench-error", option, name, parse);
    if (std::find(out.begin(), out.end(), value) == out.end()) out.push_back(value);
  }
  return out;
}

// Runs `python script plot results.json DIR`; returns an empty string on success, else why not.
std::string runPlotScript(const BenchErrorArgs& args, const fs::path& dir) {
  const std::string results = (dir / "results.json").string(), out = dir.string();
  std::vector<const char*> argv = {
      args.python.c_str(), args.plotScript.c_str(), "plot", results.c_str(), out.c_str(), nullptr};
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) return "cannot start a process";
  if (pid == 0) {
    execv(argv[0], const_cast<char* const*>(argv.data()));
    std::fprintf(stderr, "acdf: cannot run %s\n", args.python.c_str());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return "cannot wait for the plot script";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) return "cannot run " + args.python;
  return WIFEXITED(status)
             ? fmt::format("{} {} exited with status {}", args.python, args.plotScript, WEXITSTATUS(status))
             : fmt::format("{} {} was killed by signal {}", args.python, args.plotScript, WTERMSIG(status));
}

// The summary's last lines and the plots, for a run and a merge alike.
int finish(const BenchErrorArgs& args, std::string summary, std::size_t differenceImages) {
  const fs::path dir = args.out;
  summary += fmt::format("wrote       {}, {}, {} difference images in {}\n", (dir / "results.csv").string(),
                         (dir / "results.json").string(), differenceImages, (dir / "diff").string());
  std::fputs(summary.c_str(), stdout);
  if (args.noPlot) return std::fflush(stdout) == 0 ? 0 : 1;
  const std::string plotProblem = runPlotScript(args, dir);
  if (!plotProblem.empty()) {
    std::fprintf(stderr, "acdf: bench-error: plotting failed (%s); results.csv and results.json in %s are complete\n",
                 oneLine(plotProblem).c_str(), dir.string().c_str());
    return kExitPlotFailed;
  }
  std::printf("plots       %s, %s\n", (dir / "error_vs_time.png").c_str(), (dir / "memory_vs_error.png").c_str());
  return std::fflush(stdout) == 0 ? 0 : 1;
}

int merge(const BenchErrorArgs& args) {
  if (!args.scene.empty()) throw UsageError("bench-error: --merge takes shard directories, not SCENE");
  if (!args.shard.empty()) throw UsageError("bench-error: --merge and --shard exclude each other");
  const std::vector<fs::path> shards(args.merge.begin(), args.merge.end());
  const ErrorBenchmarkReport report = mergeErrorBenchmark(shards, args.out, args.targetRelMse);
  return finish(
      args,
      fmt::format("bench-error --merge: {} shards of {}, {} rows\n", report.shardsMerged, report.scene, report.rows),
      report.differenceImages);
}

int run(const BenchErrorArgs& args) {
  if (!args.merge.empty()) return merge(args);
  if (args.scene.empty()) throw UsageError("bench-error: SCENE is required (or --merge DIR...)");
  ErrorBenchmarkOptions options;
  options.scene = args.scene;
  options.reference = args.reference;
  options.out = args.out;
  options.sppBudgets = !args.sppBudgets.empty();
  options.budgets = args.budgets;
  if (options.sppBudgets) options.budgets.assign(args.sppBudgets.begin(), args.sppBudgets.end());
  options.bsdf = parseList<BrdfSampling>(args.bsdf, "--bsdf-sampling", parseBrdfSampling);
  options.env = parseList<EnvironmentSampling>(args.env, "--env-sampling", parseEnvironmentSampling);
  options.mis = parseList<MisMode>(args.mis, "--mis", parseMisMode);
  options.direct = parseList<DirectLighting>(args.direct, "--direct", parseDirectLighting);
  options.samplers = parseList<SamplerKind>(args.samplers, "--sampler", parseSamplerKind);
  options.referenceSpp = args.referenceSpp;
  options.seeds = args.seeds;
  options.threads = args.threads;
  options.targetRelMse = args.targetRelMse;
  if (!args.shard.empty()) options.shard = parseErrorBenchmarkShard(args.shard);
  options.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  options.render = renderWithProgress;
  validateFlags(options, "bench-error: ");

  const ErrorBenchmarkReport report = runErrorBenchmark(options, commandTableCache(args.noCache));
  std::string summary =
      fmt::format("bench-error {}: {} strategy combinations x {} budgets ({}), {} left out as identical\n", args.scene,
                  report.strategies, report.budgets, options.sppBudgets ? "spp" : "seconds", report.skipped.size());
  for (const SkippedStrategy& s : report.skipped)
    summary += fmt::format("  left out  {}: {}\n", s.strategy.label(), s.reason);
  if (options.shard)
    summary += fmt::format("shard       {}: the rows of index % {} == {}\n", args.shard, options.shard->n,
                           options.shard->k - 1);
  summary += fmt::format("reference   {} ({})\n", report.reference, report.referenceOrigin);
  summary += fmt::format("rows        {} rendered, {} kept from an earlier run\n", report.rendered, report.kept);
  return finish(args, summary, report.differenceImages);
}

}  // namespace

Command addBenchError(CLI::App& parent) {
  auto args = std::make_shared<BenchErrorArgs>();
  CLI::App* app = parent.add_subcommand(
      "bench-error", "Error against render time for every sampling strategy combination, against a reference.");
  app->footer(
      "Renders SCENE with every combination of the strategy lists (default: all of them) for every budget,\n"
      "--seeds times, and measures the error against a reference: relMSE = mean over pixels and channels of\n"
      "(I - R)^2 / (R^2 + 0.01), RMSE = sqrt(mean of (I - R)^2), and the firefly-robust relmse_trimmed =\n"
      "relMSE after discarding the 0.1% of pixels of largest error. A row reports the means over its seeds,\n"
      "their standard errors (*_stderr) and efficiency = 1 / (relMSE x seconds) with its delta-method error.\n"
      "Seed k of a row is a hash of the scene's seed, the strategy, the budget and k. The tables are built\n"
      "(or read from the table cache) before the timed render; their set-up time and memory are reported per row.\n"
      "A combination is BRDF sampling x environment sampling x direct lighting (--direct mis,product; default\n"
      "mis; product takes the scene's render.candidates and bsdf_fraction) x MIS mode x sample source\n"
      "(--sampler). Combinations that render the same image as another are left out and listed: bsdf-only\n"
      "with any but the first --env-sampling, product with any but the first --mis, and BRDF strategies\n"
      "other than the first when no material is measured.\n"
      "Reference: --reference REF.exr (same resolution as the scene), else DIR/reference.exr, rendered at\n"
      "--reference-spp with the scene's own strategies and reused while DIR/reference.json matches.\n"
      "Per strategy, curves.csv (and results.json's curves) give the render time to reach --target-relmse,\n"
      "interpolated log-log between budgets, else extrapolated by relMSE ~ 1/time (flagged).\n"
      "DIR gets results.csv and results.json (rewritten after every row: a stopped run resumes, skipping\n"
      "finished rows, when the scene, reference, budget kind, threads and seeds are the same), images/ (the\n"
      "first seed's renders of the largest budget), diff/ (false colour: red where a render differs from the\n"
      "reference, and where the adaptive table's render differs from the uniform table's), and the plots\n"
      "of --plot-script.\n"
      "--shard K/N renders only the rows of index % N == K - 1 (numbered strategy-major, then budget);\n"
      "--merge DIR... joins shard outputs, checked to come from one run (scene, reference, budgets, seeds,\n"
      "strategies, threads), into --out as an unsharded run writes them (scripts/bench-error-parallel).\n"
      "\n"
      "Exit status: 0 success, 2 bad scene / reference / output directory or command line, 3 the plots\n"
      "failed (the results are complete), 1 internal error.");
  app->add_option("SCENE", args->scene, "Scene file (JSON); not with --merge");
  app->add_option("--reference", args->reference, "Reference image (linear EXR of the scene's resolution)");
  app->add_option("--reference-spp", args->referenceSpp, "Samples per pixel of a rendered reference")
      ->check(CLI::Range(1u, 1u << 20));
  auto* budgets = app->add_option("--budgets", args->budgets, "Render-time budgets in seconds (default 1,2,4,8,16)")
                      ->delimiter(',');
  app->add_option("--spp-budgets", args->sppBudgets, "Sample-count budgets instead (deterministic)")
      ->delimiter(',')
      ->check(CLI::Range(1u, 1u << 20))
      ->excludes(budgets);
  app->add_option("--target-relmse", args->targetRelMse,
                  "relMSE for the time-to-target figures (default: the least of any strategy at the smallest budget)")
      ->check(CLI::PositiveNumber);
  app->add_option("--seeds", args->seeds, "Independent renders per row (default 4)")->check(CLI::Range(1u, 1000u));
  app->add_option("--shard", args->shard, "K/N: render only the rows of index % N == K - 1 (1 <= K <= N)");
  app->add_option("--merge", args->merge, "Join these shard output directories into --out, then plot")->expected(1, -1);
  app->add_option("-o,--out", args->out, "Output directory (default bench-error)");
  app->add_option("--bsdf-sampling", args->bsdf, "BRDF strategies, e.g. uniform,adaptive (default: all)")
      ->delimiter(',');
  app->add_option("--env-sampling", args->env, "Environment strategies (default: all)")->delimiter(',');
  app->add_option("--mis", args->mis, "MIS modes, e.g. power,bsdf-only (default: all)")->delimiter(',');
  app->add_option("--direct", args->direct, "Direct lighting, e.g. mis,product (default: mis)")->delimiter(',');
  app->add_option("--sampler", args->samplers, "Sample sources, e.g. independent,sobol (default: the scene's)")
      ->delimiter(',');
  app->add_option("--threads", args->threads, "Worker threads (0 = all cores)");
  app->add_flag("--no-cache", args->noCache, "Neither read nor store tables in the table cache");
  app->add_flag("--no-plot", args->noPlot, "Do not run the plot script");
  app->add_option("--plot-script", args->plotScript,
                  "The plot script (default: the one installed beside the program, else the source tree's)")
      ->capture_default_str();
  app->add_option("--python", args->python, "Python with matplotlib (default /usr/bin/python3)");
  return Command{app, [args] {
                   try {
                     return run(*args);
                   } catch (const OptionError& e) {
                     throw UsageError("bench-error: " + flagError(e));
                   }
                 }};
}

}  // namespace acdf::app

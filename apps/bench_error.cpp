#include "bench_error.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "acdf/envmap/image_file.h"
#include "acdf/integrator/render_error.h"
#include "acdf/integrator/renderer.h"
#include "acdf/integrator/scene.h"
#include "acdf/integrator/strategy_plan.h"
#include "acdf/sampling/table_cache.h"
#include "acdf/sampling/write_atomically.h"
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
using Json = nlohmann::ordered_json;

// Exit status when every row is in results.csv / results.json but the plots could not be drawn.
constexpr int kExitPlotFailed = 3;
struct BenchErrorArgs {
  std::string scene, reference, out = "bench-error";
  std::vector<double> budgets;  // seconds
  std::vector<uint32_t> sppBudgets;
  std::vector<std::string> bsdf, env, mis, samplers;
  uint32_t referenceSpp = 1024;
  double targetRelMse = 0;  // 0: the least relMSE of any strategy at the smallest budget
  uint32_t seeds = 4;
  std::string shard;               // "K/N", empty: every row
  std::vector<std::string> merge;  // shard output directories to join
  uint32_t threads = 0;
  bool noCache = false, noPlot = false;
  std::string plotScript = ACDF_BENCH_ERROR_SCRIPT, python = "/usr/bin/python3";
};

std::string hexHash(const ContentHash& hash) { return hash.digest().hex(); }

std::string readText(const std::string& path) {
  const std::vector<unsigned char> bytes = readFileBytes(path);
  return std::string(bytes.begin(), bytes.end());
}

std::optional<Json> readJsonFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  std::ifstream in(path);
  Json j = Json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  return j;
}

void writeImage(const std::string& path, const Image& image, bool png) {
  png ? writeSrgbPng(path, image) : writeExr(path, image);
}

template <class T, class Parse>
std::vector<T> parseList(const std::vector<std::string>& names, const std::string& option, Parse parse,
                         std::vector<T> all) {
  if (names.empty()) return all;
  std::vector<T> out;
  for (const std::string& name : names) {
    const T value = parseOption("bench-error", option, name, parse);
    if (std::find(out.begin(), out.end(), value) == out.end()) out.push_back(value);
  }
  return out;
}

// A results row's strategy; none if a name is missing or unknown.
std::optional<Strategy> strategyOf(const Json& row) {
  try {
    return Strategy{parseBrdfSampling(row.value("bsdf_sampling", "")),
                    parseEnvironmentSampling(row.value("env_sampling", "")), parseMisMode(row.value("mis", "")),
                    parseSamplerKind(row.value("sampler", ""))};
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
}

// The strategy's four names, as rows, curves and skipped entries carry them (strategyOf reads them).
Json strategyJson(const Strategy& s) {
  return {{"bsdf_sampling", toString(s.bsdf)},
          {"env_sampling", toString(s.env)},
          {"mis", toString(s.mis)},
          {"sampler", toString(s.sampler)}};
}

// Row key for resuming: the strategy and the budget.
std::string rowKey(const Strategy& s, double budget) { return fmt::format("{}|{:a}", s.id(), budget); }
std::optional<std::string> rowKey(const Json& row) {
  const std::optional<Strategy> s = strategyOf(row);
  if (!s || !row.contains("budget") || !row["budget"].is_number()) return std::nullopt;
  return rowKey(*s, row["budget"].get<double>());
}

const char* const kCsvColumns[] = {"bsdf_sampling",
                                   "env_sampling",
                                   "mis",
                                   "sampler",
                                   "budget_kind",
                                   "budget",
                                   "seeds",
                                   "seconds",
                                   "seconds_stderr",
                                   "spp",
                                   "relmse",
                                   "relmse_stderr",
                                   "relmse_trimmed",
                                   "relmse_trimmed_stderr",
                                   "rmse",
                                   "rmse_stderr",
                                   "efficiency",
                                   "efficiency_stderr",
                                   "brdf_table_bytes",
                                   "env_table_bytes",
                                   "table_bytes",
                                   "table_ms",
                                   "tables_built",
                                   "tables_from_cache"};

std::string csvCell(const Json& v) {
  if (v.is_string()) return v.get<std::string>();  // strategy names: no commas or quotes
  if (v.is_number_float()) return fmt::format("{:.9g}", v.get<double>());
  return v.dump();
}

std::string toCsv(const Json& rows) {
  std::string out;
  for (const char* c : kCsvColumns) out += std::string(out.empty() ? "" : ",") + c;
  out += "\n";
  for (const Json& row : rows) {
    std::string line;
    for (const char* c : kCsvColumns) line += std::string(line.empty() ? "" : ",") + csvCell(row.at(c));
    out += line + "\n";
  }
  return out;
}

// The relMSE the time-to-target figures aim at: the one given, else the least any strategy
// reached at the smallest budget (so the best strategy needs that budget, the others longer).
double targetRelMse(const Json& rows, double given) {
  if (given > 0 || rows.empty()) return given;
  double smallest = std::numeric_limits<double>::infinity(), target = 0;
  for (const Json& row : rows) smallest = std::min(smallest, row.value("budget", 0.0));
  for (const Json& row : rows)
    if (row.value("budget", 0.0) == smallest && row.value("relmse", 0.0) > 0)
      target = target > 0 ? std::min(target, row.value("relmse", 0.0)) : row.value("relmse", 0.0);
  return target;
}

// Per strategy, the render time to reach `target` along its rows (timeToReach).
Json curves(const Json& rows, double target) {
  std::map<std::string, std::pair<Strategy, std::vector<ErrorAtTime>>> byStrategy;
  for (const Json& row : rows) {
    const Strategy s = *strategyOf(row);
    auto& [strategy, points] = byStrategy.try_emplace(s.id(), s, std::vector<ErrorAtTime>{}).first->second;
    points.push_back({row.value("seconds", 0.0), {row.value("relmse", 0.0), row.value("relmse_stderr", 0.0)}});
  }
  Json out = Json::array();
  for (auto& [id, entry] : byStrategy) {
    auto& [s, points] = entry;
    std::sort(points.begin(), points.end(),
              [](const ErrorAtTime& a, const ErrorAtTime& b) { return a.seconds < b.seconds; });
    const TimeToTarget t = timeToReach(points, target);
    Json curve = strategyJson(s);
    curve.update(Json{{"time_to_target", std::isfinite(t.seconds) ? Json(t.seconds) : Json()},
                      {"time_to_target_stderr", std::isfinite(t.standardError) ? Json(t.standardError) : Json()},
                      {"time_to_target_extrapolated", t.extrapolated}});
    out.push_back(std::move(curve));
  }
  return out;
}

std::string curvesCsv(const Json& curves) {
  std::string out = "bsdf_sampling,env_sampling,mis,sampler,time_to_target,time_to_target_stderr,extrapolated\n";
  for (const Json& c : curves)
    out += fmt::format("{},{},{},{},{},{},{}\n", c["bsdf_sampling"].get<std::string>(),
                       c["env_sampling"].get<std::string>(), c["mis"].get<std::string>(),
                       c["sampler"].get<std::string>(), csvCell(c["time_to_target"]),
                       csvCell(c["time_to_target_stderr"]), c["time_to_target_extrapolated"].get<bool>() ? 1 : 0);
  return out;
}

// DIR/results.csv, DIR/curves.csv and DIR/results.json, each replaced atomically.
void writeResultFiles(const fs::path& dir, const Json& settings, const Json& skipped, const Json& rows,
                      double givenTarget) {
  const double target = targetRelMse(rows, givenTarget);
  Json j{{"settings", settings},
         {"skipped", skipped},
         {"target_relmse", target},
         {"target_relmse_rule",
          givenTarget > 0 ? "given (--target-relmse)" : "the least relmse of any strategy at the smallest budget"},
         {"time_to_target",
          "render seconds to reach target_relmse: interpolated log-log between the budgets around it, else "
          "extrapolated from the nearest end by relmse ~ 1/seconds; stderr from the budgets' relmse stderr"},
         {"curves", curves(rows, target)},
         {"rows", rows}};
  writeFileAtomically((dir / "results.csv").string(), toCsv(rows));
  writeFileAtomically((dir / "curves.csv").string(), curvesCsv(j["curves"]));
  writeFileAtomically((dir / "results.json").string(), j.dump(2) + "\n");
}

// "K/N" with 1 <= K <= N: this shard renders the rows of index % N == K - 1.
struct Shard {
  uint32_t k = 1, n = 1;
  bool has(std::size_t row) const { return row % n == k - 1; }
};

Shard parseShard(const std::string& text) {
  unsigned k = 0, n = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%u/%u%c", &k, &n, &rest) != 2 ||
      text.find_first_not_of("0123456789/") != std::string::npos || n < 1 || k < 1 || k > n)
    throw UsageError(fmt::format("bench-error: --shard: '{}' is not K/N with 1 <= K <= N", text));
  return {k, n};
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

class BenchError {
 public:
  explicit BenchError(const BenchErrorArgs& args) : args_(args), dir_(args.out) {}

  int run() {
    if (!args_.merge.empty()) return merge();
    if (args_.scene.empty()) throw UsageError("bench-error: SCENE is required (or --merge DIR...)");
    validate();
    std::optional<tbb::global_control> threads;
    if (args_.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, args_.threads);

    // The scene with its own strategies: its resolution, whether BRDF sampling matters, and the
    // reference render if there is none to reuse. Loading it validates the scene (exit 2).
    tables_.emplace(commandTableCache(args_.noCache));
    Scene scene = loadScene(args_.scene, {}, *tables_);
    const Film film = makeFilm(scene);
    width_ = film.width();
    height_ = film.height();
    sceneSeed_ = scene.settings.seed;
    if (samplers_.empty()) samplers_ = {scene.settings.sampler};
    StrategyPlan plan = planStrategies(bsdfs_, envs_, mises_, samplers_, scene.hasMeasuredMaterial());
    plan_ = std::move(plan.render);
    skipped_ = std::move(plan.skipped);
    if (!args_.reference.empty()) loadGivenReference();
    prepareOutputDirectory();
    if (args_.reference.empty()) renderOrReuseReference(scene);

    resume();
    renderRows();
    const std::size_t differenceImages = writeDifferenceImages();

    std::string summary;
    summary += fmt::format("bench-error {}: {} strategy combinations x {} budgets ({}), {} left out as identical\n",
                           args_.scene, plan_.size(), budgets_.size(), budgetKind(), skipped_.size());
    for (const SkippedStrategy& s : skipped_)
      summary += fmt::format("  left out  {}: {}\n", s.strategy.label(), s.reason);
    if (!args_.shard.empty())
      summary += fmt::format("shard       {}: the rows of index % {} == {}\n", args_.shard, shard_.n, shard_.k - 1);
    summary += fmt::format("reference   {} ({})\n", referenceDescription_, referenceOrigin_);
    summary += fmt::format("rows        {} rendered, {} kept from an earlier run\n", rendered_, kept_);
    return finish(summary, differenceImages);
  }

 private:
  // The summary's last lines and the plots, for a run and a merge alike.
  int finish(std::string summary, std::size_t differenceImages) {
    summary += fmt::format("wrote       {}, {}, {} difference images in {}\n", (dir_ / "results.csv").string(),
                           (dir_ / "results.json").string(), differenceImages, (dir_ / "diff").string());
    std::fputs(summary.c_str(), stdout);
    if (args_.noPlot) return std::fflush(stdout) == 0 ? 0 : 1;
    const std::string plotProblem = runPlotScript(args_, dir_);
    if (!plotProblem.empty()) {
      std::fprintf(stderr, "acdf: bench-error: plotting failed (%s); results.csv and results.json in %s are complete\n",
                   oneLine(plotProblem).c_str(), dir_.string().c_str());
      return kExitPlotFailed;
    }
    std::printf("plots       %s, %s\n", (dir_ / "error_vs_time.png").c_str(), (dir_ / "memory_vs_error.png").c_str());
    return std::fflush(stdout) == 0 ? 0 : 1;
  }

  // --merge: the shards' rows, checked to be of one run, into --out as an unsharded run writes
  // them. Every check comes before anything is written.
  int merge() {
    if (!args_.scene.empty()) throw UsageError("bench-error: --merge takes shard directories, not SCENE");
    if (!args_.shard.empty()) throw UsageError("bench-error: --merge and --shard exclude each other");
    std::vector<Json> shards;
    for (const std::string& dir : args_.merge) {
      const fs::path file = fs::path(dir) / "results.json";
      const auto j = readJsonFile(file);
      if (!j || !(*j)["settings"].is_object() || !(*j)["rows"].is_array())
        throw FileError(file.string(), "no results of a bench-error run (a shard's --out?)");
      shards.push_back(*j);
    }
    const Json& first = shards[0]["settings"];
    std::set<uint32_t> seen;
    for (std::size_t i = 0; i < shards.size(); ++i) {
      const Json& settings = shards[i]["settings"];
      const std::string file = (fs::path(args_.merge[i]) / "results.json").string();
      for (const char* key :
           {"scene_hash", "reference_hash", "budget_kind", "budgets", "seeds", "scene_seed", "threads", "strategies"})
        if (settings.value(key, Json()) != first.value(key, Json()))
          throw FileError(
              file, fmt::format("its {} ({}) differs from that of {} ({}): not shards of one run", key,
                                settings.value(key, Json()).dump(), args_.merge[0], first.value(key, Json()).dump()));
      const Json shard = settings.value("shard", Json());
      if (!shard.is_object()) throw FileError(file, "not a shard (run with --shard K/N)");
      if (shard.value("n", 0u) != first["shard"].value("n", 0u))
        throw FileError(file, fmt::format("shard {}/{} of another split than {} ({}/{})", shard.value("k", 0u),
                                          shard.value("n", 0u), args_.merge[0], first["shard"].value("k", 0u),
                                          first["shard"].value("n", 0u)));
      if (!seen.insert(shard.value("k", 0u)).second)
        throw FileError(file, fmt::format("shard {}/{} is given twice", shard.value("k", 0u), shard.value("n", 0u)));
      for (const Json& row : shards[i]["rows"])
        if (!rowKey(row))
          throw FileError(file,
                          "a row without a known strategy (bsdf_sampling, env_sampling, mis, sampler) and budget");
    }
    const uint32_t n = first["shard"].value("n", 0u);
    for (uint32_t k = 1; k <= n; ++k)
      if (!seen.contains(k)) throw UsageError(fmt::format("bench-error: --merge: shard {}/{} is missing", k, n));

    // The reference: the first shard's rendered one, else the given file; its pixels must be those
    // every shard measured against.
    const fs::path rendered = fs::path(args_.merge[0]) / "reference.exr";
    std::error_code ec;
    const std::string referenceFile =
        fs::is_regular_file(rendered, ec) ? rendered.string() : first["reference"].value("file", rendered.string());
    reference_ = readImage(referenceFile);
    referenceInfo_ = first["reference"];
    finishReference();
    if (referenceHash_ != first.value("reference_hash", ""))
      throw FileError(referenceFile, "its pixels are not those of the shards' reference");
    width_ = reference_.width;
    height_ = reference_.height;

    std::vector<Json> rows;
    for (const Json& shard : shards)
      for (const Json& row : shard["rows"]) rows.push_back(row);
    std::stable_sort(rows.begin(), rows.end(),
                     [](const Json& a, const Json& b) { return a.value("row", 0u) < b.value("row", 0u); });
    std::set<std::string> planned;
    for (const Json& row : rows)
      if (const Strategy s = *strategyOf(row); planned.insert(s.id()).second) plan_.push_back(s);

    prepareOutputDirectory();
    if (fs::is_regular_file(rendered, ec)) {
      fs::copy_file(rendered, dir_ / "reference.exr", fs::copy_options::overwrite_existing);
      fs::copy_file(fs::path(args_.merge[0]) / "reference.json", dir_ / "reference.json",
                    fs::copy_options::overwrite_existing);
    }
    for (const std::string& dir : args_.merge)
      for (const Strategy& s : plan_) {
        const fs::path image = fs::path(dir) / "images" / (s.id() + ".exr");
        if (fs::is_regular_file(image, ec))
          fs::copy_file(image, dir_ / "images" / image.filename(), fs::copy_options::overwrite_existing);
      }
    Json settings = first;
    settings.erase("shard");
    Json rowsJson = Json::array();
    for (const Json& row : rows) rowsJson.push_back(row);
    writeResultFiles(dir_, settings, shards[0]["skipped"], rowsJson, args_.targetRelMse);
    const std::size_t differenceImages = writeDifferenceImages();
    const std::string summary = fmt::format("bench-error --merge: {} shards of {}, {} rows\n", shards.size(),
                                            first.value("scene", ""), rows.size());
    return finish(summary, differenceImages);
  }

  // Everything about the command line that can be checked before anything is written.
  void validate() {
    if (!args_.shard.empty()) shard_ = parseShard(args_.shard);
    bsdfs_ = parseList<BrdfSampling>(args_.bsdf, "--bsdf-sampling", parseBrdfSampling,
                                     {BrdfSampling::Cosine, BrdfSampling::Uniform, BrdfSampling::Adaptive});
    envs_ = parseList<EnvironmentSampling>(args_.env, "--env-sampling", parseEnvironmentSampling,
                                           {std::begin(kEnvironmentSamplings), std::end(kEnvironmentSamplings)});
    mises_ = parseList<MisMode>(args_.mis, "--mis", parseMisMode,
                                {MisMode::Power, MisMode::Balance, MisMode::BsdfOnly, MisMode::LightOnly});
    samplers_ = parseList<SamplerKind>(args_.samplers, "--sampler", parseSamplerKind, {});
    if (!args_.sppBudgets.empty()) {
      for (uint32_t spp : args_.sppBudgets) budgets_.push_back(spp);
    } else {
      budgets_ = args_.budgets.empty() ? std::vector<double>{1, 2, 4, 8, 16} : args_.budgets;
      for (double b : budgets_)
        if (!(b > 0) || !std::isfinite(b))
          throw UsageError(fmt::format("bench-error: --budgets: {} is not a positive number of seconds", b));
    }
    std::sort(budgets_.begin(), budgets_.end());
    budgets_.erase(std::unique(budgets_.begin(), budgets_.end()), budgets_.end());
    sceneHash_ = hexHash(ContentHash().text(readText(args_.scene)));
  }

  const char* budgetKind() const { return args_.sppBudgets.empty() ? "seconds" : "spp"; }

  // --out: an existing writable directory, or one we can create. Created only after every
  // check passed, so bad input leaves nothing behind.
  void prepareOutputDirectory() {
    std::error_code ec;
    if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec)) throw FileError(dir_.string(), "--out is not a directory");
    if (fs::is_directory(dir_, ec)) {
      if (access(dir_.c_str(), W_OK) != 0) throw FileError(dir_.string(), "the output directory is not writable");
    } else {
      const fs::path parent = dir_.parent_path().empty() ? fs::path(".") : dir_.parent_path();
      if (!fs::is_directory(parent, ec)) throw FileError(dir_.string(), "its parent directory does not exist");
      if (access(parent.c_str(), W_OK) != 0)
        throw FileError(dir_.string(), "cannot create the output directory (parent not writable)");
      if (!fs::create_directory(dir_, ec) && ec)
        throw FileError(dir_.string(), "cannot create the output directory (" + ec.message() + ")");
    }
    fs::create_directories(dir_ / "images", ec);
    if (!ec) fs::create_directories(dir_ / "diff", ec);
    if (ec) throw FileError(dir_.string(), "cannot create its images/ and diff/ directories (" + ec.message() + ")");
  }

  void checkReferenceShape(const Image& image, const std::string& file) const {
    if (image.width != width_ || image.height != height_)
      throw FileError(file, fmt::format("the reference is {}x{} but {} renders {}x{}", image.width, image.height,
                                        args_.scene, width_, height_));
    if (image.channels != 3) throw FileError(file, "the reference must have RGB channels");
  }

  void loadGivenReference() {
    reference_ = readImage(args_.reference);
    checkReferenceShape(reference_, args_.reference);
    referenceDescription_ = args_.reference;
    referenceOrigin_ = "given";
    referenceInfo_ = Json{{"file", fs::absolute(args_.reference).string()}};
    finishReference();
  }

  // DIR/reference.exr with DIR/reference.json saying what it is; reused only when the scene's
  // text, the sample count and the resolution match.
  void renderOrReuseReference(Scene& scene) {
    const fs::path exr = dir_ / "reference.exr", info = dir_ / "reference.json";
    Json wanted{{"scene", args_.scene},
                {"scene_hash", sceneHash_},
                {"spp", args_.referenceSpp},
                {"width", width_},
                {"height", height_},
                {"seed", scene.settings.seed},
                {"bsdf_sampling", "scene"},
                {"env_sampling", toString(scene.environment->options().strategy)},
                {"mis", toString(scene.settings.mis)}};
    referenceDescription_ = exr.string();
    if (const auto stored = readJsonFile(info)) {
      const bool same = stored->value("scene_hash", "") == sceneHash_ &&
                        stored->value("spp", 0u) == args_.referenceSpp && stored->value("width", 0u) == width_ &&
                        stored->value("height", 0u) == height_;
      std::error_code ec;
      if (same && fs::is_regular_file(exr, ec)) {
        try {
          reference_ = readImage(exr.string());
          checkReferenceShape(reference_, exr.string());
          referenceOrigin_ = fmt::format("{} spp, reused", args_.referenceSpp);
          referenceInfo_ = *stored;
          finishReference();
          return;
        } catch (const std::exception& e) {
          std::fprintf(stderr, "acdf: warning: %s: rendering the reference again\n", oneLine(e.what()).c_str());
        }
      }
    }
    std::fprintf(stderr, "reference: %s, %u spp\n", args_.scene.c_str(), args_.referenceSpp);
    scene.settings.spp = args_.referenceSpp;
    const RenderStats stats = renderImage(scene, std::nullopt);
    wanted["seconds"] = stats.seconds;
    referenceOrigin_ = fmt::format("{} spp, rendered in {:.1f} s", args_.referenceSpp, stats.seconds);
    writeImage(exr.string(), reference_ = lastImage_, false);
    writeFileAtomically(info.string(), wanted.dump(2) + "\n");
    referenceInfo_ = wanted;
    finishReference();
  }

  void finishReference() {
    referenceHash_ = hexHash(ContentHash().values(std::span<const float>(reference_.pixels)));
    referenceInfo_["pixels_hash"] = referenceHash_;
  }

  // Renders into lastImage_.
  RenderStats renderImage(const Scene& scene, std::optional<double> seconds) {
    Film film = makeFilm(scene);
    const RenderStats stats = renderWithProgress(scene, film, seconds);
    lastImage_ = film.image();
    return stats;
  }

  Json strategyIds() const {
    Json ids = Json::array();
    for (const Strategy& s : plan_) ids.push_back(s.id());
    return ids;
  }

  Json settings() const {
    Json j{{"scene", args_.scene},
           {"scene_hash", sceneHash_},
           {"reference", referenceInfo_},
           {"reference_hash", referenceHash_},
           {"budget_kind", budgetKind()},
           {"threads", args_.threads},
           {"budgets", budgets_},
           {"strategies", strategyIds()},
           {"seeds", args_.seeds},
           {"scene_seed", sceneSeed_},
           {"relmse", "mean over pixels and channels of (I - R)^2 / (R^2 + 0.01)"},
           {"relmse_trimmed",
            fmt::format("relmse after discarding the floor({} x pixels) pixels of largest error (a pixel's error: "
                        "the mean over its channels)",
                        kTrimmedFraction)},
           {"rmse", "sqrt(mean over pixels and channels of (I - R)^2)"},
           {"efficiency",
            "1 / (relmse x seconds) of the means over seeds; its stderr by the delta method with the seeds' "
            "covariance of relmse and seconds"},
           {"stderr", "standard error of the mean over seeds: sample standard deviation / sqrt(seeds)"}};
    if (!args_.shard.empty()) j["shard"] = {{"k", shard_.k}, {"n", shard_.n}};
    return j;
  }

  // Rows of an earlier run with the same scene, reference, budget kind, threads and seeds are kept.
  void resume() {
    const fs::path path = dir_ / "results.json";
    const auto earlier = readJsonFile(path);
    if (!earlier) return;
    const Json now = settings();
    const Json& then = (*earlier)["settings"];
    const bool same = then.is_object() && then.value("scene_hash", "") == now["scene_hash"] &&
                      then.value("reference_hash", "") == now["reference_hash"] &&
                      then.value("budget_kind", "") == now["budget_kind"] &&
                      then.value("threads", 0u) == args_.threads && then.value("seeds", 0u) == args_.seeds &&
                      then.value("scene_seed", uint64_t(0)) == sceneSeed_ &&
                      then.value("shard", Json()) == now.value("shard", Json());
    if (!same || !(*earlier)["rows"].is_array()) {
      std::fprintf(stderr,
                   "bench-error: %s is from other settings (scene, reference, budget kind, threads, seeds or shard): "
                   "starting afresh\n",
                   path.c_str());
      return;
    }
    for (const Json& row : (*earlier)["rows"])
      if (const auto key = row.is_object() ? rowKey(row) : std::nullopt; key && done_.insert(*key).second)
        rows_.push_back(row);
    kept_ = rows_.size();
  }

  // Seed `k` of a row: a hash of the scene's seed, the strategy, the budget and k, so every render
  // of the matrix has its own seed and a rerun (or a shard) renders the same ones.
  uint64_t seedFor(const Strategy& s, double budget, uint32_t k) const {
    return ContentHash().number(sceneSeed_).text(s.id()).number(std::bit_cast<uint64_t>(budget)).number(k).digest().low;
  }

  void renderRows() {
    // A row's index in the matrix (strategy-major, then budget): what a shard selects by, and the
    // order --merge restores. Rows kept from an earlier run get their index in this matrix.
    std::map<std::string, std::size_t> indexOf;
    for (std::size_t i = 0; i < plan_.size(); ++i)
      for (std::size_t b = 0; b < budgets_.size(); ++b)
        indexOf[rowKey(plan_[i], budgets_[b])] = i * budgets_.size() + b;
    for (Json& row : rows_)
      if (const auto at = indexOf.find(*rowKey(row)); at != indexOf.end()) row["row"] = at->second;

    const std::size_t total = plan_.size() * budgets_.size();
    std::size_t index = 0;
    for (const Strategy& s : plan_) {
      const auto pending = [&](double budget) {
        return shard_.has(indexOf.at(rowKey(s, budget))) && !done_.contains(rowKey(s, budget));
      };
      if (std::none_of(budgets_.begin(), budgets_.end(), pending)) {
        index += budgets_.size();
        std::fprintf(stderr, "[%zu/%zu] %s: kept from an earlier run or in another shard\n", index, total,
                     s.label().c_str());
        continue;
      }
      SceneOverrides overrides;
      overrides.bsdfSampling = s.bsdf;
      overrides.envSampling = s.env;
      overrides.mis = s.mis;
      overrides.sampler = s.sampler;
      const std::size_t builtBefore = tables_->tablesBuilt().size(), cachedBefore = tables_->tablesFromCache().size();
      const auto setupStart = Clock::now();
      Scene scene = loadScene(args_.scene, overrides, *tables_);
      scene.buildDeferredTables();
      const double tableMs = millisecondsSince(setupStart);
      const Scene::TableBytes memory = scene.tableBytes();
      for (double budget : budgets_) {
        ++index;
        if (!pending(budget)) continue;
        std::vector<SeedRender> renders;
        Json perSeed = Json::array();
        uint64_t sppSum = 0;
        for (uint32_t k = 0; k < args_.seeds; ++k) {
          scene.settings.seed = seedFor(s, budget, k);
          std::optional<double> seconds;
          if (args_.sppBudgets.empty())
            seconds = budget;
          else
            scene.settings.spp = static_cast<uint32_t>(budget);
          const RenderStats stats = renderImage(scene, seconds);
          const RenderError error = renderError(lastImage_, reference_);
          renders.push_back({error, stats.seconds});
          sppSum += stats.spp;
          perSeed.push_back({{"seed", scene.settings.seed},
                             {"seconds", stats.seconds},
                             {"spp", stats.spp},
                             {"relmse", error.relMse},
                             {"relmse_trimmed", error.relMseTrimmed},
                             {"rmse", error.rmse}});
          // The first seed's image of the largest budget feeds the difference images; written
          // before its row, so a row on disk always has its image.
          if (k == 0 && budget == budgets_.back())
            writeImage((dir_ / "images" / (s.id() + ".exr")).string(), lastImage_, false);
        }
        const SeedAggregate a = aggregateSeeds(renders);
        const uint64_t spp = (sppSum + args_.seeds / 2) / args_.seeds;
        Json row{{"row", indexOf.at(rowKey(s, budget))}};
        row.update(strategyJson(s));
        row.update(Json{{"budget_kind", budgetKind()},
                        {"budget", budget},
                        {"seeds", args_.seeds},
                        {"seconds", a.seconds.mean},
                        {"seconds_stderr", a.seconds.standardError},
                        {"spp", spp},
                        {"relmse", a.relMse.mean},
                        {"relmse_stderr", a.relMse.standardError},
                        {"relmse_trimmed", a.relMseTrimmed.mean},
                        {"relmse_trimmed_stderr", a.relMseTrimmed.standardError},
                        {"rmse", a.rmse.mean},
                        {"rmse_stderr", a.rmse.standardError},
                        {"efficiency", a.efficiency.mean},
                        {"efficiency_stderr", a.efficiency.standardError},
                        {"brdf_table_bytes", memory.brdf},
                        {"env_table_bytes", memory.environment},
                        {"table_bytes", memory.brdf + memory.environment},
                        {"table_ms", tableMs},
                        {"tables_built", tables_->tablesBuilt().size() - builtBefore},
                        {"tables_from_cache", tables_->tablesFromCache().size() - cachedBefore},
                        {"per_seed", perSeed}});
        done_.insert(rowKey(s, budget));
        rows_.push_back(std::move(row));
        ++rendered_;
        writeResults();
        std::fprintf(stderr, "[%zu/%zu] %s, %g %s, %u seeds: %llu spp, relMSE %.3g +- %.2g, trimmed %.3g\n", index,
                     total, s.label().c_str(), budget, args_.sppBudgets.empty() ? "s" : "spp", args_.seeds,
                     static_cast<unsigned long long>(spp), a.relMse.mean, a.relMse.standardError, a.relMseTrimmed.mean);
      }
    }
    if (rendered_ == 0) writeResults();  // the settings of this run, even when nothing was new
  }

  void writeResults() const {
    Json skipped = Json::array();
    for (const SkippedStrategy& s : skipped_) {
      Json entry = strategyJson(s.strategy);
      entry["reason"] = s.reason;
      skipped.push_back(std::move(entry));
    }
    Json rows = Json::array();
    for (const Json& r : rows_) rows.push_back(r);
    writeResultFiles(dir_, settings(), skipped, rows, args_.targetRelMse);
  }

  // diff/<strategy>.png against the reference, and diff/<axis>-adaptive-vs-uniform_<rest>.png
  // between the adaptive and the uniform table of one axis (the paper's Table 2), each from the
  // images of the largest budget.
  std::size_t writeDifferenceImages() const {
    std::map<std::string, Image> images;
    for (const Strategy& s : plan_) {
      const fs::path file = dir_ / "images" / (s.id() + ".exr");
      std::error_code ec;
      if (!fs::is_regular_file(file, ec)) continue;
      Image image = readImage(file.string());
      if (image.width != width_ || image.height != height_ || image.channels != 3) continue;
      images.emplace(s.id(), std::move(image));
    }
    std::size_t written = 0;
    const auto write = [&](const std::string& name, const Image& a, const Image& b) {
      writeImage((dir_ / "diff" / (name + ".png")).string(), differenceImage(a, b, reference_), true);
      ++written;
    };
    for (const auto& [id, image] : images) write(id, image, reference_);
    for (const Strategy& s : plan_) {
      if (s.env == EnvironmentSampling::Adaptive) {
        const Strategy uniform{s.bsdf, EnvironmentSampling::Uniform, s.mis, s.sampler};
        if (images.contains(s.id()) && images.contains(uniform.id()))
          write(fmt::format("env-adaptive-vs-uniform_{}_{}_{}", toString(s.bsdf), toString(s.mis), toString(s.sampler)),
                images.at(s.id()), images.at(uniform.id()));
      }
      if (s.bsdf == BrdfSampling::Adaptive) {
        const Strategy uniform{BrdfSampling::Uniform, s.env, s.mis, s.sampler};
        if (images.contains(s.id()) && images.contains(uniform.id()))
          write(fmt::format("bsdf-adaptive-vs-uniform_{}_{}_{}", toString(s.env), toString(s.mis), toString(s.sampler)),
                images.at(s.id()), images.at(uniform.id()));
      }
    }
    return written;
  }

  const BenchErrorArgs& args_;
  fs::path dir_;
  // One provider for the run: the scene's inputs (MERL files, maps) are read once, and a
  // combination's set-up time is that of its own tables.
  std::optional<TableProvider> tables_;
  std::vector<BrdfSampling> bsdfs_;
  std::vector<EnvironmentSampling> envs_;
  std::vector<MisMode> mises_;
  std::vector<SamplerKind> samplers_;  // empty until the scene is loaded: its own sampler
  std::vector<double> budgets_;
  std::vector<Strategy> plan_;
  std::vector<SkippedStrategy> skipped_;
  std::string sceneHash_, referenceHash_, referenceDescription_, referenceOrigin_;
  Json referenceInfo_;
  uint32_t width_ = 0, height_ = 0;
  uint64_t sceneSeed_ = 0;
  Shard shard_;
  Image reference_, lastImage_;
  std::set<std::string> done_;
  std::vector<Json> rows_;
  std::size_t rendered_ = 0, kept_ = 0;
};

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
      "A combination is BRDF sampling x environment sampling x MIS mode x sample source (--sampler).\n"
      "Combinations that render the same image as another are left out and listed: bsdf-only with any but\n"
      "the first --env-sampling, and BRDF strategies other than the first when no material is measured.\n"
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
  app->add_option("--sampler", args->samplers, "Sample sources, e.g. independent,sobol (default: the scene's)")
      ->delimiter(',');
  app->add_option("--threads", args->threads, "Worker threads (0 = all cores)");
  app->add_flag("--no-cache", args->noCache, "Neither read nor store tables in the table cache");
  app->add_flag("--no-plot", args->noPlot, "Do not run the plot script");
  app->add_option("--plot-script", args->plotScript,
                  "The plot script (default: bench/error_report.py of the source tree)");
  app->add_option("--python", args->python, "Python with matplotlib (default /usr/bin/python3)");
  return Command{app, [args] { return BenchError(*args).run(); }};
}

}  // namespace acdf::app

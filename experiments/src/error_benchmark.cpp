#include "acdf/experiments/error_benchmark.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "acdf/envmap/image_file.h"
#include "acdf/experiments/render_error.h"
#include "acdf/integrator/scene.h"
#include "acdf/sampling/file_error.h"
#include "acdf/sampling/option_error.h"
#include "acdf/sampling/timing.h"
#include "acdf/sampling/write_atomically.h"

namespace acdf {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

std::vector<double> defaultBudgets() { return {1, 2, 4, 8, 16}; }

std::string hexHash(const ContentHash& hash) { return hash.digest().hex(); }

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw FileError(path.string(), "cannot read the file");
  return text.str();
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

// A results row's strategy; none if a name is missing or unknown.
std::optional<Strategy> strategyOf(const Json& row) {
  try {
    return Strategy{parseBrdfSampling(row.value("bsdf_sampling", "")),
                    parseEnvironmentSampling(row.value("env_sampling", "")), parseMisMode(row.value("mis", "")),
                    parseSamplerKind(row.value("sampler", "")), parseDirectLighting(row.value("direct", "mis"))};
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
}

// The strategy's five names, as rows, curves and skipped entries carry them (strategyOf reads them;
// rows of runs from before the direct-lighting axis have no "direct": they are "mis").
Json strategyJson(const Strategy& s) {
  return {{"bsdf_sampling", toString(s.bsdf)},
          {"env_sampling", toString(s.env)},
          {"direct", toString(s.direct)},
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
                                   "direct",
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
  std::string out =
      "bsdf_sampling,env_sampling,direct,mis,sampler,time_to_target,time_to_target_stderr,extrapolated\n";
  for (const Json& c : curves)
    out += fmt::format("{},{},{},{},{},{},{},{}\n", c["bsdf_sampling"].get<std::string>(),
                       c["env_sampling"].get<std::string>(), c["direct"].get<std::string>(),
                       c["mis"].get<std::string>(),
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

class ErrorBenchmark {
 public:
  explicit ErrorBenchmark(const ErrorBenchmarkOptions& options) : options_(options), dir_(options.out) {}

  ErrorBenchmarkReport run(TableCache cache) {
    validate();
    std::optional<tbb::global_control> threads;
    if (options_.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, options_.threads);

    // The scene with its own strategies: its resolution, whether BRDF sampling matters, and the
    // reference render if there is none to reuse. Loading it validates the scene.
    tables_.emplace(std::move(cache));
    Scene scene = loadScene(options_.scene, {}, *tables_);
    sceneHash_ = hexHash(ContentHash().text(readText(options_.scene)));
    const Film film = makeFilm(scene);
    width_ = film.width();
    height_ = film.height();
    sceneSeed_ = scene.settings.seed;
    if (samplers_.empty()) samplers_ = {scene.settings.sampler};
    product_ = scene.settings.product;
    StrategyPlan plan = planStrategies(bsdfs_, envs_, mises_, samplers_, scene.usesMeasuredMaterial, directs_);
    plan_ = std::move(plan.render);
    skipped_ = std::move(plan.skipped);
    if (!options_.reference.empty()) loadGivenReference();
    prepareOutputDirectory();
    if (options_.reference.empty()) renderOrReuseReference(scene);

    resume();
    renderRows();
    ErrorBenchmarkReport report = reportBase();
    report.differenceImages = writeDifferenceImages();
    return report;
  }

  // The shards' rows, checked to be of one run, into the output directory as an unsharded run
  // writes them. Every check comes before anything is written.
  ErrorBenchmarkReport merge(const std::vector<fs::path>& shardDirs) {
    std::vector<Json> shards;
    for (const fs::path& dir : shardDirs) {
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
      const std::string file = (shardDirs[i] / "results.json").string();
      for (const char* key :
           {"scene_hash", "reference_hash", "budget_kind", "budgets", "seeds", "scene_seed", "threads", "strategies"})
        if (settings.value(key, Json()) != first.value(key, Json()))
          throw FileError(file, fmt::format("its {} ({}) differs from that of {} ({}): not shards of one run", key,
                                            settings.value(key, Json()).dump(), shardDirs[0].string(),
                                            first.value(key, Json()).dump()));
      const Json shard = settings.value("shard", Json());
      if (!shard.is_object()) throw FileError(file, "not a shard (run with --shard K/N)");
      if (shard.value("n", 0u) != first["shard"].value("n", 0u))
        throw FileError(file, fmt::format("shard {}/{} of another split than {} ({}/{})", shard.value("k", 0u),
                                          shard.value("n", 0u), shardDirs[0].string(), first["shard"].value("k", 0u),
                                          first["shard"].value("n", 0u)));
      if (!seen.insert(shard.value("k", 0u)).second)
        throw FileError(file, fmt::format("shard {}/{} is given twice", shard.value("k", 0u), shard.value("n", 0u)));
      for (const Json& row : shards[i]["rows"])
        if (!rowKey(row))
          throw FileError(
              file, "a row without a known strategy (bsdf_sampling, env_sampling, direct, mis, sampler) and budget");
    }
    const uint32_t n = first["shard"].value("n", 0u);
    for (uint32_t k = 1; k <= n; ++k)
      if (!seen.contains(k)) throw OptionError("bench-error", "merge", fmt::format("misses shard {}/{}", k, n));

    // The reference: the first shard's rendered one, else the given file; its pixels must be those
    // every shard measured against.
    const fs::path rendered = shardDirs[0] / "reference.exr";
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
      fs::copy_file(shardDirs[0] / "reference.json", dir_ / "reference.json", fs::copy_options::overwrite_existing);
    }
    for (const fs::path& dir : shardDirs)
      for (const Strategy& s : plan_) {
        const fs::path image = dir / "images" / (s.id() + ".exr");
        if (fs::is_regular_file(image, ec))
          fs::copy_file(image, dir_ / "images" / image.filename(), fs::copy_options::overwrite_existing);
      }
    Json settings = first;
    settings.erase("shard");
    Json rowsJson = Json::array();
    for (const Json& row : rows) rowsJson.push_back(row);
    writeResultFiles(dir_, settings, shards[0]["skipped"], rowsJson, options_.targetRelMse);
    ErrorBenchmarkReport report;
    report.shardsMerged = shards.size();
    report.scene = first.value("scene", "");
    report.rows = rows.size();
    report.strategies = plan_.size();
    report.reference = referenceFile;
    report.differenceImages = writeDifferenceImages();
    return report;
  }

  // The lists and budgets of the options, their defaults filled in.
  void validate() {
    acdf::validate(options_);
    shard_ = options_.shard.value_or(ErrorBenchmarkShard{});
    bsdfs_ = options_.bsdf.empty()
                 ? std::vector<BrdfSampling>{BrdfSampling::Cosine, BrdfSampling::Uniform, BrdfSampling::Adaptive}
                 : options_.bsdf;
    envs_ = options_.env.empty()
                ? std::vector<EnvironmentSampling>{std::begin(kEnvironmentSamplings), std::end(kEnvironmentSamplings)}
                : options_.env;
    mises_ = options_.mis.empty()
                 ? std::vector<MisMode>{MisMode::Power, MisMode::Balance, MisMode::BsdfOnly, MisMode::LightOnly}
                 : options_.mis;
    samplers_ = options_.samplers;
    directs_ = options_.direct.empty() ? std::vector<DirectLighting>{DirectLighting::Mis} : options_.direct;
    budgets_ = options_.budgets.empty() ? defaultBudgets() : options_.budgets;
    std::sort(budgets_.begin(), budgets_.end());
    budgets_.erase(std::unique(budgets_.begin(), budgets_.end()), budgets_.end());
  }

  ErrorBenchmarkReport reportBase() const {
    ErrorBenchmarkReport report;
    report.strategies = plan_.size();
    report.budgets = budgets_.size();
    report.skipped = skipped_;
    report.reference = referenceDescription_;
    report.referenceOrigin = referenceOrigin_;
    report.rendered = rendered_;
    report.kept = kept_;
    return report;
  }

  void log(const std::string& line) const {
    if (options_.log) options_.log(line);
  }

  const char* budgetKind() const { return options_.sppBudgets ? "spp" : "seconds"; }

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
                                        options_.scene.string(), width_, height_));
    if (image.channels != 3) throw FileError(file, "the reference must have RGB channels");
  }

  void loadGivenReference() {
    const std::string file = options_.reference.string();
    reference_ = readImage(file);
    checkReferenceShape(reference_, file);
    referenceDescription_ = file;
    referenceOrigin_ = "given";
    referenceInfo_ = Json{{"file", fs::absolute(options_.reference).string()}};
    finishReference();
  }

  // DIR/reference.exr with DIR/reference.json saying what it is; reused only when the scene's
  // text, the sample count and the resolution match.
  void renderOrReuseReference(Scene& scene) {
    const fs::path exr = dir_ / "reference.exr", info = dir_ / "reference.json";
    Json wanted{{"scene", options_.scene.string()},
                {"scene_hash", sceneHash_},
                {"spp", options_.referenceSpp},
                {"width", width_},
                {"height", height_},
                {"seed", scene.settings.seed},
                {"bsdf_sampling", "scene"},
                {"env_sampling", toString(scene.environment->options().strategy)},
                {"mis", toString(scene.settings.mis)}};
    referenceDescription_ = exr.string();
    if (const auto stored = readJsonFile(info)) {
      const bool same = stored->value("scene_hash", "") == sceneHash_ &&
                        stored->value("spp", 0u) == options_.referenceSpp && stored->value("width", 0u) == width_ &&
                        stored->value("height", 0u) == height_;
      std::error_code ec;
      if (same && fs::is_regular_file(exr, ec)) {
        try {
          reference_ = readImage(exr.string());
          checkReferenceShape(reference_, exr.string());
          referenceOrigin_ = fmt::format("{} spp, reused", options_.referenceSpp);
          referenceInfo_ = *stored;
          finishReference();
          return;
        } catch (const std::exception& e) {
          log(fmt::format("warning: {}: rendering the reference again", oneLine(e.what())));
        }
      }
    }
    log(fmt::format("reference: {}, {} spp", options_.scene.string(), options_.referenceSpp));
    scene.settings.spp = options_.referenceSpp;
    const RenderStats stats = renderImage(scene, std::nullopt);
    wanted["seconds"] = stats.seconds;
    referenceOrigin_ = fmt::format("{} spp, rendered in {:.1f} s", options_.referenceSpp, stats.seconds);
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
    RenderStats stats;
    if (options_.render) {
      stats = options_.render(scene, film, seconds);
    } else {
      RenderOptions render;
      render.seconds = seconds;
      stats = acdf::render(scene, film, render);
    }
    lastImage_ = film.image();
    return stats;
  }

  Json strategyIds() const {
    Json ids = Json::array();
    for (const Strategy& s : plan_) ids.push_back(s.id());
    return ids;
  }

  Json settings() const {
    Json j{{"scene", options_.scene.string()},
           {"scene_hash", sceneHash_},
           {"reference", referenceInfo_},
           {"reference_hash", referenceHash_},
           {"budget_kind", budgetKind()},
           {"threads", options_.threads},
           {"budgets", budgets_},
           {"strategies", strategyIds()},
           {"product_sampling", {{"candidates", product_.candidates}, {"bsdf_fraction", product_.bsdfFraction}}},
           {"seeds", options_.seeds},
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
    if (options_.shard) j["shard"] = {{"k", shard_.k}, {"n", shard_.n}};
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
                      then.value("threads", 0u) == options_.threads && then.value("seeds", 0u) == options_.seeds &&
                      then.value("scene_seed", uint64_t(0)) == sceneSeed_ &&
                      then.value("shard", Json()) == now.value("shard", Json());
    if (!same || !(*earlier)["rows"].is_array()) {
      log(
          fmt::format("bench-error: {} is from other settings (scene, reference, budget kind, threads, seeds or "
                      "shard): starting afresh",
                      path.string()));
      return;
    }
    for (const Json& row : (*earlier)["rows"])
      if (const auto key = row.is_object() ? rowKey(row) : std::nullopt; key && done_.insert(*key).second) {
        rows_.push_back(row);
        rows_.back().update(strategyJson(*strategyOf(row)));  // every column, also in an older run's rows
      }
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
        log(fmt::format("[{}/{}] {}: kept from an earlier run or in another shard", index, total, s.label()));
        continue;
      }
      SceneOverrides overrides;
      overrides.bsdfSampling = s.bsdf;
      overrides.envSampling = s.env;
      overrides.mis = s.mis;
      overrides.direct = s.direct;
      overrides.sampler = s.sampler;
      const std::size_t builtBefore = tables_->tablesBuilt().size(), cachedBefore = tables_->tablesFromCache().size();
      const auto setupStart = Clock::now();
      Scene scene = loadScene(options_.scene, overrides, *tables_);
      scene.buildDeferredTables();
      const double tableMs = millisecondsSince(setupStart);
      const Scene::TableBytes memory = scene.tableBytes();
      for (double budget : budgets_) {
        ++index;
        if (!pending(budget)) continue;
        std::vector<SeedRender> renders;
        Json perSeed = Json::array();
        uint64_t sppSum = 0;
        for (uint32_t k = 0; k < options_.seeds; ++k) {
          scene.settings.seed = seedFor(s, budget, k);
          std::optional<double> seconds;
          if (options_.sppBudgets)
            scene.settings.spp = static_cast<uint32_t>(budget);
          else
            seconds = budget;
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
        const uint64_t spp = (sppSum + options_.seeds / 2) / options_.seeds;
        Json row{{"row", indexOf.at(rowKey(s, budget))}};
        row.update(strategyJson(s));
        row.update(Json{{"budget_kind", budgetKind()},
                        {"budget", budget},
                        {"seeds", options_.seeds},
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
        log(fmt::format("[{}/{}] {}, {:g} {}, {} seeds: {} spp, relMSE {:.3g} +- {:.2g}, trimmed {:.3g}", index, total,
                        s.label(), budget, options_.sppBudgets ? "spp" : "s", options_.seeds, spp, a.relMse.mean,
                        a.relMse.standardError, a.relMseTrimmed.mean));
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
    writeResultFiles(dir_, settings(), skipped, rows, options_.targetRelMse);
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
        const Strategy uniform{s.bsdf, EnvironmentSampling::Uniform, s.mis, s.sampler, s.direct};
        if (images.contains(s.id()) && images.contains(uniform.id()))
          write(fmt::format("env-adaptive-vs-uniform_{}_{}_{}", toString(s.bsdf), s.lighting(), toString(s.sampler)),
                images.at(s.id()), images.at(uniform.id()));
      }
      if (s.bsdf == BrdfSampling::Adaptive) {
        const Strategy uniform{BrdfSampling::Uniform, s.env, s.mis, s.sampler, s.direct};
        if (images.contains(s.id()) && images.contains(uniform.id()))
          write(fmt::format("bsdf-adaptive-vs-uniform_{}_{}_{}", toString(s.env), s.lighting(), toString(s.sampler)),
                images.at(s.id()), images.at(uniform.id()));
      }
    }
    return written;
  }

  const ErrorBenchmarkOptions& options_;
  fs::path dir_;
  // One provider for the run: the scene's inputs (MERL files, maps) are read once, and a
  // combination's set-up time is that of its own tables.
  std::optional<SceneAssets> tables_;
  std::vector<BrdfSampling> bsdfs_;
  std::vector<EnvironmentSampling> envs_;
  std::vector<MisMode> mises_;
  std::vector<DirectLighting> directs_;
  ProductSamplingOptions product_;  // the scene's, for every product row
  std::vector<SamplerKind> samplers_;  // empty until the scene is loaded: its own sampler
  std::vector<double> budgets_;
  std::vector<Strategy> plan_;
  std::vector<SkippedStrategy> skipped_;
  std::string sceneHash_, referenceHash_, referenceDescription_, referenceOrigin_;
  Json referenceInfo_;
  uint32_t width_ = 0, height_ = 0;
  uint64_t sceneSeed_ = 0;
  ErrorBenchmarkShard shard_;
  Image reference_, lastImage_;
  std::set<std::string> done_;
  std::vector<Json> rows_;
  std::size_t rendered_ = 0, kept_ = 0;
};

}  // namespace

ErrorBenchmarkShard parseErrorBenchmarkShard(std::string_view text) {
  const std::string s(text);
  unsigned k = 0, n = 0;
  char rest = 0;
  if (std::sscanf(s.c_str(), "%u/%u%c", &k, &n, &rest) != 2 ||
      s.find_first_not_of("0123456789/") != std::string::npos || n < 1 || k < 1 || k > n)
    throw OptionError("bench-error", "shard", fmt::format("'{}' is not K/N with 1 <= K <= N", s));
  return {k, n};
}

void validate(const ErrorBenchmarkOptions& options) {
  for (double b : options.budgets) {
    if (!(b > 0) || !std::isfinite(b))
      throw OptionError("bench-error", options.sppBudgets ? "spp_budgets" : "budgets",
                        fmt::format("must be positive, not {}", OptionError::number(b)));
    if (options.sppBudgets && (b != std::floor(b) || b > double{std::numeric_limits<uint32_t>::max()}))
      throw OptionError("bench-error", "spp_budgets",
                        fmt::format("must be whole numbers of samples, not {}", OptionError::number(b)));
  }
  if (options.seeds == 0) throw OptionError("bench-error", "seeds", "must be at least 1");
  if (options.referenceSpp == 0) throw OptionError("bench-error", "reference_spp", "must be at least 1");
  if (options.shard && (options.shard->n < 1 || options.shard->k < 1 || options.shard->k > options.shard->n))
    throw OptionError("bench-error", "shard", "must be K/N with 1 <= K <= N");
  if (!(options.targetRelMse >= 0) || !std::isfinite(options.targetRelMse))
    throw OptionError("bench-error", "target_relmse", "must be positive (or 0: the default)");
}

ErrorBenchmarkReport runErrorBenchmark(const ErrorBenchmarkOptions& options, TableCache cache) {
  return ErrorBenchmark(options).run(std::move(cache));
}

ErrorBenchmarkReport mergeErrorBenchmark(const std::vector<fs::path>& shards, const fs::path& out,
                                         double targetRelMse) {
  if (shards.empty()) throw OptionError("bench-error", "merge", "needs at least one shard directory");
  ErrorBenchmarkOptions options;
  options.out = out;
  options.targetRelMse = targetRelMse;
  return ErrorBenchmark(options).merge(shards);
}

}  // namespace acdf

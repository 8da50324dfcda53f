#pragma once
// The error-against-time benchmark (`acdf bench-error`): a scene rendered with every strategy of a
// plan (strategy_plan.h) for every budget, `seeds` times, each render measured against a
// reference (render_error.h). It writes into one output directory:
//   results.json, results.csv  a row per strategy × budget: the means over the seeds and their
//                              standard errors, set-up time and table memory. Rewritten after every
//                              row, so a stopped run resumes: rows of an earlier run with the same
//                              scene, reference, budget kind, threads, seeds and shard are kept.
//   curves.csv                 per strategy, the render time to reach the target relMSE (timeToReach)
//   reference.exr, .json       a rendered reference, reused while the scene's text, the sample count
//                              and the resolution match (none when one is given)
//   images/<strategy>.exr      the first seed's render at the largest budget
//   diff/*.png                 false colour against the reference, and between the adaptive and the
//                              uniform table of one axis
// Seed k of a row is a hash of the scene's seed, the strategy, the budget and k, so a rerun or a
// shard renders the same images. A shard K/N renders the rows of index % N == K − 1 (strategy-major,
// then budget); mergeErrorBenchmark() joins shards, checked to be of one run, into what the
// unsharded run writes.
// Bad input (scene, reference, output directory, shards) throws FileError naming the file, bad
// options OptionError (scope "bench-error", options named as the flags in snake case); every check
// comes before anything is written.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/integrator/renderer.h"
#include "acdf/experiments/strategy_plan.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

struct ErrorBenchmarkShard {
  uint32_t k = 1, n = 1;  // 1 <= k <= n
  bool has(std::size_t row) const { return row % n == k - 1; }
};
// "K/N"; throws OptionError (option "shard") for anything else.
ErrorBenchmarkShard parseErrorBenchmarkShard(std::string_view text);

struct ErrorBenchmarkOptions {
  std::filesystem::path scene;
  std::filesystem::path reference;  // empty: render out/reference.exr at referenceSpp (or reuse it)
  std::filesystem::path out = "bench-error";
  // Render seconds per row (default 1, 2, 4, 8, 16), or with sppBudgets samples per pixel.
  std::vector<double> budgets;
  bool sppBudgets = false;
  // The strategy lists; empty: every strategy (samplers: the scene's own).
  std::vector<BrdfSampling> bsdf;
  std::vector<EnvironmentSampling> env;
  std::vector<MisMode> mis;
  std::vector<SamplerKind> samplers;
  std::vector<DirectLighting> direct;  // empty: mis only (product's M and b: the scene's)
  uint32_t referenceSpp = 1024;
  uint32_t seeds = 4;
  uint32_t threads = 0;     // 0: all cores
  double targetRelMse = 0;  // 0: the least relMSE of any strategy at the smallest budget
  std::optional<ErrorBenchmarkShard> shard;
  // Progress and warnings, one line each; may be empty.
  std::function<void(const std::string& line)> log;
  // How a row or the reference is rendered, for `seconds` (else the scene's sample count); empty:
  // render() as is. A command line passes one that draws a progress bar.
  std::function<RenderStats(const Scene&, Film&, std::optional<double> seconds)> render;
};

// Throws OptionError: budgets not positive and finite (whole numbers >= 1 of spp), seeds or
// referenceSpp 0.
void validate(const ErrorBenchmarkOptions& options);

// What a run or a merge did, for a summary.
struct ErrorBenchmarkReport {
  std::size_t strategies = 0, budgets = 0;  // the matrix
  std::vector<SkippedStrategy> skipped;     // left out as identical to a rendered strategy
  std::string reference, referenceOrigin;   // its file; "given", "1024 spp, reused", ...
  std::size_t rendered = 0, kept = 0;       // rows rendered now, rows kept from an earlier run
  std::size_t shardsMerged = 0, rows = 0;   // a merge's
  std::string scene;                        // a merge's: the scene the shards rendered
  std::size_t differenceImages = 0;
};

// `cache`: where built tables are read and stored (TableCache::disabled() for none).
ErrorBenchmarkReport runErrorBenchmark(const ErrorBenchmarkOptions& options, TableCache cache);

// The shards' output directories, every one of a split, into `out`. Throws FileError for a
// directory without results or of another run, OptionError (option "merge") for a shard missing.
ErrorBenchmarkReport mergeErrorBenchmark(const std::vector<std::filesystem::path>& shards,
                                         const std::filesystem::path& out, double targetRelMse = 0);

}  // namespace acdf

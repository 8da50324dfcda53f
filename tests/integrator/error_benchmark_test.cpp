// The error-against-time benchmark as a library (acdf/experiments/error_benchmark.h): its option
// checks, its shard syntax, and a run in process that renders exactly the matrix it reports
// through the renderer it is given, logging a line per row. The command line's behaviour (resume,
// the reference, merging, plots, bad input) is tested in tests/apps/bench_error_test.cpp.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acdf/experiments/error_benchmark.h"
#include "acdf/sampling/option_error.h"
#include "app_test_util.h"

namespace acdf {
namespace {

namespace fs = std::filesystem;

std::string optionRejected(const ErrorBenchmarkOptions& options) {
  try {
    validate(options);
  } catch (const OptionError& e) {
    return e.option();
  }
  return "";
}

TEST(ErrorBenchmark, OptionsAreChecked) {
  ErrorBenchmarkOptions options;
  EXPECT_EQ(optionRejected(options), "");
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    options.budgets = {1, bad};
    EXPECT_EQ(optionRejected(options), "budgets") << bad;
  }
  options.sppBudgets = true;
  options.budgets = {4, 1.5};
  EXPECT_EQ(optionRejected(options), "spp_budgets");
  options.budgets = {4, 64};
  EXPECT_EQ(optionRejected(options), "");
  options.seeds = 0;
  EXPECT_EQ(optionRejected(options), "seeds");
  options.seeds = 1;
  options.referenceSpp = 0;
  EXPECT_EQ(optionRejected(options), "reference_spp");
  options.referenceSpp = 1;
  options.shard = ErrorBenchmarkShard{3, 2};
  EXPECT_EQ(optionRejected(options), "shard");
}

TEST(ErrorBenchmark, ShardsSplitTheRows) {
  const ErrorBenchmarkShard second = parseErrorBenchmarkShard("2/3");
  EXPECT_EQ(second.k, 2u);
  EXPECT_EQ(second.n, 3u);
  EXPECT_FALSE(second.has(0));
  EXPECT_TRUE(second.has(1));
  EXPECT_TRUE(second.has(4));
  for (const char* bad : {"", "0/2", "3/2", "2", "1/0", "a/b", "1/2x", "-1/2", "1/2/3"})
    EXPECT_THROW(parseErrorBenchmarkShard(bad), OptionError) << bad;
}

class ErrorBenchmarkRun : public apptest::TempDirTest {};

// A diffuse sphere under a constant sky: 2 spp, depth 2, plus `render` settings.
nlohmann::json greySphereUnderConstantSky(int width, int height, const nlohmann::json& render) {
  nlohmann::json scene = {
      {"camera", {{"eye", {0, 0.6, 4}}, {"target", {0, 0.3, 0}}, {"fov", 40}, {"width", width}, {"height", height}}},
      {"render", {{"spp", 2}, {"seed", 3}, {"max_depth", 2}}},
      {"environment", {{"type", "constant"}, {"radiance", 1.0}}},
      {"materials", {{"grey", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}, {"material", "grey"}}}},
  };
  scene["render"].update(render);
  return scene;
}

TEST_F(ErrorBenchmarkRun, RendersTheMatrixItReportsThroughTheGivenRenderer) {
  apptest::writeFile(path("scene.json"), greySphereUnderConstantSky(16, 8, nlohmann::json::object()).dump(2));

  ErrorBenchmarkOptions options;
  options.scene = path("scene.json");
  options.out = path("out");
  options.sppBudgets = true;
  options.budgets = {2, 1, 2};  // sorted, repeats dropped
  options.mis = {MisMode::Power, MisMode::BsdfOnly};
  options.seeds = 2;
  options.referenceSpp = 8;
  std::vector<std::string> lines;
  options.log = [&](const std::string& line) { lines.push_back(line); };
  std::vector<uint32_t> spp;
  options.render = [&](const Scene& s, Film& film, std::optional<double> seconds) {
    EXPECT_FALSE(seconds) << "spp budgets: no time limit";
    spp.push_back(s.settings.spp);
    return render(s, film);
  };
  const ErrorBenchmarkReport report = runErrorBenchmark(options, TableCache::disabled());

  // No measured material: one BRDF strategy; bsdf-only with the first environment strategy only.
  const std::size_t envs = std::size(kEnvironmentSamplings);
  EXPECT_EQ(report.strategies, envs + 1);
  EXPECT_EQ(report.budgets, 2u);
  EXPECT_EQ(report.rendered, report.strategies * report.budgets);
  EXPECT_EQ(report.kept, 0u);
  EXPECT_EQ(report.referenceOrigin.find("8 spp, rendered"), 0u) << report.referenceOrigin;

  // The reference, then each row's seeds at the row's budget.
  ASSERT_EQ(spp.size(), 1 + report.rendered * options.seeds);
  EXPECT_EQ(spp[0], 8u);
  for (std::size_t i = 1; i < spp.size(); ++i) EXPECT_TRUE(spp[i] == 1 || spp[i] == 2) << spp[i];

  std::ifstream in(fs::path(path("out")) / "results.json");
  const nlohmann::json results = nlohmann::json::parse(in);
  ASSERT_EQ(results["rows"].size(), report.rendered);
  std::size_t rowLines = 0;
  for (const std::string& line : lines) rowLines += line.find(" seeds: ") != std::string::npos;
  EXPECT_EQ(rowLines, report.rendered);
  for (const auto& row : results["rows"]) {
    EXPECT_EQ(row["seeds"], 2);
    EXPECT_GT(row["relmse"].get<double>(), 0);
  }
}

// --direct mis,product: product rows with the first MIS mode only (it uses none), each row naming
// its direct lighting, and the scene's product options in the settings.
TEST_F(ErrorBenchmarkRun, DirectLightingIsAnAxis) {
  apptest::writeFile(path("scene.json"), greySphereUnderConstantSky(8, 4, {{"candidates", 3}}).dump(2));
  ErrorBenchmarkOptions options;
  options.scene = path("scene.json");
  options.out = path("out");
  options.sppBudgets = true;
  options.budgets = {2};
  options.bsdf = {BrdfSampling::Cosine};
  options.env = {EnvironmentSampling::Adaptive};
  options.mis = {MisMode::Power, MisMode::Balance};
  options.direct = {DirectLighting::Mis, DirectLighting::Product};
  options.seeds = 1;
  options.referenceSpp = 4;
  std::vector<DirectLighting> rendered;
  options.render = [&](const Scene& s, Film& film, std::optional<double>) {
    rendered.push_back(s.settings.direct);
    return render(s, film);
  };
  const ErrorBenchmarkReport report = runErrorBenchmark(options, TableCache::disabled());
  EXPECT_EQ(report.strategies, 3u);  // power, balance, product
  ASSERT_EQ(report.skipped.size(), 1u);
  EXPECT_EQ(report.skipped[0].strategy.direct, DirectLighting::Product);
  EXPECT_EQ(report.skipped[0].strategy.mis, MisMode::Balance);
  EXPECT_EQ(std::count(rendered.begin(), rendered.end(), DirectLighting::Product), 1);

  std::ifstream in(fs::path(path("out")) / "results.json");
  const nlohmann::json results = nlohmann::json::parse(in);
  EXPECT_EQ(results["settings"]["product_sampling"]["candidates"], 3);
  std::vector<std::string> directs;
  for (const auto& row : results["rows"]) directs.push_back(row["direct"]);
  EXPECT_EQ(directs, (std::vector<std::string>{"mis", "mis", "product"}));
  EXPECT_TRUE(fs::exists(fs::path(path("out")) / "images" / "cosine_adaptive_product_sobol.exr"));
}

}  // namespace
}  // namespace acdf

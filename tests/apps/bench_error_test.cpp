// `acdf bench-error` end to end on a 32×16 scene (a tabulated gold sphere on a diffuse floor under a
// smooth 64×32 sky the test writes) with sample-count budgets, so every figure is deterministic:
// a row for every strategy combination, error falling with the sample count, the mean and
// standard error over seeds, the time to a target relMSE, CSV and JSON that agree, resuming
// without rendering finished rows, reusing the reference only while it matches, sample sources
// side by side, shards (GNU parallel here and over ssh, a Slurm array) merging to the unsharded
// run, and the bad-input contract (exit 2, one line, nothing written).

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acdf/envmap/image_file.h"
#include "app_test_util.h"

namespace acdf {
namespace {

namespace fs = std::filesystem;
using apptest::expectOneLineFailure;
using apptest::RunResult;

#ifdef ACDF_SANITIZED_BUILD
constexpr const char* kReferenceSpp = "256";
#else
constexpr const char* kReferenceSpp = "1024";
#endif

const std::vector<std::string> kBsdf = {"cosine", "uniform", "adaptive"};
const std::vector<std::string> kEnv = {"uniform-sphere", "uniform",      "alias", "adaptive",
                                       "compensated",    "hierarchical", "local", "local-compensated"};
const std::vector<std::string> kMis = {"power", "balance", "bsdf-only", "light-only"};

using Combination = std::tuple<std::string, std::string, std::string>;  // bsdf, env, mis

class BenchErrorCli : public apptest::TempDirTest {
 protected:
  void SetUp() override {
    apptest::TempDirTest::SetUp();
    ::setenv("XDG_CACHE_HOME", path("cache").c_str(), 1);  // the test's table cache, not the user's
    writeSky(path("sky.exr"), 64, 32);
    writeScene(1);
  }

  // A smooth sky with a soft bright patch (high up to the camera's left, towards −X): the
  // strategies differ, without the fireflies of a sun that would make a single seed's
  // error jump about.
  static void writeSky(const std::string& file, uint32_t width, uint32_t height) {
    Image sky;
    sky.width = width;
    sky.height = height;
    sky.channels = 3;
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const double dx = (x + 0.5) / width - 0.7, dy = (y + 0.5) / height - 0.3;
        const double patch = 4.0 * std::exp(-(dx * dx + dy * dy) / 0.01);
        sky.pixels.insert(sky.pixels.end(), {float(0.3 + patch), float(0.35 + 0.8 * patch), float(0.45 + 0.5 * patch)});
      }
    writeExr(file, sky);
  }

  void writeScene(int seed) {
    const nlohmann::json scene = {
        {"camera", {{"eye", {0, 0.6, 4}}, {"target", {0, 0.3, 0}}, {"fov", 40}, {"width", 32}, {"height", 16}}},
        {"render", {{"spp", 4}, {"seed", seed}, {"max_depth", 4}}},
        {"environment", {{"type", "map"}, {"file", path("sky.exr")}, {"sampling", "adaptive"}}},
        {"materials",
         {{"gold",
           {{"type", "measured"}, {"preset", "gold"}, {"sampling", "adaptive"}, {"table", {{"layout", "isotropic"}}}}},
          {"floor", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
        {"shapes",
         {{{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.5}, {"material", "gold"}},
          {{"type", "quad"},
           {"corner", {-5, 0, -5}},
           {"edge_u", {0, 0, 10}},
           {"edge_v", {10, 0, 0}},
           {"material", "floor"}}}},
    };
    apptest::writeFile(path("scene.json"), scene.dump(2));
  }

  RunResult benchError(std::vector<std::string> extra, const std::string& out = "out") {
    std::vector<std::string> args = {"bench-error", path("scene.json"), "--out",
                                     path(out),     "--reference-spp",  kReferenceSpp};
    args.insert(args.end(), extra.begin(), extra.end());
    return apptest::runAcdf(args, dir_);
  }

  nlohmann::json results(const std::string& out = "out") {
    return nlohmann::json::parse(apptest::readFile(path(out + "/results.json")));
  }

  // The "rows N rendered, M kept" line of the summary.
  static std::pair<int, int> rowCounts(const RunResult& r) {
    const auto at = r.out.find("\nrows ");
    if (at == std::string::npos) return {-1, -1};
    int rendered = -1, kept = -1;
    std::sscanf(r.out.c_str() + at, "\nrows %d rendered, %d kept", &rendered, &kept);
    return {rendered, kept};
  }
};

std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

// A row's figures against those of its seeds (relMSE's stderr = s / √K by hand); adds the seeds.
void expectRowAggregatesItsSeeds(const nlohmann::json& row, std::size_t seeds, std::set<uint64_t>& seedValues) {
  ASSERT_EQ(row["seeds"], seeds);
  ASSERT_EQ(row["per_seed"].size(), seeds);
  double sum = 0, sq = 0;
  for (const auto& render : row["per_seed"]) {
    seedValues.insert(render["seed"].get<uint64_t>());
    EXPECT_EQ(render["spp"].get<double>(), row["budget"].get<double>());
    sum += render["relmse"].get<double>();
  }
  const double mean = sum / double(seeds);
  for (const auto& render : row["per_seed"]) sq += std::pow(render["relmse"].get<double>() - mean, 2);
  const double stderr_ = seeds > 1 ? std::sqrt(sq / double(seeds - 1) / double(seeds)) : 0.0;
  EXPECT_NEAR(row["relmse"].get<double>(), mean, 1e-12 * mean);
  EXPECT_NEAR(row["relmse_stderr"].get<double>(), stderr_, 1e-9 * mean);
  EXPECT_EQ(row["relmse_stderr"].get<double>() > 0, seeds > 1);
  EXPECT_NEAR(row["relmse_trimmed"].get<double>(), mean, 1e-12 * mean) << "512 pixels: none discarded";
  EXPECT_NEAR(row["efficiency"].get<double>(), 1 / (mean * row["seconds"].get<double>()),
              1e-9 * row["efficiency"].get<double>());
  EXPECT_EQ(row["efficiency_stderr"].get<double>() > 0, seeds > 1);
}

TEST_F(BenchErrorCli, EveryCombinationErrorFallsCsvMatchesJsonAndASecondRunRendersNothing) {
  // Two seeds a row: the error falls with the sample count on their mean (a single seed's firefly
  // can break that), and 225 rows stay fast. The resume test runs the default four.
  const RunResult first = benchError({"--spp-budgets", "1,8,64", "--no-plot", "--seeds", "2"});
  ASSERT_EQ(first.exitCode, 0) << apptest::describe(first);

  // The combinations: all of them, minus those identical by construction.
  std::set<Combination> expected;
  for (const auto& m : kMis)
    for (const auto& b : kBsdf)
      for (const auto& e : kEnv)
        if (!(m == "bsdf-only" && e != "uniform-sphere")) expected.insert({b, e, m});
  ASSERT_EQ(expected.size(), 75u);

  const nlohmann::json j = results();
  EXPECT_EQ(j["skipped"].size(), 96u - 75u);
  const auto& rows = j["rows"];
  ASSERT_EQ(rows.size(), 3 * expected.size());
  std::map<Combination, std::map<double, nlohmann::json>> byCombination;
  std::set<uint64_t> seeds;
  for (const auto& row : rows) {
    byCombination[{row["bsdf_sampling"], row["env_sampling"], row["mis"]}][row["budget"].get<double>()] = row;
    expectRowAggregatesItsSeeds(row, 2, seeds);
    EXPECT_EQ(row["spp"].get<double>(), row["budget"].get<double>());
    EXPECT_EQ(row["table_bytes"], row["brdf_table_bytes"].get<uint64_t>() + row["env_table_bytes"].get<uint64_t>());
    EXPECT_GT(row["relmse"].get<double>(), 0);
    EXPECT_GT(row["rmse"].get<double>(), 0);
  }
  EXPECT_EQ(seeds.size(), 2 * rows.size()) << "every render has its own seed";
  ASSERT_EQ(byCombination.size(), expected.size());
  std::size_t strictlyFalling = 0;
  for (const auto& entry : byCombination) {
    // Named references, not structured bindings: the lambdas below capture them (clang 14).
    const auto& combination = entry.first;
    const auto& budgets = entry.second;
    const std::string& bsdf = std::get<0>(combination);
    const std::string& env = std::get<1>(combination);
    const std::string& mis = std::get<2>(combination);
    EXPECT_TRUE(expected.contains(combination)) << bsdf << " " << env << " " << mis;
    ASSERT_EQ(budgets.size(), 3u);
    // The error falls with the sample count: beyond doubt over 64× the samples; over 8× within
    // two standard errors, as a firefly in one seed (cosine sampling of the gold) can lift a mean.
    const auto e = [&](double spp) { return budgets.at(spp)["relmse"].get<double>(); };
    const auto se = [&](double spp) { return budgets.at(spp)["relmse_stderr"].get<double>(); };
    EXPECT_LT(e(64), e(1)) << bsdf << " " << env << " " << mis;
    EXPECT_LT(e(64) - 2 * se(64), e(8) + 2 * se(8)) << bsdf << " " << env << " " << mis;
    EXPECT_LT(e(8) - 2 * se(8), e(1) + 2 * se(1)) << bsdf << " " << env << " " << mis;
    strictlyFalling += e(64) < e(8) && e(8) < e(1);
    // Table memory: none without tables; the adaptive BRDF table is the smaller one.
    const auto bytes = [&](const std::string& b, const std::string& e) {
      return byCombination.at({b, e, mis}).at(64)["brdf_table_bytes"].get<uint64_t>();
    };
    EXPECT_EQ(budgets.at(64)["brdf_table_bytes"].get<uint64_t>() == 0, bsdf == "cosine");
    EXPECT_EQ(budgets.at(64)["env_table_bytes"].get<uint64_t>() == 0, env == "uniform-sphere");
    if (bsdf == "adaptive") {
      EXPECT_LT(bytes("adaptive", env), bytes("uniform", env));
    }
    EXPECT_EQ(budgets.at(64)["sampler"], "sobol") << "the scene's sampler";
    EXPECT_TRUE(fs::is_regular_file(path("out/images/" + bsdf + "_" + env + "_" + mis + "_sobol.exr")));
    EXPECT_TRUE(fs::is_regular_file(path("out/diff/" + bsdf + "_" + env + "_" + mis + "_sobol.png")));
  }
  EXPECT_GE(strictlyFalling, 50u) << "of 57 combinations";
  EXPECT_TRUE(fs::is_regular_file(path("out/diff/env-adaptive-vs-uniform_adaptive_power_sobol.png")));
  EXPECT_TRUE(fs::is_regular_file(path("out/diff/bsdf-adaptive-vs-uniform_hierarchical_balance_sobol.png")));

  // Time to the target relMSE, by default the least at the smallest budget: the strategy that
  // reached it needs exactly that row's time; every other one crosses it later along its own
  // rows, or is extrapolated because it stays above it.
  double target = INFINITY;
  for (const auto& row : rows)
    if (row["budget"] == 1) target = std::min(target, row["relmse"].get<double>());
  EXPECT_EQ(j["target_relmse"].get<double>(), target);
  ASSERT_EQ(j["curves"].size(), expected.size());
  std::size_t atTheTarget = 0;
  for (const auto& curve : j["curves"]) {
    const auto& budgets = byCombination.at({curve["bsdf_sampling"], curve["env_sampling"], curve["mis"]});
    const double t = curve["time_to_target"].get<double>();
    EXPECT_GT(curve["time_to_target_stderr"].get<double>(), 0);
    if (budgets.at(1)["relmse"] == target) {
      ++atTheTarget;
      EXPECT_NEAR(t, budgets.at(1)["seconds"].get<double>(), 1e-9 * t);
    } else if (curve["time_to_target_extrapolated"]) {
      EXPECT_GT(budgets.at(64)["relmse"].get<double>(), target) << curve;
      EXPECT_GT(t, budgets.at(64)["seconds"].get<double>()) << curve;
    } else {
      EXPECT_GT(t, budgets.at(1)["seconds"].get<double>()) << curve;
      EXPECT_LE(t, budgets.at(64)["seconds"].get<double>()) << curve;
    }
  }
  EXPECT_EQ(atTheTarget, 1u);
  EXPECT_EQ(parseCsv(apptest::readFile(path("out/curves.csv"))).size(), expected.size() + 1);

  // results.csv: the same rows, the same figures.
  const auto csv = parseCsv(apptest::readFile(path("out/results.csv")));
  ASSERT_EQ(csv.size(), rows.size() + 1);
  const std::vector<std::string>& header = csv[0];
  ASSERT_EQ(header.size(), 25u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(csv[i + 1].size(), header.size());
    for (std::size_t c = 0; c < header.size(); ++c) {
      const nlohmann::json& value = rows[i].at(header[c]);
      if (value.is_string())
        EXPECT_EQ(csv[i + 1][c], value.get<std::string>()) << header[c];
      else
        EXPECT_NEAR(std::stod(csv[i + 1][c]), value.get<double>(), 1e-7 * std::abs(value.get<double>())) << header[c];
    }
  }

  // Nothing new to render: every row is kept, the reference reused.
  const RunResult second = benchError({"--spp-budgets", "1,8,64", "--no-plot", "--seeds", "2"});
  ASSERT_EQ(second.exitCode, 0) << apptest::describe(second);
  EXPECT_EQ(rowCounts(first), std::make_pair(225, 0));
  EXPECT_EQ(rowCounts(second), std::make_pair(0, 225));
  EXPECT_NE(second.out.find("reused"), std::string::npos) << second.out;
  EXPECT_EQ(results()["rows"], rows);
}

TEST_F(BenchErrorCli, ResumeRendersOnlyTheRowsMissing) {
  const std::vector<std::string> small = {"--spp-budgets",    "1,4",      "--no-plot",
                                          "--bsdf-sampling",  "adaptive", "--env-sampling",
                                          "uniform,adaptive", "--mis",    "power"};
  const RunResult first = benchError(small);
  ASSERT_EQ(first.exitCode, 0) << apptest::describe(first);
  EXPECT_EQ(rowCounts(first), std::make_pair(4, 0));
  const nlohmann::json complete = results();
  std::set<uint64_t> seeds;
  for (const auto& row : complete["rows"]) expectRowAggregatesItsSeeds(row, 4, seeds);
  EXPECT_EQ(seeds.size(), 16u) << "four seeds a row, each its own";

  // A run stopped after its second row: the rows on disk are those finished.
  nlohmann::json stopped = complete;
  stopped["rows"].erase(stopped["rows"].begin() + 2, stopped["rows"].end());
  apptest::writeFile(path("out/results.json"), stopped.dump(2));
  const RunResult resumed = benchError(small);
  ASSERT_EQ(resumed.exitCode, 0) << apptest::describe(resumed);
  EXPECT_EQ(rowCounts(resumed), std::make_pair(2, 2));
  const nlohmann::json resumedResults = results();
  const nlohmann::json& again = resumedResults["rows"];
  ASSERT_EQ(again.size(), complete["rows"].size());
  for (std::size_t i = 0; i < again.size(); ++i)
    for (const char* key : {"bsdf_sampling", "env_sampling", "budget", "seeds", "spp", "relmse", "relmse_stderr",
                            "relmse_trimmed", "rmse", "table_bytes"})
      EXPECT_EQ(again[i][key], complete["rows"][i][key])
          << "row " << i << " " << key << ": the same seed, the same row";
  for (std::size_t i = 0; i < again.size(); ++i)
    for (std::size_t k = 0; k < 4; ++k)
      EXPECT_EQ(again[i]["per_seed"][k]["seed"], complete["rows"][i]["per_seed"][k]["seed"]) << "row " << i;

  // A wider matrix keeps the rows it shares with the earlier one.
  std::vector<std::string> wider = small;
  wider.back() = "power,balance";
  const RunResult more = benchError(wider);
  ASSERT_EQ(more.exitCode, 0) << apptest::describe(more);
  EXPECT_EQ(rowCounts(more), std::make_pair(4, 4));

  // Another number of seeds: other rows, rendered afresh.
  std::vector<std::string> fewer = small;
  fewer.insert(fewer.end(), {"--seeds", "1"});
  const RunResult reseeded = benchError(fewer);
  ASSERT_EQ(reseeded.exitCode, 0) << apptest::describe(reseeded);
  EXPECT_EQ(rowCounts(reseeded), std::make_pair(4, 0));
  EXPECT_NE(reseeded.err.find("starting afresh"), std::string::npos) << reseeded.err;
}

TEST_F(BenchErrorCli, ReferenceIsReusedOnlyWhileItMatches) {
  const std::vector<std::string> small = {
      "--spp-budgets", "1,4", "--no-plot", "--bsdf-sampling", "cosine", "--env-sampling", "adaptive", "--mis", "power"};
  ASSERT_EQ(benchError(small).exitCode, 0);
  const nlohmann::json info = nlohmann::json::parse(apptest::readFile(path("out/reference.json")));
  EXPECT_EQ(info["spp"], std::stoi(kReferenceSpp));
  EXPECT_EQ(info["width"], 32);
  EXPECT_EQ(info["height"], 16);
  EXPECT_EQ(info["scene_hash"].get<std::string>().size(), 32u);

  // Another scene text: a new reference, and the earlier rows no longer count.
  writeScene(2);
  const RunResult changed = benchError(small);
  ASSERT_EQ(changed.exitCode, 0) << apptest::describe(changed);
  EXPECT_NE(changed.out.find("rendered in"), std::string::npos) << changed.out;
  EXPECT_EQ(rowCounts(changed), std::make_pair(2, 0));
  EXPECT_NE(nlohmann::json::parse(apptest::readFile(path("out/reference.json")))["scene_hash"], info["scene_hash"]);

  // A given reference of the right size is used as it is.
  fs::copy_file(path("out/reference.exr"), path("given.exr"));
  const RunResult given = benchError({"--spp-budgets", "1", "--no-plot", "--bsdf-sampling", "cosine", "--env-sampling",
                                      "adaptive", "--mis", "power", "--reference", path("given.exr")},
                                     "given-out");
  ASSERT_EQ(given.exitCode, 0) << apptest::describe(given);
  EXPECT_NE(given.out.find("(given)"), std::string::npos) << given.out;
  EXPECT_FALSE(fs::exists(path("given-out/reference.exr")));

  // One of another size: exit 2, nothing written.
  writeSky(path("small.exr"), 8, 8);
  const RunResult mismatch = benchError({"--spp-budgets", "1", "--reference", path("small.exr")}, "mismatch-out");
  expectOneLineFailure(mismatch, "acdf: " + path("small.exr") + ": ", "the reference is 8x8 but");
  EXPECT_FALSE(fs::exists(path("mismatch-out")));
}

TEST_F(BenchErrorCli, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const RunResult missing = apptest::runAcdf({"bench-error", path("nope.json"), "--out", path("out")}, dir_);
  expectOneLineFailure(missing, "acdf: " + path("nope.json") + ": ", "no such file");
  EXPECT_FALSE(fs::exists(path("out")));

  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"--budgets", "0"},
                                             {"--budgets", "1,-2"},
                                             {"--budgets", "abc"},
                                             {"--spp-budgets", "0"},
                                             {"--seeds", "0"},
                                             {"--shard", "0/2"},
                                             {"--shard", "3/2"},
                                             {"--shard", "2"},
                                             {"--shard", "1/0"},
                                             {"--shard", "a/b"},
                                             {"--shard", "1/2x"},
                                             {"--budgets", "1", "--spp-budgets", "2"},
                                             {"--env-sampling", "sunny"},
                                             {"--mis", "both"}}) {
    const RunResult r = benchError(bad);
    EXPECT_EQ(r.exitCode, 2) << bad[0] << " " << bad[1] << ": " << apptest::describe(r);
    EXPECT_EQ(r.errLines().size(), 1u) << apptest::describe(r);
    EXPECT_FALSE(fs::exists(path("out")));
  }

  apptest::writeFile(path("a-file"), "x");
  expectOneLineFailure(benchError({"--spp-budgets", "1"}, "a-file"), "acdf: " + path("a-file") + ": ",
                       "not a directory");
  expectOneLineFailure(benchError({"--spp-budgets", "1"}, "no/such/dir"), "acdf: " + path("no/such/dir") + ": ",
                       "parent directory does not exist");
  EXPECT_FALSE(fs::exists(path("no")));
  if (::geteuid() != 0) {  // root writes anywhere
    fs::create_directory(path("readonly"));
    fs::permissions(path("readonly"), fs::perms::owner_read | fs::perms::owner_exec);
    expectOneLineFailure(benchError({"--spp-budgets", "1"}, "readonly/out"), "acdf: " + path("readonly/out") + ": ",
                         "not writable");
    fs::permissions(path("readonly"), fs::perms::owner_all);
  }
}

TEST_F(BenchErrorCli, APlotFailureKeepsTheResultsAndSaysWhy) {
  const RunResult r = benchError({"--spp-budgets", "1", "--bsdf-sampling", "cosine", "--env-sampling", "adaptive",
                                  "--mis", "power", "--python", path("no-python")});
  EXPECT_EQ(r.exitCode, 3) << apptest::describe(r);
  EXPECT_NE(r.err.find("plotting failed (cannot run " + path("no-python") + ")"), std::string::npos) << r.err;
  EXPECT_EQ(results()["rows"].size(), 1u);
}

// The figures of a row that do not depend on the clock or the table cache.
nlohmann::json deterministic(const nlohmann::json& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& row : rows) {
    nlohmann::json r;
    for (const char* key :
         {"row", "bsdf_sampling", "env_sampling", "mis", "sampler", "budget", "seeds", "spp", "relmse", "relmse_stderr",
          "relmse_trimmed", "relmse_trimmed_stderr", "rmse", "rmse_stderr", "table_bytes"})
      r[key] = row.at(key);
    for (const auto& seed : row.at("per_seed")) r["per_seed"].push_back({seed.at("seed"), seed.at("relmse")});
    out.push_back(r);
  }
  return out;
}

TEST_F(BenchErrorCli, TwoShardsMergeToTheUnshardedRun) {
  // 2 strategies x 3 budgets: the shards split each strategy's budgets between them.
  const std::vector<std::string> small = {"--spp-budgets",   "1,2,4",           "--seeds", "2",
                                          "--bsdf-sampling", "adaptive",        "--mis",   "power",
                                          "--env-sampling",  "uniform,adaptive"};
  std::vector<std::string> whole = small;
  whole.push_back("--no-plot");
  const RunResult unsharded = benchError(whole, "whole");
  ASSERT_EQ(unsharded.exitCode, 0) << apptest::describe(unsharded);

  // The shards at once with GNU parallel when it is there (else one after the other), measured
  // against the unsharded run's reference (rendered once, as across machines), then merged.
  std::string command = "ACDF=" + apptest::acdfExe() + " " + apptest::sourceDir() +
                        "/scripts/bench-error-parallel --no-plot 2 " + path("sharded") + " " + path("scene.json") +
                        " --reference " + path("whole/reference.exr");
  for (const std::string& a : small) command += " " + a;
  command += " >" + path("parallel.out") + " 2>" + path("parallel.err");
  ASSERT_EQ(std::system(command.c_str()), 0) << apptest::readFile(path("parallel.err"));
  const nlohmann::json merged = results("sharded"), reference = results("whole");
  EXPECT_EQ(results("sharded/shard-1")["rows"].size(), 3u);
  EXPECT_EQ(results("sharded/shard-2")["rows"].size(), 3u);
  ASSERT_EQ(merged["rows"].size(), 6u);
  EXPECT_EQ(deterministic(merged["rows"]), deterministic(reference["rows"]));
  nlohmann::json mergedSettings = merged["settings"], unshardedSettings = reference["settings"];
  mergedSettings.erase("reference");  // its render time
  unshardedSettings.erase("reference");
  EXPECT_EQ(mergedSettings, unshardedSettings);
  EXPECT_EQ(apptest::readFile(path("sharded/results.csv")).substr(0, 100),
            apptest::readFile(path("whole/results.csv")).substr(0, 100));
  for (const char* image :
       {"images/adaptive_uniform_power_sobol.exr", "images/adaptive_adaptive_power_sobol.exr",
        "diff/adaptive_adaptive_power_sobol.png",
        "diff/env-adaptive-vs-uniform_adaptive_power_sobol.png"}) {
    EXPECT_TRUE(fs::is_regular_file(path(std::string("sharded/") + image))) << image;
    EXPECT_TRUE(readImage(path(std::string("sharded/") + image)).pixels ==
                readImage(path(std::string("whole/") + image)).pixels)
        << image;
  }

  // Over ssh, as across machines: two hosts of an ssh login file, reached through a stand-in
  // for ssh that runs the remote command here as ssh would (its arguments joined, given to a
  // shell), so the quoting GNU parallel adds for the remote side is exercised (the output
  // directory's name has a space). sshd sets SHELL to the login shell, and GNU parallel's remote
  // side runs the command with $SHELL: without it, nothing runs and parallel still exits 0.
  if (std::system("command -v parallel >/dev/null 2>&1") == 0) {
    apptest::writeFile(
        path("fake-ssh"),
        "#!/usr/bin/env bash\n"
        "while [[ $# -gt 0 && $1 == -* ]]; do case $1 in -o|-p|-l|-i|-F) shift 2;; *) shift;; esac; done\n"
        "echo \"$1\" >> " +
            path("ssh-hosts") +
            "\n"
            "shift; [[ ${1-} == -- ]] && shift\n"
            "SHELL=$(getent passwd \"$(id -u)\" | cut -d: -f7) && export SHELL=${SHELL:-/bin/sh}\n"
            "exec bash -c \"$*\"\n");
    fs::permissions(path("fake-ssh"), fs::perms::owner_all);
    apptest::writeFile(path("logins"), path("fake-ssh") + " host-a\n" + path("fake-ssh") + " host-b\n");
    std::string overSsh = "ACDF=" + apptest::acdfExe() + " " + apptest::sourceDir() +
                          "/scripts/bench-error-parallel --sshloginfile " + path("logins") + " --no-plot 2 '" +
                          path("over ssh") + "' " + path("scene.json") + " --reference " + path("whole/reference.exr");
    for (const std::string& a : small) overSsh += " " + a;
    overSsh += " >" + path("ssh.out") + " 2>" + path("ssh.err");
    ASSERT_EQ(std::system(overSsh.c_str()), 0) << apptest::readFile(path("ssh.err"));
    EXPECT_EQ(deterministic(results("over ssh")["rows"]), deterministic(reference["rows"]));
    const std::string hosts = apptest::readFile(path("ssh-hosts"));
    EXPECT_NE(hosts.find("host-a"), std::string::npos) << hosts;
    EXPECT_NE(hosts.find("host-b"), std::string::npos) << hosts;
  } else {
    std::cout << "[ SKIPPED ] the run over ssh: no GNU parallel (apt-get install parallel)\n";
  }

  // As a Slurm array job: each task as Slurm starts it (its array variables set), then the merge
  // the dependent job runs.
  for (int task = 1; task <= 2; ++task) {
    std::string slurm =
        "SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
        " SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=2 SLURM_CPUS_PER_TASK=1 ACDF=" + apptest::acdfExe() + " " +
        apptest::sourceDir() + "/scripts/bench-error-slurm.sh " + path("slurm") + " " + path("scene.json") +
        " --reference " + path("whole/reference.exr");
    for (const std::string& a : small) slurm += " " + a;
    slurm += " >" + path("slurm.out") + " 2>" + path("slurm.err");
    ASSERT_EQ(std::system(slurm.c_str()), 0) << apptest::readFile(path("slurm.err"));
  }
  ASSERT_EQ(apptest::runAcdf({"bench-error", "--merge", path("slurm/shard-1"), path("slurm/shard-2"), "--out",
                              path("slurm"), "--no-plot"},
                             dir_)
                .exitCode,
            0);
  EXPECT_EQ(deterministic(results("slurm")["rows"]), deterministic(reference["rows"]));

  // Shards of other runs, a shard missing or given twice: exit 2, naming the problem.
  std::vector<std::string> other = small;
  other[3] = "1";
  other.insert(other.end(), {"--shard", "2/2", "--no-plot"});
  ASSERT_EQ(benchError(other, "other").exitCode, 0);
  const auto mergeOf = [&](std::vector<std::string> dirs) {
    std::vector<std::string> args = {"bench-error", "--out", path("merged"), "--no-plot", "--merge"};
    for (const std::string& d : dirs) args.push_back(path(d));
    return apptest::runAcdf(args, dir_);
  };
  expectOneLineFailure(mergeOf({"sharded/shard-1", "other"}), "acdf: " + path("other/results.json") + ": ",
                       "its seeds (1) differs from that of " + path("sharded/shard-1") + " (2)");
  expectOneLineFailure(mergeOf({"sharded/shard-1"}), "acdf: ", "--merge misses shard 2/2");
  expectOneLineFailure(mergeOf({"sharded/shard-1", "sharded/shard-1"}), "acdf: ", "shard 1/2 is given twice");
  expectOneLineFailure(mergeOf({"whole"}), "acdf: ", "not a shard");
  expectOneLineFailure(mergeOf({"nothing"}), "acdf: " + path("nothing/results.json") + ": ", "no results");
  EXPECT_FALSE(fs::exists(path("merged")));
}

TEST_F(BenchErrorCli, SampleSourcesAreComparedSideBySide) {
  // One strategy under both sample sources: each its own rows, seeds and image; the Sobol
  // points' stratification lowers the error at 64 spp on the smooth sky.
  const RunResult r =
      benchError({"--spp-budgets", "4,64", "--seeds", "2", "--no-plot", "--bsdf-sampling", "adaptive", "--env-sampling",
                  "adaptive", "--mis", "power", "--sampler", "independent,sobol,sobol"});
  ASSERT_EQ(r.exitCode, 0) << apptest::describe(r);
  const nlohmann::json j = results();
  ASSERT_EQ(j["rows"].size(), 4u);
  std::map<std::string, double> relMseAt64;
  for (const auto& row : j["rows"])
    if (row["budget"] == 64) relMseAt64[row["sampler"]] = row["relmse"].get<double>();
  ASSERT_EQ(relMseAt64.size(), 2u);
  EXPECT_LT(relMseAt64["sobol"], 0.5 * relMseAt64["independent"]);  // 0.19× (0.29× at 256 reference spp)
  EXPECT_EQ(j["settings"]["strategies"],
            nlohmann::json({"adaptive_adaptive_power_independent", "adaptive_adaptive_power_sobol"}));
  EXPECT_NE(readImage(path("out/images/adaptive_adaptive_power_independent.exr")).pixels,
            readImage(path("out/images/adaptive_adaptive_power_sobol.exr")).pixels);
  expectOneLineFailure(benchError({"--spp-budgets", "1", "--sampler", "halton"}, "bad"), "acdf: ", "--sampler");
  EXPECT_FALSE(fs::exists(path("bad")));
}

bool haveMatplotlib() { return std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0; }

TEST_F(BenchErrorCli, PlotsAndTheDocsSectionAreWritten) {
  if (!haveMatplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib (apt-get install python3-matplotlib)";
  const RunResult r = benchError({"--spp-budgets", "1,4", "--bsdf-sampling", "uniform,adaptive", "--env-sampling",
                                  "uniform,adaptive", "--mis", "power,bsdf-only"});
  ASSERT_EQ(r.exitCode, 0) << apptest::describe(r);
  for (const char* png : {"out/error_vs_time.png", "out/memory_vs_error.png"}) {
    ASSERT_TRUE(fs::is_regular_file(path(png))) << png;
    EXPECT_EQ(apptest::readFile(path(png)).substr(1, 3), "PNG") << png;
  }

  // The docs section: between its markers, the same after a second run.
  apptest::writeFile(path("doc.md"),
                     "# Doc\n\nbefore\n<!-- bench-error: begin -->\nold\n<!-- bench-error: end -->\nafter\n");
  const std::string command = "/usr/bin/python3 " + apptest::sourceDir() + "/bench/error_report.py docs " +
                              path("out/results.json") + " " + path("doc.md") + " " + path("images") +
                              " --command 'acdf bench-error ...' >/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const std::string once = apptest::readFile(path("doc.md"));
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(apptest::readFile(path("doc.md")), once);
  EXPECT_EQ(once.find("old"), std::string::npos);
  EXPECT_NE(once.find("before\n<!-- bench-error: begin -->"), std::string::npos);
  EXPECT_NE(once.find("<!-- bench-error: end -->\nafter"), std::string::npos);
  EXPECT_NE(once.find("| adaptive | adaptive | power | sobol |"), std::string::npos) << once;
  EXPECT_NE(once.find("](images/error_vs_time.png)"), std::string::npos) << once;
  EXPECT_TRUE(fs::is_regular_file(path("images/env-adaptive-vs-uniform_adaptive_power_sobol.png")));
}

}  // namespace
}  // namespace acdf

// End-to-end tests of the BRDF commands: `acdf brdf-stats` (the keys and their consistency, the
// library's default table, the table form) and `acdf chi2 --brdf` (every sampler passes on a
// generated GGX table), and their bad input (exit 2, one line on stderr, nothing on stdout, no
// file written). Sample counts and resolutions are small: the suite also runs under ASan.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acdf/brdf/reflectance_estimator.h"
#include "acdf/brdf/table_options.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "app_test_util.h"

namespace acdf::apptest {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A small isotropic table (16 θo × 64 θh × 16 Δφ cells, 8 of them stored when mirrored): quick to
// tabulate, still enough cells for the simplifier to compress.
const std::vector<std::string> kSmallIso = {"--table", "isotropic", "--res", "16x64x16", "--samples", "256"};

class BrdfCli : public TempDirTest {
 protected:
  // One generated material for the whole suite (merl-gen takes a second, more under ASan).
  static void SetUpTestSuite() {
    suiteDir_ = fs::temp_directory_path() / ("acdf_brdf_cli_" + std::to_string(::getpid()));
    fs::create_directories(suiteDir_);
    const RunResult r = runAcdf({"merl-gen", "--preset", "gold", "-o", gold()}, suiteDir_);
    ASSERT_EQ(r.exitCode, 0) << describe(r);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(suiteDir_, ec);
  }
  static std::string gold() { return (suiteDir_ / "gold.binary").string(); }

  RunResult run(const std::vector<std::string>& args) { return runAcdf(args, dir_); }

  std::vector<std::string> stats(const std::string& file, std::vector<std::string> extra) {
    std::vector<std::string> args = {"brdf-stats", file};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

  json runJson(const std::vector<std::string>& args) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_TRUE(r.err.empty()) << describe(r);
    try {
      return json::parse(r.out);
    } catch (const json::exception& e) {
      ADD_FAILURE() << "not JSON (" << e.what() << "): " << describe(r);
      return json::object();
    }
  }

  // Bad input: exit 2 with one line, and no file left in the test's directory (runAcdf puts its
  // stdout/stderr captures there, so those are all it may hold).
  void expectFailure(const std::vector<std::string>& args, const std::string& prefix, const std::string& needle) {
    const RunResult r = run(args);
    expectOneLineFailure(r, "acdf: " + prefix, needle);
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "stdout.txt" || name == "stderr.txt" || name.ends_with(".binary"))
          << "file left behind: " << name;
    }
  }

  static fs::path suiteDir_;
};

fs::path BrdfCli::suiteDir_;

TEST_F(BrdfCli, StatsJsonKeysAreConsistent) {
  std::vector<std::string> args = stats(gold(), kSmallIso);
  args.push_back("--json");
  const json j = runJson(args);
  ASSERT_TRUE(j.is_object()) << j;
  for (const char* key : {"uniform_res", "adaptive_avg_res", "uniform_bytes", "adaptive_bytes", "compression",
                          "build_ms", "tabulation_ms", "cosine", "uniform", "adaptive"})
    ASSERT_TRUE(j.contains(key)) << key << " missing in " << j.dump(2);

  // The mirrored isotropic table stores half of the 16 Δφ cells.
  EXPECT_EQ(j["uniform_res"], json({16, 64, 8})) << j.dump(2);
  const auto adaptiveRes = j["adaptive_avg_res"].get<std::vector<double>>();
  ASSERT_EQ(adaptiveRes.size(), 3u);
  EXPECT_EQ(adaptiveRes[0], 16);  // the conditioning axis is not simplified
  EXPECT_LT(adaptiveRes[1], 64);
  EXPECT_LE(adaptiveRes[2], 8);

  const auto uniformBytes = j["uniform_bytes"].get<double>(), adaptiveBytes = j["adaptive_bytes"].get<double>();
  EXPECT_LT(adaptiveBytes, uniformBytes);
  EXPECT_NEAR(j["compression"].get<double>(), uniformBytes / adaptiveBytes, 1e-9 * uniformBytes / adaptiveBytes);
  EXPECT_EQ(j["uniform"]["bytes"], j["uniform_bytes"]);
  EXPECT_EQ(j["adaptive"]["bytes"], j["adaptive_bytes"]);
  EXPECT_EQ(j["adaptive"]["build_ms"], j["build_ms"]);
  EXPECT_EQ(j["adaptive"]["tabulation_ms"], j["tabulation_ms"]);
  EXPECT_EQ(j["estimator"]["samples_per_direction"], 256);

  for (const char* sampler : {"cosine", "uniform", "adaptive"}) {
    const json& s = j[sampler];
    SCOPED_TRACE(sampler);
    // A gold conductor reflects most of the light: an albedo in (0, 1], positive variance.
    EXPECT_GT(s["mean"].get<double>(), 0.1) << s;
    EXPECT_LT(s["mean"].get<double>(), 1.05) << s;
    EXPECT_GT(s["variance"].get<double>(), 0) << s;
    EXPECT_GT(s["ns_per_sample"].get<double>(), 0) << s;
    // No sample can be below the mean of a positive estimator everywhere.
    EXPECT_GT(s["max_weight"].get<double>(), 1.0) << s;
    const double efficiency = s["efficiency"].get<double>();
    EXPECT_NEAR(efficiency, 1e9 / (s["variance"].get<double>() * s["ns_per_sample"].get<double>()), 1e-6 * efficiency)
        << s;
  }
  EXPECT_EQ(j["cosine"]["bytes"], 0);  // no table
  // Importance sampling by the table must beat cosine sampling on a glossy lobe (α = 0.15).
  EXPECT_LT(j["uniform"]["variance"].get<double>(), j["cosine"]["variance"].get<double>()) << j.dump(2);
  EXPECT_LT(j["adaptive"]["variance"].get<double>(), j["cosine"]["variance"].get<double>()) << j.dump(2);
}

// --quadrature adds each sampler's figures by quadrature, labelled as such: one mean for every
// sampler (the same integral of f cos), variances ranked as the sampled ones are, and nothing left
// unsampled by tables with a cosine mixture. Without the flag there is no "quadrature" key.
TEST_F(BrdfCli, StatsQuadratureFigures) {
  std::vector<std::string> args = stats(gold(), kSmallIso);
  args.push_back("--json");
  EXPECT_FALSE(runJson(args).contains("quadrature"));
  args.push_back("--quadrature");
  const json j = runJson(args);
  ASSERT_TRUE(j.contains("quadrature")) << j.dump(2);
  EXPECT_EQ(j["quadrature"]["theta_half_points"], ReflectanceQuadratureOptions{}.thetaHalfPoints);
  EXPECT_EQ(j["quadrature"]["phi_half_points"], ReflectanceQuadratureOptions{}.phiHalfPoints);
  const double mean = j["cosine"]["quadrature"]["mean"].get<double>();
  EXPECT_NEAR(mean, j["cosine"]["mean"].get<double>(), 0.05 * mean);
  for (const char* sampler : {"cosine", "uniform", "adaptive"}) {
    const json& q = j[sampler]["quadrature"];
    SCOPED_TRACE(sampler);
    EXPECT_EQ(q["mean"].get<double>(), mean) << q;
    EXPECT_GT(q["variance"].get<double>(), 0) << q;
    EXPECT_EQ(q["unsampled"].get<double>(), 0) << q;
    EXPECT_NEAR(q["variance_vs_uniform"].get<double>(),
                q["variance"].get<double>() / j["uniform"]["quadrature"]["variance"].get<double>(), 1e-12)
        << q;
  }
  EXPECT_LT(j["uniform"]["quadrature"]["variance"].get<double>(), j["cosine"]["quadrature"]["variance"].get<double>());
}

// --cosine-weight and --slice-grouping reach the tables: a weight of 1 is cosine sampling (the same
// variance by quadrature, to rounding), and grouping the 4D table's outgoing slices stores fewer
// bytes.
TEST_F(BrdfCli, StatsTableLeversReachTheTables) {
  std::vector<std::string> args = stats(gold(), kSmallIso);
  args.insert(args.end(), {"--quadrature", "--json", "--cosine-weight", "1"});
  const json allCosine = runJson(args);
  const double cosine = allCosine["cosine"]["quadrature"]["variance"].get<double>();
  for (const char* table : {"uniform", "adaptive"})
    EXPECT_NEAR(allCosine[table]["quadrature"]["variance"].get<double>(), cosine, 1e-9 * cosine) << table;

  const std::vector<std::string> small4d = {"brdf-stats", gold(),      "--table", "4d",    "--res",
                                            "8x8x64x16",  "--samples", "1",       "--json"};
  std::vector<std::string> grouped = small4d;
  grouped.insert(grouped.end(), {"--slice-grouping", "1e-2"});
  EXPECT_LT(runJson(grouped)["adaptive"]["bytes"].get<double>(), runJson(small4d)["adaptive"]["bytes"].get<double>());

  expectFailure({"brdf-stats", gold(), "--cosine-weight", "2"}, "", "--cosine-weight");
  expectFailure({"brdf-stats", gold(), "--slice-grouping", "-1"}, "", "--slice-grouping");
}

// The flags are the table options' list (table_options.h), the scene format's keys in kebab case;
// the per-axis flags build the table --res describes.
TEST_F(BrdfCli, StatsFlagsAreTheTableOptions) {
  const RunResult help = run({"brdf-stats", "--help"});
  ASSERT_EQ(help.exitCode, 0) << describe(help);
  for (const TableOption& option : tableOptionList()) {
    std::string flag = "--" + std::string(option.key);
    std::replace(flag.begin(), flag.end(), '_', '-');
    EXPECT_NE(help.out.find(flag), std::string::npos) << flag << " not in:\n" << help.out;
  }
  const json res = runJson(stats(gold(), {"--table", "isotropic", "--res", "16x64x16", "--samples", "16", "--json"}));
  const json axes = runJson(stats(gold(), {"--layout", "isotropic", "--theta-out", "16", "--theta-half", "64",
                                           "--phi-half", "16", "--samples", "16", "--json"}));
  EXPECT_EQ(axes["uniform_res"], res["uniform_res"]);
  EXPECT_EQ(axes["adaptive_bytes"], res["adaptive_bytes"]);
  const json unmirrored =
      runJson(stats(gold(), {"--table", "isotropic", "--res", "16x64x16", "--mirror", "false", "--samples", "16",
                             "--tolerance", "constant", "--supersampling", "1", "--json"}));
  EXPECT_EQ(unmirrored["uniform_res"], json({16, 64, 16}));
}

TEST_F(BrdfCli, StatsDefaultsAreTheLibrarys) {
  // No --res: TabulatedBrdfOptions' resolution, whatever the library's defaults are today. The
  // isotropic table, because the 4D one takes seconds to tabulate (minutes under ASan).
  const json j = runJson({"brdf-stats", gold(), "--table", "isotropic", "--samples", "1", "--json"});
  const TabulatedBrdfOptions defaults;
  ASSERT_TRUE(defaults.mirror);
  EXPECT_EQ(j["table"], "isotropic");
  EXPECT_EQ(j["uniform_res"], json({defaults.thetaOutCells, defaults.thetaHalfCells, defaults.phiHalfCells / 2}));
  EXPECT_EQ(j["chi2_epsilon"], defaults.simplify.epsilon);
  EXPECT_EQ(j["interpolation"], "nearest");
  EXPECT_EQ(j["estimator"]["samples_per_direction"], 1);
  EXPECT_LT(j["adaptive_bytes"].get<double>(), j["uniform_bytes"].get<double>()) << j.dump(2);
}

TEST_F(BrdfCli, StatsPrintsATable) {
  std::vector<std::string> args = stats(gold(), kSmallIso);
  args.insert(args.end(), {"--interpolation", "trilinear", "--chi2-epsilon", "0.01"});
  const RunResult r = run(args);
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  for (const char* text : {"isotropic table", "trilinear interpolation", "chi2 epsilon 0.01", "16 x 64 x 8", "compression",
                           "cosine", "uniform", "adaptive", "efficiency"})
    EXPECT_NE(r.out.find(text), std::string::npos) << text << " not in:\n" << r.out;
  EXPECT_EQ(r.out.find("quadrature"), std::string::npos) << r.out;
}

TEST_F(BrdfCli, StatsBadInput) {
  expectFailure({"brdf-stats", path("missing.binary")}, path("missing.binary") + ": ", "no such file");
  const std::string truncated = path("truncated.binary");
  writeFile(truncated, readFile(gold()).substr(0, 1000));
  expectFailure(stats(truncated, kSmallIso), truncated + ": ", "truncated");

  for (const char* res :
       {"32x16x256", "32x16x256x32x2", "0x16x256x32", "32x16xx32", "axbxcxd", "32x-16x256x32", "32x16x256x32x"})
    expectFailure({"brdf-stats", gold(), "--res", res}, "", "--res");
  expectFailure({"brdf-stats", gold(), "--table", "isotropic", "--res", "32x16x256x32"}, "",
                "--res for the isotropic layout");
  expectFailure({"brdf-stats", gold(), "--res", "4096x4096x4096x4096"}, "", "at most");
  // A mirrored isotropic table needs an even Δφ count: the library's check, reported as usage.
  expectFailure({"brdf-stats", gold(), "--table", "isotropic", "--res", "8x16x7"}, "", "even");
  expectFailure({"brdf-stats", gold(), "--chi2-epsilon", "-1"}, "", "--chi2-epsilon");
  expectFailure({"brdf-stats", gold(), "--epsilon", "1e-4"}, "", "--epsilon");  // the map's metric; renamed
  expectFailure({"brdf-stats", gold(), "--table", "6d"}, "", "--layout unknown BRDF table layout '6d'");
  expectFailure({"brdf-stats", gold(), "--table", "iso"}, "", "--layout");  // one spelling: isotropic
  expectFailure({"brdf-stats", gold(), "--theta-half", "2.5"}, "", "--theta-half must be a whole number");
  expectFailure({"brdf-stats", gold(), "--mirror", "yes"}, "", "--mirror must be true or false");
  expectFailure({"brdf-stats", gold(), "--theta-half", "0"}, "", "--theta-half must be at least 1");
  expectFailure({"brdf-stats", gold(), "--theta-half", "65536", "--phi-half", "4096"}, "", "at most");
  expectFailure({"brdf-stats", gold(), "--res", "8x8x64x16", "--theta-half", "64"}, "", "excludes");
  expectFailure({"brdf-stats", gold(), "--interpolation", "cubic"}, "", "--interpolation");
  expectFailure({"brdf-stats", gold(), "--samples", "0"}, "", "--samples");
  expectFailure({"brdf-stats"}, "", "input");
}

TEST_F(BrdfCli, Chi2PassesForEverySampler) {
  for (const char* sampler : {"cosine", "uniform", "adaptive"})
    for (const char* theta : {"0", "60", "85"}) {
      // Cosine sampling ignores ωo: one angle tests it.
      if (std::string(sampler) == "cosine" && std::string(theta) != "60") continue;
      SCOPED_TRACE(std::string(sampler) + " at theta_o " + theta);
      const RunResult r = run({"chi2", "--brdf", gold(), "--theta-o", theta, "--sampler", sampler, "--table",
                               "isotropic", "--res", "16x64x16", "--samples", "20000", "--json"});
      ASSERT_EQ(r.exitCode, 0) << describe(r);
      const json j = json::parse(r.out);
      EXPECT_TRUE(j["passed"].get<bool>()) << j;
      EXPECT_GE(j["pvalue"].get<double>(), 0.01) << j;
      EXPECT_EQ(j["samples"], 20000);
      EXPECT_GT(j["dof"].get<int>(), 100) << j;
    }
  // The table form of the same verdict.
  const RunResult r = run({"chi2", "--brdf", gold(), "--theta-o", "30", "--sampler", "adaptive", "--table", "isotropic",
                           "--res", "16x64x16", "--samples", "20000"});
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_EQ(r.out.rfind("passed: p = ", 0), 0u) << r.out;
}

TEST_F(BrdfCli, Chi2BadInput) {
  auto args = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = {"chi2", "--brdf", gold(), "--sampler", "cosine"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  for (const char* theta : {"90", "-1", "120", "nan"})
    expectFailure(args({"--theta-o", theta}), "chi2 --brdf: ", "--theta-o must be in [0, 90)");
  expectFailure(args({"--theta-o", "abc"}), "", "--theta-o");
  expectFailure(args({}), "chi2 --brdf: ", "--theta-o");
  expectFailure({"chi2", "--brdf", gold(), "--theta-o", "30", "--sampler", "alias"},
                "chi2 --brdf: ", "cosine, uniform, adaptive or rgl");
  expectFailure({"chi2", "--brdf", path("missing.binary"), "--theta-o", "30", "--sampler", "uniform"},
                path("missing.binary") + ": ", "no such file");
  const std::string truncated = path("truncated.binary");
  writeFile(truncated, readFile(gold()).substr(0, 5000));
  expectFailure({"chi2", "--brdf", truncated, "--theta-o", "30", "--sampler", "adaptive"}, truncated + ": ",
                "truncated");
  expectFailure(args({"--theta-o", "30", "--res", "8x8"}), "", "--res");
  expectFailure(args({"--theta-o", "30", "--envmap", gold()}), "", "--envmap");
  expectFailure({"chi2", "--envmap", gold(), "--sampler", "uniform", "--table", "isotropic"}, "", "--brdf");
  expectFailure({"chi2", "--sampler", "uniform", "--theta-o", "30"}, "", "--brdf");
}

}  // namespace
}  // namespace acdf::apptest

// `acdf rgl-gen` and the measured-BRDF commands on RGL .bsdf files: a generated file is taken by
// brdf-stats (with the file's own warps as a fourth sampler) and chi2 --sampler rgl, recognised
// by content; bad files and outputs fail with one line naming the file, exit 2, no partial file.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app_test_util.h"

namespace {

using namespace acdf::apptest;
namespace fs = std::filesystem;

class RglCli : public TempDirTest {
 protected:
  RunResult run(const std::vector<std::string>& args) { return runAcdf(args, dir_); }
  // A small file of the gold preset, named without the .bsdf extension (content decides).
  std::string smallFile() {
    const std::string out = path("gold.dat");
    const RunResult r = run({"rgl-gen", "--preset", "gold", "--theta-i", "4", "--vndf", "32", "--reflectance", "16",
                             "--ndf", "64", "-o", out});
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    return out;
  }
};

TEST_F(RglCli, BrdfStatsReportsTheFileWarpsBesideOurTables) {
  const RunResult r =
      run({"brdf-stats", smallFile(), "--table", "isotropic", "--res", "8x32x8", "--samples", "64", "--json"});
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], "rgl");
  for (const char* sampler : {"cosine", "uniform", "adaptive", "rgl"}) {
    ASSERT_TRUE(j.contains(sampler)) << sampler;
    EXPECT_TRUE(j[sampler].contains("bytes")) << sampler;
    EXPECT_GT(j[sampler]["mean"].get<double>(), 0) << sampler;
  }
  EXPECT_EQ(j["cosine"]["bytes"], 0);
  // 4 theta_i slices of a 16² luminance warp and a 32² visible-NDF warp, 2 floats per vertex and more.
  EXPECT_GT(j["rgl"]["bytes"].get<double>(), 4 * (16 * 16 + 32 * 32) * 2 * 4);
}

TEST_F(RglCli, Chi2TakesTheFormatSampler) {
  const std::string file = smallFile();
  const RunResult r = run({"chi2", "--brdf", file, "--theta-o", "30", "--sampler", "rgl", "--samples", "100000"});
  EXPECT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_NE(r.out.find("passed"), std::string::npos) << describe(r);
}

TEST_F(RglCli, BadFilesAndOutputsFailOnOneLine) {
  const std::string file = smallFile();
  const std::string cut = path("cut.bsdf");
  writeFile(cut, readFile(file).substr(0, 300));
  expectOneLineFailure(run({"brdf-stats", cut}), "acdf: " + cut + ": ", "truncated header");
  const std::string out = path("missing-dir/x.bsdf");
  expectOneLineFailure(run({"rgl-gen", "--preset", "gold", "-o", out}), "acdf: " + out + ": ", "temporary file");
  EXPECT_FALSE(fs::exists(out));
  expectOneLineFailure(run({"rgl-gen", "--preset", "nope", "-o", path("y.bsdf")}), "acdf: ", "--preset");
  expectOneLineFailure(run({"rgl-gen", "--preset", "gold", "--vndf", "1", "-o", path("y.bsdf")}), "acdf: ", "--vndf");
  EXPECT_FALSE(fs::exists(path("y.bsdf")));
}

}  // namespace

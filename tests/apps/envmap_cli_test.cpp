// End-to-end tests of the environment-map commands: `acdf env-gen` (writes a readable map, no
// partial file on failure), `acdf envmap-stats` (the documented keys; bad maps exit 2 with one
// line) and `acdf chi2 --envmap` (every sampler passes on a generated map; exit codes).

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acdf/envmap/image_file.h"
#include "app_test_util.h"

namespace acdf::apptest {
namespace {

namespace fs = std::filesystem;

class EnvmapCli : public TempDirTest {
 protected:
  RunResult run(const std::vector<std::string>& args) { return runAcdf(args, dir_); }

  // A float RGB EXR of the given pixels (3 per pixel).
  std::string writeMap(const std::string& name, uint32_t width, uint32_t height, std::vector<float> rgb) {
    acdf::Image image;
    image.width = width;
    image.height = height;
    image.channels = 3;
    image.pixels = std::move(rgb);
    const std::string file = path(name);
    acdf::writeExr(file, image);
    return file;
  }

  std::string generated(const std::string& width = "128") {
    const std::string file = path("sky" + width + ".exr");
    const RunResult r = run({"env-gen", "--preset", "sunset", "--width", width, "-o", file});
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    return file;
  }
};

TEST_F(EnvmapCli, EnvGenWritesTheMapItDescribes) {
  const std::string file = path("noon.exr");
  const RunResult r = run({"env-gen", "-o", file, "--width", "64", "--height", "40", "--sun-elevation", "45"});
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_NE(r.out.find("sun 45 deg high"), std::string::npos) << r.out;
  const acdf::Image image = acdf::readImage(file);
  EXPECT_EQ(image.width, 64u);
  EXPECT_EQ(image.height, 40u);
  EXPECT_EQ(image.channels, 3u);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) files += entry.path().filename().string().find("noon") == 0;
  EXPECT_EQ(files, 1u) << "a temporary file was left next to the output";
}

// A signal that kills env-gen while it writes (SIGXFSZ past a 16 KB file-size limit; Ctrl-C takes
// the same path) leaves neither the map nor its temporary (acdf/sampling/temporary_files.h; a
// partial "*.tmp-…" was left before).
TEST_F(EnvmapCli, EnvGenKilledMidWriteLeavesNoFile) {
  const std::string exe = acdfExe(), file = path("killed.exr");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlimit limit{16 << 10, 16 << 10};
    setrlimit(RLIMIT_FSIZE, &limit);
    const int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, STDOUT_FILENO);
    dup2(devnull, STDERR_FILENO);
    execl(exe.c_str(), "acdf", "env-gen", "--width", "512", "-o", file.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGXFSZ) << "status " << status;
  EXPECT_TRUE(std::filesystem::is_empty(dir_)) << "a file was left behind";
}

TEST_F(EnvmapCli, EnvGenBadArgumentsExitTwoWithoutOutput) {
  expectOneLineFailure(run({"env-gen", "--preset", "midnight", "-o", path("a.exr")}), "acdf: env-gen:", "midnight");
  expectOneLineFailure(run({"env-gen", "--sun-elevation", "100", "-o", path("a.exr")}), "acdf: env-gen:", "elevation");
  expectOneLineFailure(run({"env-gen", "--width", "0", "-o", path("a.exr")}), "acdf: env-gen:", "width");
  const std::string unwritable = path("missing/dir/a.exr");
  expectOneLineFailure(run({"env-gen", "-o", unwritable}), "acdf: " + unwritable + ":", "");
  EXPECT_FALSE(fs::exists(path("a.exr")));
}

TEST_F(EnvmapCli, EnvmapStatsReportsTheDocumentedKeys) {
  const RunResult r = run({"envmap-stats", generated(), "--json"});
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  const auto j = nlohmann::json::parse(r.out);
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.insert(key);
  const std::set<std::string> expected = {"width",
                                          "height",
                                          "uniform_bytes",
                                          "alias_bytes",
                                          "adaptive_bytes",
                                          "hierarchical_bytes",
                                          "compression",
                                          "chi2_divergence",
                                          "max_weight_ratio",
                                          "unreachable_mass",
                                          "uniform_chi2_divergence",
                                          "uniform_unreachable_mass",
                                          "negative_pixels_clamped",
                                          "declared_chromaticities",
                                          "build_ms",
                                          "uniform_sphere",
                                          "cosine",
                                          "uniform",
                                          "alias",
                                          "adaptive",
                                          "hierarchical"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(j["width"], 128);
  EXPECT_EQ(j["height"], 64);
  EXPECT_TRUE(j["declared_chromaticities"].is_null());
  EXPECT_GT(j["compression"].get<double>(), 1.0);
  // Every lit pixel is reachable, and the uniform table is the exact distribution up to float CDFs.
  EXPECT_EQ(j["unreachable_mass"].get<double>(), 0.0);
  EXPECT_EQ(j["uniform_unreachable_mass"].get<double>(), 0.0);
  EXPECT_LT(j["uniform_chi2_divergence"].get<double>(), 1e-6);
  for (const char* method : {"uniform", "alias", "adaptive", "hierarchical"})
    EXPECT_GE(j["build_ms"][method].get<double>(), 0.0);
  for (const char* strategy : {"uniform_sphere", "cosine", "uniform", "alias", "adaptive", "hierarchical"}) {
    EXPECT_GT(j[strategy]["variance"].get<double>(), 0.0) << strategy;
    EXPECT_GT(j[strategy]["ns_per_sample"].get<double>(), 0.0) << strategy;
    EXPECT_GT(j[strategy]["efficiency"].get<double>(), 0.0) << strategy;
  }
  // Stratified variates: every map sampler gains, and the warps (the cascades' inversion, the
  // hierarchical descent) far more than the alias tables, which scatter neighbouring variates.
  for (const char* strategy : {"uniform", "alias", "adaptive", "hierarchical"})
    EXPECT_LT(j[strategy]["stratified_variance"].get<double>(), j[strategy]["variance"].get<double>()) << strategy;
  EXPECT_LT(2 * j["hierarchical"]["stratified_variance"].get<double>(),
            j["alias"]["stratified_variance"].get<double>());
  EXPECT_FALSE(j["cosine"].contains("stratified_variance"));
  // A sunset's power is in a tiny sun: sampling the map beats sampling the sphere by far.
  EXPECT_LT(10 * j["adaptive"]["variance"].get<double>(), j["uniform_sphere"]["variance"].get<double>());
}

TEST_F(EnvmapCli, DirtyAndBrokenMapsExitTwoWithOneLine) {
  const std::string black = writeMap("black.exr", 4, 2, std::vector<float>(24, 0.0f));
  expectOneLineFailure(run({"envmap-stats", black}), "acdf: " + black + ":", "black");
  expectOneLineFailure(run({"chi2", "--envmap", black, "--sampler", "adaptive"}), "acdf: " + black + ":", "black");

  std::vector<float> rgb(24, 1.0f);
  rgb[7] = std::numeric_limits<float>::quiet_NaN();
  const std::string nan = writeMap("nan.exr", 4, 2, rgb);
  expectOneLineFailure(run({"envmap-stats", nan}), "acdf: " + nan + ":", "NaN");
  expectOneLineFailure(run({"envmap-stats", nan, "--epsilon", "-1"}), "acdf: envmap-stats: --epsilon",
                       "must be finite and >= 0, got -1");
  const RunResult sanitized = run({"envmap-stats", nan, "--sanitize", "--json"});
  ASSERT_EQ(sanitized.exitCode, 0) << describe(sanitized);
  EXPECT_EQ(nlohmann::json::parse(sanitized.out)["nonfinite_pixels_replaced"], 1);

  rgb[7] = -2.0f;
  const RunResult negative = run({"envmap-stats", writeMap("neg.exr", 4, 2, rgb), "--json"});
  ASSERT_EQ(negative.exitCode, 0) << describe(negative);
  EXPECT_EQ(nlohmann::json::parse(negative.out)["negative_pixels_clamped"], 1);

  const std::string text = path("text.exr");
  writeFile(text, "not an image\n");
  expectOneLineFailure(run({"envmap-stats", text}), "acdf: " + text + ":", "");
  const std::string whole = readFile(generated());
  const std::string truncated = path("truncated.exr");
  writeFile(truncated, whole.substr(0, whole.size() / 2));
  expectOneLineFailure(run({"envmap-stats", truncated}), "acdf: " + truncated + ":", "");
  expectOneLineFailure(run({"chi2", "--envmap", path("missing.exr"), "--sampler", "uniform"}),
                       "acdf: " + path("missing.exr") + ":", "no such file");
}

TEST_F(EnvmapCli, EnvmapStatsReportsTheDeclaredPrimaries) {
  // A map saved in ProPhoto RGB (D50 white): reported as declared and converted; a Rec. 709 one as
  // declared and left; one declaring nothing as assumed Rec. 709.
  acdf::Image image;
  image.width = 8;
  image.height = 4;
  image.channels = 3;
  image.pixels.assign(8 * 4 * 3, 1.0f);
  image.pixels[40] = 50.0f;
  const acdf::Chromaticities proPhoto{{0.7347, 0.2653}, {0.1596, 0.8404}, {0.0366, 0.0001}, {0.3457, 0.3585}};
  const std::string file = path("prophoto.exr");
  acdf::writeExr(file, image, proPhoto);
  const RunResult json = run({"envmap-stats", file, "--json"});
  ASSERT_EQ(json.exitCode, 0) << describe(json);
  const auto declared = nlohmann::json::parse(json.out)["declared_chromaticities"];
  EXPECT_NEAR(declared["white"][0].get<double>(), 0.3457, 1e-6);
  EXPECT_NEAR(declared["blue"][1].get<double>(), 0.0001, 1e-6);
  EXPECT_TRUE(declared["converted_to_rec709"].get<bool>());
  const RunResult text = run({"envmap-stats", file});
  ASSERT_EQ(text.exitCode, 0) << describe(text);
  EXPECT_NE(text.out.find("chromaticities     declared red (0.7347, 0.2653), green (0.1596, 0.8404), blue (0.0366, "
                          "0.0001), white (0.3457, 0.3585), converted to Rec. 709 / D65"),
            std::string::npos)
      << text.out;
  acdf::writeExr(file, image, acdf::kRec709);
  EXPECT_FALSE(nlohmann::json::parse(run({"envmap-stats", file, "--json"}).out)["declared_chromaticities"]
                   ["converted_to_rec709"]
                       .get<bool>());
  EXPECT_NE(run({"envmap-stats", writeMap("plain.exr", 8, 4, image.pixels)}).out.find("none declared"),
            std::string::npos);
}

// --local adds local sampling: its tables against the dense 4D one, and its irradiance variance,
// far below the global strategies' (the estimator's own normals each sample their slice; 8.4x
// below adaptive's on this 512 x 256 sunset, whose 16 x 16-pixel blocks span 11 degrees).
TEST_F(EnvmapCli, EnvmapStatsLocalReportsItsObject) {
  const RunResult r = run({"envmap-stats", generated("512"), "--local", "--normal-res", "16,32", "--json"});
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("local"));
  const auto& local = j["local"];
  std::set<std::string> keys;
  for (const auto& [key, value] : local.items()) keys.insert(key);
  const std::set<std::string> expected = {
      "normal_rows", "normal_columns", "block_size",    "bytes",      "dense_bytes",         "slices_built",
      "build_ms",    "variance",       "ns_per_sample", "efficiency", "stratified_variance", "adaptive_variance_ratio"};
  EXPECT_EQ(keys, expected);
  EXPECT_EQ(local["normal_rows"], 16);
  EXPECT_EQ(local["normal_columns"], 32);
  EXPECT_EQ(local["slices_built"], 512);
  EXPECT_EQ(local["dense_bytes"].get<uint64_t>(), uint64_t{512} * 512 * 256 * 4);
  EXPECT_LT(local["bytes"].get<uint64_t>(), local["dense_bytes"].get<uint64_t>());
  EXPECT_GE(local["build_ms"].get<double>(), 0.0);
  EXPECT_GT(local["efficiency"].get<double>(), 0.0);
  EXPECT_LT(local["stratified_variance"].get<double>(), local["variance"].get<double>());
  EXPECT_DOUBLE_EQ(local["adaptive_variance_ratio"].get<double>(),
                   j["adaptive"]["variance"].get<double>() / local["variance"].get<double>());
  for (const char* strategy : {"uniform_sphere", "cosine", "uniform", "alias", "adaptive", "hierarchical"})
    EXPECT_LT(4 * local["variance"].get<double>(), j[strategy]["variance"].get<double>()) << strategy;

  const std::string map = generated();
  expectOneLineFailure(run({"envmap-stats", map, "--local", "--normal-res", "0,16"}),
                       "acdf: envmap-stats:", "--normal-res must be in [1, 4096], got 0");
  expectOneLineFailure(run({"envmap-stats", map, "--local", "--normal-res", "8"}),
                       "acdf: envmap-stats:", "--normal-res takes ROWS,COLUMNS");
  expectOneLineFailure(run({"envmap-stats", map, "--normal-res", "8,16"}), "acdf:", "--local");
}

TEST_F(EnvmapCli, Chi2LocalNeedsANormal) {
  const std::string map = generated();
  for (const char* normal : {"0,1,0", "0.3,0.5,-0.8", "1,0,0"}) {
    const RunResult r =
        run({"chi2", "--envmap", map, "--sampler", "local", "--normal", normal, "--samples", "2e5", "--json"});
    ASSERT_EQ(r.exitCode, 0) << normal << ": " << describe(r);
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["passed"].get<bool>()) << normal;
    EXPECT_GT(j["dof"].get<int>(), 100) << normal;
  }
  expectOneLineFailure(run({"chi2", "--envmap", map, "--sampler", "local"}),
                       "acdf: chi2 --envmap --sampler local:", "--normal X,Y,Z");
  expectOneLineFailure(run({"chi2", "--envmap", map, "--sampler", "adaptive", "--normal", "0,1,0"}),
                       "acdf: chi2 --envmap:", "the local strategies only");
  expectOneLineFailure(run({"chi2", "--envmap", map, "--sampler", "local", "--normal", "0,0,0"}),
                       "acdf: chi2 --envmap:", "not all 0");
  expectOneLineFailure(run({"chi2", "--envmap", map, "--sampler", "local", "--normal", "1,2"}),
                       "acdf: chi2 --envmap:", "three finite numbers");
}

TEST_F(EnvmapCli, Chi2PassesForEverySamplerAndRejectsBadUsage) {
  const std::string map = generated();
  for (const char* sampler : {"uniform-sphere", "uniform", "alias", "adaptive", "compensated", "hierarchical"}) {
    const RunResult r = run({"chi2", "--envmap", map, "--sampler", sampler, "--samples", "2e5", "--json"});
    ASSERT_EQ(r.exitCode, 0) << sampler << ": " << describe(r);
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j.size(), 4u);
    EXPECT_TRUE(j["passed"].get<bool>());
    EXPECT_GE(j["pvalue"].get<double>(), 0.01);
    EXPECT_EQ(j["samples"], 200000);
    EXPECT_GT(j["dof"].get<int>(), 100);
  }
  expectOneLineFailure(run({"chi2", "--envmap", map, "--sampler", "cosine"}), "acdf: chi2 --envmap:", "cosine");
  expectOneLineFailure(run({"chi2", "--sampler", "uniform"}), "acdf: chi2:", "--envmap");
  expectOneLineFailure(run({"chi2", "--envmap", map, "--sampler", "uniform", "--samples", "0"}),
                       "acdf: chi2:", "--samples");
}

}  // namespace
}  // namespace acdf::apptest

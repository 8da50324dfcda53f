// End-to-end tests of the acdf program: runs build/bin/acdf as a subprocess and checks its exit
// code, stdout (the --json report) and stderr (one line per error).

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "acdf/envmap/environment_table.h"
#include "acdf/sampling/simplify.h"
#include "app_test_util.h"

namespace acdf::apptest {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// Writes a float image with OpenImageIO (format from the extension).
void writeImage(const std::string& file, int width, int height, int channels, const std::vector<float>& pixels) {
  auto out = OIIO::ImageOutput::create(file);
  ASSERT_TRUE(out) << OIIO::geterror();
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
  ASSERT_TRUE(out->open(file, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close()) << out->geterror();
}

class Cli : public TempDirTest {
 protected:
  RunResult run(const std::vector<std::string>& args) { return runAcdf(args, dir_); }

  // Runs `cdf-stats ARGS --json`, expects success and returns the parsed report.
  json stats(std::vector<std::string> args) {
    args.insert(args.begin(), "cdf-stats");
    args.push_back("--json");
    const RunResult r = run(args);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    json j;
    try {
      j = json::parse(r.out);
    } catch (const json::exception& e) {
      ADD_FAILURE() << "stdout is not JSON: " << e.what() << "\n" << describe(r);
      return json::object();
    }
    EXPECT_TRUE(j.is_object()) << describe(r);
    return j;
  }

  // Expects a bad-input failure: exit 2, nothing on stdout, exactly one stderr line
  // "acdf: <file>: <problem>" whose problem contains `needle`.
  void expectFileError(const std::string& file, const std::string& needle, std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"cdf-stats", file};
    args.insert(args.end(), extra.begin(), extra.end());
    for (bool asJson : {false, true}) {
      if (asJson) args.push_back("--json");
      expectOneLineFailure(run(args), "acdf: " + file + ": ", needle);
    }
  }

  // Expects a usage failure: exit 2, nothing on stdout, exactly one line on stderr.
  void expectUsageError(const std::vector<std::string>& args, const std::string& needle = "") {
    expectOneLineFailure(run(args), "acdf: ", needle);
  }

  std::string writePeaked(const std::string& name = "peaked.npy", std::size_t rows = 64, std::size_t cols = 128) {
    const std::string file = path(name);
    writeFile(file, npyF4({rows, cols}, peakedGrid(rows, cols)));
    return file;
  }
};

// Every key of the report, with the type and range any input must give.
void expectWellFormedReport(const json& j, const std::vector<std::size_t>& dims) {
  for (const char* key :
       {"input", "dims", "cells", "uniform_bytes", "alias_bytes", "adaptive_bytes", "compression", "points",
        "average_intervals", "chi2_divergence", "max_weight_ratio", "unreachable_mass", "chi2_test_pvalue",
        "ns_per_sample", "ns_per_pdf", "build_ms", "options", "negative_values_clamped", "uniform_fallback"})
    ASSERT_TRUE(j.contains(key)) << "missing key " << key << " in " << j.dump(2);

  EXPECT_EQ(j["dims"].get<std::vector<std::size_t>>(), dims);
  std::size_t cells = 1;
  for (auto d : dims) cells *= d;
  EXPECT_EQ(j["cells"].get<std::size_t>(), cells);
  EXPECT_GT(j["uniform_bytes"].get<std::size_t>(), 0u);
  EXPECT_EQ(j["alias_bytes"].get<std::size_t>(), 12 * cells);  // 12 bytes a cell (alias_table_1d.h)
  EXPECT_GT(j["adaptive_bytes"].get<std::size_t>(), 0u);
  EXPECT_NEAR(j["compression"].get<double>(), j["uniform_bytes"].get<double>() / j["adaptive_bytes"].get<double>(),
              1e-9);
  ASSERT_EQ(j["points"].size(), dims.size());
  ASSERT_EQ(j["average_intervals"].size(), dims.size());
  for (std::size_t d = 0; d < dims.size(); ++d) {
    EXPECT_GE(j["points"][d].get<std::size_t>(), 2u);
    const double intervals = j["average_intervals"][d].get<double>();
    EXPECT_GE(intervals, 1.0);
    EXPECT_LE(intervals, static_cast<double>(dims[d]));
  }
  EXPECT_GE(j["chi2_divergence"].get<double>(), -1e-9);
  EXPECT_GE(j["max_weight_ratio"].get<double>(), 1.0 - 1e-6);
  EXPECT_GE(j["unreachable_mass"].get<double>(), 0.0);
  EXPECT_LE(j["unreachable_mass"].get<double>(), 1e-12);
  ASSERT_TRUE(j["chi2_test_pvalue"].is_number()) << j["chi2_test_pvalue"];
  EXPECT_GE(j["chi2_test_pvalue"].get<double>(), 0.0);
  EXPECT_LE(j["chi2_test_pvalue"].get<double>(), 1.0);
  for (const char* key : {"ns_per_sample", "ns_per_pdf", "build_ms"}) {
    for (const char* dist : {"uniform", "alias", "adaptive"}) {
      ASSERT_TRUE(j[key].contains(dist)) << key << "." << dist;
      const double v = j[key][dist].get<double>();
      EXPECT_TRUE(std::isfinite(v)) << key << "." << dist;
      EXPECT_GE(v, 0.0) << key << "." << dist;
      if (std::string(key) != "build_ms") {
        EXPECT_GT(v, 0.0) << key << "." << dist;
        EXPECT_LT(v, 1e6) << key << "." << dist;
      }
    }
  }
  for (const char* key : {"epsilon", "max_points", "weight_bound", "simplifier", "metric"})
    EXPECT_TRUE(j["options"].contains(key)) << "options." << key;
  EXPECT_TRUE(j["uniform_fallback"].is_boolean());
  EXPECT_GE(j["negative_values_clamped"].get<std::size_t>(), 0u);
}

// ---- help and version --------------------------------------------------------------------------

TEST_F(Cli, HelpAndVersion) {
  RunResult r = run({"--help"});
  EXPECT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_NE(r.out.find("cdf-stats"), std::string::npos) << r.out;

  r = run({"cdf-stats", "--help"});
  EXPECT_EQ(r.exitCode, 0) << describe(r);
  for (const char* flag : {"--epsilon", "--max-points", "--weight-bound", "--simplifier", "--metric", "--samples",
                           "--seed", "--json", "[0,1)"})
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag << " not in help:\n" << r.out;

  r = run({"--version"});
  EXPECT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_EQ(r.out.rfind("acdf ", 0), 0u) << r.out;

  // The strategies' help comes from their declared list: every one is named.
  for (const char* command : {"render", "chi2"}) {
    r = run({command, "--help"});
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    for (EnvironmentSampling s : kEnvironmentSamplings)
      EXPECT_NE(r.out.find(std::string(toString(s))), std::string::npos) << toString(s) << " not in help:\n" << r.out;
  }
  EXPECT_NE(run({"render", "--help"}).out.find("local-compensated"), std::string::npos);
}

// ---- reports -----------------------------------------------------------------------------------

TEST_F(Cli, PeakedInputCompressesAndPassesItsOwnChiSquareTest) {
  const std::string file = writePeaked();
  const json j = stats({file});
  expectWellFormedReport(j, {64, 128});
  EXPECT_EQ(j["input"], file);
  EXPECT_GT(j["compression"].get<double>(), 1.0) << j.dump(2);
  EXPECT_LT(j["adaptive_bytes"].get<std::size_t>(), j["uniform_bytes"].get<std::size_t>());
  EXPECT_EQ(j["uniform_fallback"], false);
  EXPECT_EQ(j["negative_values_clamped"], 0);
  // The sampler against its own pdf: a correct engine fails this only by chance (p < 1e-4).
  EXPECT_GT(j["chi2_test_pvalue"].get<double>(), 1e-4) << j.dump(2);
  // Defaults of the engine's SimplifyOptions.
  EXPECT_EQ(j["options"]["simplifier"], "douglas-peucker");
  EXPECT_EQ(j["options"]["metric"], "vertical");
  EXPECT_EQ(j["options"]["max_points"], 0);
  EXPECT_DOUBLE_EQ(j["options"]["epsilon"].get<double>(), acdf::SimplifyOptions{}.epsilon);
  EXPECT_DOUBLE_EQ(j["options"]["weight_bound"].get<double>(), acdf::SimplifyOptions{}.weightBound);
}

TEST_F(Cli, ReportsAreReproducibleForAFixedSeed) {
  const std::string file = writePeaked();
  const json a = stats({file, "--samples", "20000", "--seed", "7"});
  const json b = stats({file, "--samples", "20000", "--seed", "7"});
  EXPECT_EQ(a["chi2_test_pvalue"], b["chi2_test_pvalue"]);
  EXPECT_EQ(a["adaptive_bytes"], b["adaptive_bytes"]);
  EXPECT_EQ(a["chi2_divergence"], b["chi2_divergence"]);
}

TEST_F(Cli, OptionsReachTheEngine) {
  const std::string file = writePeaked();
  const json loose = stats({file, "--epsilon", "0.05", "--samples", "20000"});
  const json tight = stats({file, "--epsilon", "0.0001", "--samples", "20000"});
  EXPECT_DOUBLE_EQ(loose["options"]["epsilon"].get<double>(), 0.05);
  EXPECT_GT(tight["adaptive_bytes"].get<std::size_t>(), loose["adaptive_bytes"].get<std::size_t>());

  const json budget = stats({file, "--max-points", "8", "--weight-bound", "0", "--samples", "20000"});
  EXPECT_EQ(budget["options"]["simplifier"], "greedy");  // --max-points implies greedy
  EXPECT_EQ(budget["options"]["max_points"], 8);
  EXPECT_EQ(budget["options"]["weight_bound"], 0);
  expectWellFormedReport(budget, {64, 128});
  EXPECT_LE(budget["points"][0].get<std::size_t>(), 8u);  // one 1D CDF on axis 0, no weight bound

  const json greedy = stats({file, "--simplifier", "greedy", "--metric", "perpendicular", "--samples", "20000"});
  EXPECT_EQ(greedy["options"]["simplifier"], "greedy");
  EXPECT_EQ(greedy["options"]["metric"], "perpendicular");
  EXPECT_EQ(greedy["options"]["max_points"], 0);
  expectWellFormedReport(greedy, {64, 128});
}

TEST_F(Cli, SkipsTheChiSquareTestWithZeroSamples) {
  const json j = stats({writePeaked(), "--samples", "0"});
  EXPECT_TRUE(j["chi2_test_pvalue"].is_null());
}

TEST_F(Cli, AllZeroInputFallsBackToUniform) {
  const std::string file = path("zeros.npy");
  writeFile(file, npyF4({16, 8}, std::vector<float>(16 * 8, 0.0f)));
  const json j = stats({file, "--samples", "50000"});
  expectWellFormedReport(j, {16, 8});
  EXPECT_EQ(j["uniform_fallback"], true);
  EXPECT_NEAR(j["chi2_divergence"].get<double>(), 0.0, 1e-6);
}

TEST_F(Cli, OneToFourDimensionsAndFloat64) {
  std::vector<float> v1 = peakedGrid(1, 300);
  writeFile(path("d1.npy"), npyF4({300}, v1));
  expectWellFormedReport(stats({path("d1.npy"), "--samples", "20000"}), {300});

  std::vector<double> v2(40 * 30);
  for (std::size_t i = 0; i < v2.size(); ++i) v2[i] = 1.0 + std::sin(0.1 * static_cast<double>(i));
  writeFile(path("d2.npy"), npyF8({40, 30}, v2, 2));
  expectWellFormedReport(stats({path("d2.npy"), "--samples", "20000"}), {40, 30});

  std::vector<float> v3 = peakedGrid(8 * 6, 10);
  writeFile(path("d3.npy"), npyF4({8, 6, 10}, v3));
  expectWellFormedReport(stats({path("d3.npy"), "--samples", "20000"}), {8, 6, 10});

  std::vector<float> v4 = peakedGrid(4 * 5 * 6, 7);
  writeFile(path("d4.npy"), npyF4({4, 5, 6, 7}, v4, 3));
  expectWellFormedReport(stats({path("d4.npy"), "--samples", "20000"}), {4, 5, 6, 7});
}

TEST_F(Cli, HumanReadableTable) {
  const RunResult r = run({"cdf-stats", writePeaked(), "--samples", "20000"});
  EXPECT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  for (const char* word : {"uniform", "alias", "adaptive", "compression", "chi2 test", "ns per sample"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word << " not in:\n" << r.out;
}

TEST_F(Cli, EightMillionCells) {
  const std::size_t rows = 2048, cols = 4096;
  const std::string file = path("big.npy");
  writeFile(file, npyF4({rows, cols}, peakedGrid(rows, cols)));
  const json j = stats({file, "--samples", "1000000"});
  expectWellFormedReport(j, {rows, cols});
  EXPECT_GT(j["compression"].get<double>(), 1.0);
}

// ---- images ------------------------------------------------------------------------------------

TEST_F(Cli, ImageLuminanceWithNegativePixelsClamped) {
  const int w = 32, h = 16;
  std::vector<float> rgb(static_cast<std::size_t>(w * h * 3), 0.5f);
  rgb[0] = -1.0f;  // pixel 0: luminance 0.2126 * -1 + 0.7152 * .5 + ... > 0: not clamped
  for (int c = 0; c < 3; ++c) {
    rgb[3 * 5 + c] = -0.25f;    // pixel 5: all negative
    rgb[3 * 200 + c] = -1e-3f;  // pixel 200: all slightly negative
  }
  rgb[3 * 300 + 1] = 500.0f;  // a bright green pixel
  const std::string file = path("small.exr");
  writeImage(file, w, h, 3, rgb);
  const json j = stats({file, "--samples", "20000"});
  expectWellFormedReport(j, {static_cast<std::size_t>(h), static_cast<std::size_t>(w)});
  EXPECT_EQ(j["negative_values_clamped"], 2);
  EXPECT_EQ(j["negative_channel_pixels"], 3);
  EXPECT_GT(j["compression"].get<double>(), 1.0);
}

TEST_F(Cli, OneChannelImage) {
  const int w = 20, h = 10;
  std::vector<float> gray(static_cast<std::size_t>(w * h), 1.0f);
  gray[57] = 1000.0f;
  const std::string file = path("gray.exr");
  writeImage(file, w, h, 1, gray);
  const json j = stats({file, "--samples", "20000"});
  expectWellFormedReport(j, {10, 20});
  EXPECT_EQ(j["negative_values_clamped"], 0);
}

// OpenImageIO and the about 250 libraries it links are loaded only for an image that is not
// OpenEXR: glibc's loader, asked to list what it loads (LD_DEBUG=libs), names none of them for a
// run on an EXR file, and acdf's OpenImageIO module for a run on a PNG.
TEST_F(Cli, LoadsOpenImageIoOnlyForAnImageThatIsNotOpenExr) {
  const std::vector<float> rgb(32 * 16 * 3, 0.5f);
  writeImage(path("map.exr"), 32, 16, 3, rgb);
  writeImage(path("map.png"), 32, 16, 3, rgb);
  ASSERT_EQ(setenv("LD_DEBUG", "libs", 1), 0);
  const RunResult exr = run({"cdf-stats", path("map.exr"), "--samples", "0"});
  const RunResult png = run({"cdf-stats", path("map.png"), "--samples", "0"});
  unsetenv("LD_DEBUG");
  ASSERT_EQ(exr.exitCode, 0) << describe(exr);
  ASSERT_EQ(png.exitCode, 0) << describe(png);
  EXPECT_EQ(exr.err.find("OpenImageIO"), std::string::npos) << exr.err;
  EXPECT_EQ(exr.err.find("acdf_openimageio"), std::string::npos) << exr.err;
  EXPECT_NE(png.err.find("acdf_openimageio"), std::string::npos) << png.err;
  EXPECT_NE(png.err.find("libOpenImageIO"), std::string::npos) << png.err;
}

TEST_F(Cli, BundledSunsetEnvironmentMap) {
  const std::string file = sourceDir() + "/data/envmaps/sunset_1024x512.exr";
  if (!fs::exists(file)) GTEST_SKIP() << file << " is not in the source tree";
  const json j = stats({file});
  expectWellFormedReport(j, {512, 1024});
  EXPECT_GT(j["compression"].get<double>(), 1.0);
  EXPECT_EQ(j["uniform_fallback"], false);
  EXPECT_GT(j["chi2_test_pvalue"].get<double>(), 1e-4) << j.dump(2);
}

// ---- bad input: exit 2, one line on stderr naming the file -------------------------------------

TEST_F(Cli, MissingFile) { expectFileError(path("nope.npy"), "no such file"); }

TEST_F(Cli, MissingImage) { expectFileError(path("nope.exr"), "no such file"); }

TEST_F(Cli, Directory) {
  fs::create_directory(path("adir"));
  expectFileError(path("adir"), "directory");
}

TEST_F(Cli, EmptyFile) {
  writeFile(path("empty.npy"), "");
  expectFileError(path("empty.npy"), "empty");
  writeFile(path("empty.exr"), "");
  expectFileError(path("empty.exr"), "empty");
}

TEST_F(Cli, TruncatedNpy) {
  const std::string whole = npyF4({8, 8}, peakedGrid(8, 8));
  writeFile(path("trunc.npy"), whole.substr(0, whole.size() - 1));
  expectFileError(path("trunc.npy"), "truncated");
  writeFile(path("trunc_header.npy"), whole.substr(0, 30));
  expectFileError(path("trunc_header.npy"), "truncated");
}

TEST_F(Cli, BadHeader) {
  writeFile(path("hdr.npy"), npyPreamble("{'descr': '<f4', 'fortran_order': False, 'shape': [4]}") +
                                 rawBytes(std::vector<float>(4, 1.0f)));
  expectFileError(path("hdr.npy"), "bad .npy header");
}

TEST_F(Cli, BadDtype) {
  writeFile(path("int.npy"), npyPreamble(npyDict("<i4", {4})) + rawBytes(std::vector<int32_t>(4, 1)));
  expectFileError(path("int.npy"), "unsupported dtype '<i4'");
  writeFile(path("be.npy"), npyPreamble(npyDict(">f8", {4})) + std::string(32, '\0'));
  expectFileError(path("be.npy"), "big-endian");
}

TEST_F(Cli, FortranOrderTooManyDimsZeroSizeTrailingBytes) {
  writeFile(path("f.npy"), npyPreamble(npyDict("<f4", {2, 2}, true)) + rawBytes(std::vector<float>(4, 1.0f)));
  expectFileError(path("f.npy"), "fortran_order");
  writeFile(path("d5.npy"), npyF4({1, 1, 1, 1, 2}, {1.0f, 2.0f}));
  expectFileError(path("d5.npy"), "at most 4");
  writeFile(path("z.npy"), npyPreamble(npyDict("<f4", {0})));
  expectFileError(path("z.npy"), "size 0");
  writeFile(path("trail.npy"), npyF4({2}, {1.0f, 2.0f}) + "!");
  expectFileError(path("trail.npy"), "1 unexpected bytes");
}

TEST_F(Cli, BadValues) {
  std::vector<float> v = peakedGrid(4, 4);
  v[6] = -3.0f;
  writeFile(path("neg.npy"), npyF4({4, 4}, v));
  expectFileError(path("neg.npy"), "index 6");

  v = peakedGrid(4, 4);
  v[9] = std::numeric_limits<float>::quiet_NaN();
  writeFile(path("nan.npy"), npyF4({4, 4}, v));
  expectFileError(path("nan.npy"), "NaN");

  std::vector<double> d(4, 1.0);
  d[3] = std::numeric_limits<double>::infinity();
  writeFile(path("inf.npy"), npyF8({4}, d));
  expectFileError(path("inf.npy"), "index 3");

  d[3] = 1e200;
  writeFile(path("big.npy"), npyF8({4}, d));
  expectFileError(path("big.npy"), "overflows float32");
}

TEST_F(Cli, AxisTooFineForFloat) {
  // 2^24 cells over [0,1) are narrower than a float can resolve; the engine's GridAxis refuses.
  const std::size_t n = std::size_t{1} << 24;
  writeFile(path("fine.npy"), npyF4({n}, std::vector<float>(n, 1.0f)));
  expectFileError(path("fine.npy"), "axis 0", {"--samples", "0"});
}

TEST_F(Cli, NotAnImage) {
  writeFile(path("notes.txt"), "hello\n");
  expectFileError(path("notes.txt"), "not an image");
  writeFile(path("fake.png"), "definitely not a PNG file, just text pretending to be one\n");
  expectFileError(path("fake.png"), "not an image");
  writeFile(path("noise.exr"), std::string(1000, '\x42'));
  expectFileError(path("noise.exr"), "not an image");
}

TEST_F(Cli, TruncatedImage) {
  const int w = 64, h = 64;
  std::vector<float> rgb(static_cast<std::size_t>(w * h * 3));
  for (std::size_t i = 0; i < rgb.size(); ++i)
    rgb[i] = static_cast<float>(std::sin(0.37 * static_cast<double>(i))) + 1.5f;
  writeImage(path("whole.exr"), w, h, 3, rgb);
  const std::string bytes = readFile(path("whole.exr"));
  writeFile(path("cut.exr"), bytes.substr(0, bytes.size() / 2));
  const RunResult r = run({"cdf-stats", path("cut.exr")});
  EXPECT_EQ(r.signal, 0) << describe(r);
  EXPECT_EQ(r.exitCode, 2) << describe(r);
  const auto lines = r.errLines();
  ASSERT_EQ(lines.size(), 1u) << describe(r);
  EXPECT_EQ(lines[0].rfind("acdf: " + path("cut.exr") + ": ", 0), 0u) << describe(r);
}

TEST_F(Cli, ImageWithNanOrInf) {
  const int w = 8, h = 4;
  std::vector<float> rgb(static_cast<std::size_t>(w * h * 3), 1.0f);
  rgb[3 * 13 + 2] = std::numeric_limits<float>::quiet_NaN();
  writeImage(path("nan.exr"), w, h, 3, rgb);
  expectFileError(path("nan.exr"), "pixel (x 5, y 1)");

  rgb[3 * 13 + 2] = 1.0f;
  rgb[3 * 30] = std::numeric_limits<float>::infinity();
  writeImage(path("inf.exr"), w, h, 3, rgb);
  expectFileError(path("inf.exr"), "pixel (x 6, y 3) has channel R");
}

// ---- usage errors: exit 2, one line ------------------------------------------------------------

TEST_F(Cli, UsageErrors) {
  const std::string file = writePeaked();
  expectUsageError({});
  expectUsageError({"no-such-command"});
  expectUsageError({"cdf-stats"});
  expectUsageError({"cdf-stats", file, "--bogus"});
  expectUsageError({"cdf-stats", file, "--epsilon", "abc"});
  // The library's validator judges; the CLI names the flag.
  expectUsageError({"cdf-stats", file, "--epsilon", "-1"}, "--epsilon must be finite and >= 0, got -1");
  expectUsageError({"cdf-stats", file, "--weight-bound", "0.5"},
                   "--weight-bound must be 0 (no bound) or >= 1, got 0.5");
  expectUsageError({"cdf-stats", file, "--simplifier", "best"});
  expectUsageError({"cdf-stats", file, "--metric", "diagonal"});
  expectUsageError({"cdf-stats", file, "--max-points", "1"}, "--max-points must be at least 2 (the end points)");
  expectUsageError({"cdf-stats", file, "--simplifier", "douglas-peucker", "--max-points", "16"},
                   "--simplifier douglas-peucker");
  expectUsageError({"cdf-stats", file, "--simplifier", "dp"});
  expectUsageError({"cdf-stats", file, "--samples", "-5"});
  expectUsageError({"cdf-stats", file, path("second.npy")});
}

}  // namespace
}  // namespace acdf::apptest

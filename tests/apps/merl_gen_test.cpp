// End-to-end tests of `acdf merl-gen`: the tables it writes agree with the reference tool
// nbrdf_to_merl.py (run with numpy when it and numpy are present), --list, and bad input (exit 2,
// one line on stderr, no partial output file).

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app_test_util.h"

namespace acdf::apptest {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kCells = 90 * 90 * 180;

// The raw values of a .binary file (3 · kCells doubles after the 12-byte header).
std::vector<double> readTable(const std::string& file) {
  const std::string bytes = readFile(file);
  EXPECT_EQ(bytes.size(), 12 + 3 * kCells * sizeof(double)) << file;
  if (bytes.size() != 12 + 3 * kCells * sizeof(double)) return {};
  int32_t dims[3];
  std::memcpy(dims, bytes.data(), 12);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  std::vector<double> values(3 * kCells);
  std::memcpy(values.data(), bytes.data() + 12, values.size() * sizeof(double));
  return values;
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

class MerlGen : public TempDirTest {
 protected:
  RunResult run(const std::vector<std::string>& args) { return runAcdf(args, dir_); }

  // A directory for output files only, so "no partial file" can be checked by listing it.
  fs::path outDir() {
    const fs::path d = dir_ / "out";
    fs::create_directories(d);
    return d;
  }

  // Expects exit 2, nothing on stdout, one stderr line starting "acdf: <prefix>" containing
  // `needle`, and nothing left in outDir().
  void expectFailure(const std::vector<std::string>& args, const std::string& prefix, const std::string& needle) {
    const RunResult r = run(args);
    expectOneLineFailure(r, "acdf: " + prefix, needle);
    EXPECT_TRUE(fs::is_empty(outDir())) << "output left behind after: " << r.err;
  }
};

// acdf merl-gen against nbrdf_to_merl.py: identical −1 masks, values within 1e-5 relative.
void compareWithTool(const fs::path& dir, const std::string& material) {
  const std::string tool = ACDF_NBRDF_TOOL;
  if (!fs::exists(tool)) GTEST_SKIP() << "reference tool " << tool << " not found";
  if (std::system("/usr/bin/python3 -c 'import numpy' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with numpy not available (scripts/install-deps installs python3-numpy)";

  const std::string pyOut = (dir / (material + ".py.binary")).string();
  const std::string ourOut = (dir / (material + ".acdf.binary")).string();
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = std::system(("/usr/bin/python3 " + quoted(tool) + " " + quoted(material) + " " + quoted(pyOut) +
                              " > " + quoted((dir / "py.log").string()) + " 2>&1")
                                 .c_str());
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_EQ(rc, 0) << readFile((dir / "py.log").string());
  const RunResult r = runAcdf({"merl-gen", "--nbrdf", material, "-o", ourOut}, dir);
  const auto t2 = std::chrono::steady_clock::now();
  ASSERT_EQ(r.exitCode, 0) << describe(r);

  const std::vector<double> expected = readTable(pyOut), actual = readTable(ourOut);
  ASSERT_EQ(expected.size(), actual.size());
  std::size_t maskMismatches = 0, invalid = 0, worstIndex = 0;
  double worst = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const bool expectedInvalid = expected[i] == -1.0, actualInvalid = actual[i] == -1.0;
    if (expectedInvalid != actualInvalid) {
      if (maskMismatches++ < 5) ADD_FAILURE() << material << ": mask differs at " << i;
      continue;
    }
    if (expectedInvalid) {
      ++invalid;
      continue;
    }
    const double rel = std::abs(actual[i] - expected[i]) / std::abs(expected[i]);
    if (!(rel <= worst)) {
      worst = rel;
      worstIndex = i;
    }
  }
  EXPECT_EQ(maskMismatches, 0u) << material;
  EXPECT_GT(invalid, 0u);
  EXPECT_LE(worst, 1e-5) << material << " at " << worstIndex << ": " << actual[worstIndex] << " vs "
                         << expected[worstIndex];
  std::cout << "[ merl-gen ] " << material << ": max relative difference " << worst << " over "
            << (expected.size() - invalid) << " valid values, " << invalid / 3 << " cells below the horizon; python "
            << std::chrono::duration<double>(t1 - t0).count() << " s, acdf merl-gen "
            << std::chrono::duration<double>(t2 - t1).count() << " s\n";
}

TEST_F(MerlGen, NickelMatchesTheReferenceTool) { compareWithTool(dir_, "nickel"); }
TEST_F(MerlGen, BlueMetallicPaintMatchesTheReferenceTool) { compareWithTool(dir_, "blue-metallic-paint"); }
TEST_F(MerlGen, SpecularBluePhenolicMatchesTheReferenceTool) { compareWithTool(dir_, "specular-blue-phenolic"); }

TEST_F(MerlGen, ListsTheBundledMaterials) {
  const RunResult r = run({"merl-gen", "--list"});
  ASSERT_EQ(r.exitCode, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  std::size_t lines = 0;
  for (char c : r.out) lines += c == '\n';
  EXPECT_EQ(lines, 100u);
  EXPECT_NE(r.out.find("\nnickel\n"), std::string::npos);
  EXPECT_EQ(r.out.rfind("alum-bronze\n", 0), 0u);
}

TEST_F(MerlGen, HelpDescribesTheCommand) {
  RunResult r = run({"merl-gen", "--help"});
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("--nbrdf"), std::string::npos);
  EXPECT_NE(r.out.find("merl_nbrdf_weights.json"), std::string::npos);
  r = run({"--help"});
  EXPECT_NE(r.out.find("merl-gen"), std::string::npos);
}

TEST_F(MerlGen, UnknownMaterial) {
  const std::string out = (outDir() / "t.binary").string();
  expectFailure({"merl-gen", "--nbrdf", "unobtainium", "-o", out}, "", "no material named 'unobtainium'");
  expectFailure({"merl-gen", "--nbrdf", "unobtainium", "-o", out}, "", "alum-bronze");
}

TEST_F(MerlGen, MissingWeightsFile) {
  const std::string weights = path("nope.json");
  expectFailure({"merl-gen", "--nbrdf", "nickel", "--weights", weights, "-o", (outDir() / "t.binary").string()},
                weights + ": ", "no such file");
  expectFailure({"merl-gen", "--list", "--weights", weights}, weights + ": ", "no such file");
}

TEST_F(MerlGen, BadJson) {
  const std::string weights = path("bad.json");
  writeFile(weights, "{\"nickel\": {\"layers\": [\n{\"W\": [1, 2");
  expectFailure({"merl-gen", "--nbrdf", "nickel", "--weights", weights, "-o", (outDir() / "t.binary").string()},
                weights + ": ", "invalid JSON");
}

TEST_F(MerlGen, WrongLayerShape) {
  const std::string weights = path("shape.json");
  writeFile(weights, R"({"m": {"layers": [{"W": [[1, 2]], "b": [0]}, {"W": [], "b": []}, {"W": [], "b": []}]}})");
  expectFailure({"merl-gen", "--nbrdf", "m", "--weights", weights, "-o", (outDir() / "t.binary").string()},
                weights + ": ", "layer 0 W");
}

TEST_F(MerlGen, UnwritableOutputLeavesNoFile) {
  const fs::path missingDir = outDir() / "no-such-dir";
  const std::string out = (missingDir / "t.binary").string();
  expectFailure({"merl-gen", "--nbrdf", "nickel", "-o", out}, out + ": ", "cannot create a temporary file");
  // The output names a directory: the temporary is written, the rename fails, nothing is left.
  const fs::path asDir = outDir() / "taken";
  fs::create_directories(asDir);
  const RunResult r = run({"merl-gen", "--nbrdf", "nickel", "-o", asDir.string()});
  EXPECT_EQ(r.exitCode, 2) << describe(r);
  EXPECT_EQ(r.errLines().size(), 1u) << describe(r);
  EXPECT_EQ(r.err.rfind("acdf: " + asDir.string() + ": ", 0), 0u) << describe(r);
  std::size_t entries = 0;
  for (const auto& e : fs::directory_iterator(outDir())) entries += e.path() != asDir;
  EXPECT_EQ(entries, 0u);
  EXPECT_TRUE(fs::is_empty(asDir));
}

TEST_F(MerlGen, AnalyticPresets) {
  const fs::path dir = outDir();
  for (const std::string name : {"gold", "rough-aluminium", "red-plastic"}) {
    const std::string out = (dir / (name + ".binary")).string();
    const RunResult r = run({"merl-gen", "--preset", name, "-o", out});
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    const std::vector<double> values = readTable(out);
    ASSERT_EQ(values.size(), 3 * kCells);
    std::size_t invalid = 0;
    for (double v : values) {
      invalid += v == -1.0;
      ASSERT_TRUE(v == -1.0 || v >= 0.0) << name << ": " << v;
    }
    EXPECT_EQ(invalid, 3 * 346568u) << name;  // the horizon mask of every generated table
  }
  const RunResult help = run({"merl-gen", "--help"});
  for (const char* name : {"gold", "rough-aluminium", "red-plastic"})
    EXPECT_NE(help.out.find(std::string("  ") + name + ": "), std::string::npos) << name;
  fs::remove_all(dir);
  expectFailure({"merl-gen", "--preset", "mithril", "-o", (outDir() / "t.binary").string()},
                "merl-gen: ", "no preset named 'mithril' (presets: gold");
  expectFailure({"merl-gen", "--preset", "gold", "--nbrdf", "nickel", "-o", (outDir() / "t.binary").string()},
                "merl-gen: ", "not both");
}

TEST_F(MerlGen, UsageErrors) {
  const std::string out = (outDir() / "t.binary").string();
  expectFailure({"merl-gen", "-o", out}, "", "--nbrdf");
  expectFailure({"merl-gen", "--nbrdf", "nickel"}, "", "-o");
  expectFailure({"merl-gen", "--list", "--nbrdf", "nickel"}, "", "--list");
}

}  // namespace
}  // namespace acdf::apptest

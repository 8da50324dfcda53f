// NeuralBrdf: loading the weights (every error), the network arithmetic on hand-made weights, the
// MERL table it builds (the horizon mask, the cell coordinates, the channel scales), writing it
// with MerlBrdf::saveRaw, and the bundled fits of the 100 MERL materials. The comparison with the
// reference Python tool is in tests/apps/merl_gen_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "acdf/brdf/merl.h"
#include "acdf/brdf/merl_tabulation.h"
#include "acdf/brdf/nbrdf.h"

namespace {

using namespace acdf;
namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = std::numbers::pi;
constexpr std::size_t kN = MerlBrdf::kCells;

const fs::path kBundled = fs::path(ACDF_SOURCE_DIR) / "data" / "merl-nbrdf" / "merl_nbrdf_weights.json";

json zeros(std::size_t rows, std::size_t cols) {
  json m = json::array();
  for (std::size_t r = 0; r < rows; ++r) m.push_back(json(std::vector<double>(cols, 0.0)));
  return m;
}

// A network of the right shapes, all zero.
json zeroNet() {
  json layers = json::array();
  const std::size_t sizes[4] = {6, 21, 21, 3};
  for (int l = 0; l < 3; ++l)
    layers.push_back({{"W", zeros(sizes[l], sizes[l + 1])}, {"b", std::vector<double>(sizes[l + 1], 0.0)}});
  return {{"layers", layers}};
}

class NeuralBrdfTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("acdf_nbrdf_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string writeJson(const json& j) { return write("weights.json", j.dump()); }

  // Expects load() to throw FileError naming `file` whose problem contains `needle`.
  void expectError(const std::string& file, const std::string& material, const std::string& needle) {
    try {
      NeuralBrdf::load(file, material);
      ADD_FAILURE() << "no error for " << file << " / " << material;
    } catch (const FileError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_NE(e.problem().find(needle), std::string::npos) << "'" << needle << "' not in: " << e.problem();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }

  fs::path dir_;
};

TEST_F(NeuralBrdfTest, FileErrors) {
  expectError((dir_ / "nope.json").string(), "nickel", "no such file");
  expectError(dir_.string(), "nickel", "directory");
  expectError(write("bad.json", "{\"nickel\": {\"layers\": [1, 2,"), "nickel", "invalid JSON");
  expectError(write("empty.json", ""), "nickel", "invalid JSON");
  expectError(write("overflow.json", "{\"nickel\": 1e999}"), "nickel", "number overflow");
  expectError(write("array.json", "[1, 2, 3]"), "nickel", "not a JSON object");
}

TEST_F(NeuralBrdfTest, UnknownMaterialNamesSomeThatExist) {
  const std::string file = writeJson({{"gold", zeroNet()}, {"alpha", zeroNet()}});
  expectError(file, "nickel", "no material named 'nickel'");
  expectError(file, "nickel", "alpha, gold");
  EXPECT_EQ(NeuralBrdf::materials(file), (std::vector<std::string>{"alpha", "gold"}));
}

TEST_F(NeuralBrdfTest, WrongLayers) {
  json j = {{"m", zeroNet()}};
  j["m"]["layers"].erase(2);
  expectError(writeJson(j), "m", "2 layers, expected 3");

  j = {{"m", zeroNet()}};
  j["m"]["layers"][1]["W"] = zeros(21, 20);
  expectError(writeJson(j), "m", "layer 1 W is row 0 of length 20, expected 21 x 21");

  j = {{"m", zeroNet()}};
  j["m"]["layers"][0]["W"] = zeros(5, 21);
  expectError(writeJson(j), "m", "layer 0 W is an array of 5 rows, expected 6 x 21");

  j = {{"m", zeroNet()}};
  j["m"]["layers"][2]["b"] = std::vector<double>(4, 0.0);
  expectError(writeJson(j), "m", "layer 2 b is of length 4, expected 3");

  j = {{"m", zeroNet()}};
  j["m"]["layers"][2]["W"][3][1] = "x";
  expectError(writeJson(j), "m", "non-number");

  j = {{"m", zeroNet()}};
  j["m"]["layers"][0].erase("b");
  expectError(writeJson(j), "m", "layer 0 lacks");

  j = {{"m", {{"weights", 1}}}};
  expectError(writeJson(j), "m", "no \"layers\" array");
}

// Hand-made weights whose outputs are known in closed form.
TEST_F(NeuralBrdfTest, NetworkArithmetic) {
  json j = {{"m", zeroNet()}};
  auto& L = j["m"]["layers"];
  L[0]["W"][2][0] = 1.0;   // hidden0 = relu(hz)
  L[0]["W"][2][1] = -1.0;  // hidden1 = relu(-hz) = 0 above the horizon
  L[0]["W"][3][2] = 2.0;   // hidden2 = relu(2 dx + 0.5)
  L[0]["b"][2] = 0.5;
  L[1]["W"][0][0] = 1.0;  // hidden'0 = hidden0
  L[1]["W"][1][1] = 1.0;  // hidden'1 = hidden1
  L[1]["W"][2][2] = 1.0;  // hidden'2 = hidden2
  L[2]["W"][0][0] = 1.0;  // r = hidden'0
  L[2]["W"][1][1] = 5.0;  // g = 5 hidden'1 + log 2
  L[2]["b"][1] = std::log(2.0);
  L[2]["W"][2][2] = 1.0;  // b = hidden'2 - 1
  L[2]["b"][2] = -1.0;
  const NeuralBrdf net = NeuralBrdf::load(writeJson(j), "m");
  EXPECT_EQ(net.name(), "m");

  for (double th : {0.0, 0.3, 1.2}) {
    for (double td : {0.0, 0.5, 1.0}) {
      for (double pd : {0.0, 1.0, 2.5}) {
        const auto f = net.evalHalfDiff(th, td, pd);
        const double dx = std::sin(td) * std::cos(pd);
        EXPECT_NEAR(f[0], std::exp(std::cos(th)) - 1, 1e-14);
        EXPECT_NEAR(f[1], 1.0, 1e-14);
        EXPECT_NEAR(f[2], std::exp(std::max(2 * dx + 0.5, 0.0) - 1) - 1, 1e-14);
      }
    }
  }
  // Below the horizon eval() is 0; above it is the network at the half/difference angles.
  EXPECT_EQ(net.eval({0.6, 0, -0.8}, {0, 0, 1}), Rgb{});
  const Vec3d wi{0.6, 0, 0.8}, wo{-0.6, 0, 0.8};
  const Rgb v = net.eval(wo, wi);
  EXPECT_NEAR(v.r, std::exp(1.0) - 1, 1e-6);  // θh = 0
  EXPECT_NEAR(v.g, 1.0, 1e-6);
}

// The table: −1 exactly where the tool's horizon test says so, elsewhere the network at the cell's
// corner coordinates over the channel scale.
TEST_F(NeuralBrdfTest, MerlTableMaskCoordinatesAndScales) {
  json j = {{"m", zeroNet()}};
  auto& L = j["m"]["layers"];
  for (int k = 0; k < 6; ++k) L[0]["W"][k][k] = 0.25 * (k + 1);  // hidden k = relu(input k / ...)
  for (int k = 0; k < 21; ++k) L[1]["W"][k][k] = 1.0;
  for (int k = 0; k < 6; ++k) L[2]["W"][k][k % 3] = 0.1 * (k + 1);
  L[0]["b"] = std::vector<double>(21, 0.05);
  const NeuralBrdf net = NeuralBrdf::load(writeJson(j), "m");
  const std::vector<double> table = net.merlTable();
  ASSERT_EQ(table.size(), 3 * kN);

  std::size_t below = 0;
  for (int i = 0; i < 90; ++i) {
    for (int jj = 0; jj < 90; ++jj) {
      for (int k = 0; k < 180; ++k) {
        const std::size_t index = MerlBrdf::flatIndex(i, jj, k);
        const double thetaHalf = (i / 90.0) * (i / 90.0) * (kPi / 2);
        const double thetaDiff = jj / 90.0 * (kPi / 2);
        const double phiDiff = k / 180.0 * kPi;
        // The geometry: both directions above the horizon, up to rounding right at it.
        const DirectionPair p = fromHalfDiff({thetaHalf, 0.0, thetaDiff, phiDiff});
        const bool marked = merlCellBelowHorizon(i, jj, k);
        if (std::min(p.wi.z, p.wo.z) > 1e-12) {
          ASSERT_FALSE(marked) << i << " " << jj << " " << k;
        }
        if (std::min(p.wi.z, p.wo.z) < -1e-12) {
          ASSERT_TRUE(marked) << i << " " << jj << " " << k;
        }
        if (marked) {
          ++below;
          for (int c = 0; c < 3; ++c) ASSERT_EQ(table[c * kN + index], -1.0);
          continue;
        }
        if ((index % 997) != 0) continue;  // the values: a sample of cells
        const auto f = net.evalHalfDiff(thetaHalf, thetaDiff, phiDiff);
        for (int c = 0; c < 3; ++c) {
          const double expected = f[c] / MerlBrdf::kChannelScale[c];
          ASSERT_NEAR(table[c * kN + index], expected, 1e-12 * std::abs(expected)) << index << " channel " << c;
        }
      }
    }
  }
  // Roughly the part of (θh, θd, φd) space with θh + θd beyond π/2 in some φd.
  EXPECT_GT(below, kN / 10);
  EXPECT_LT(below, kN / 2);
  EXPECT_FALSE(merlCellBelowHorizon(0, 89, 0));  // θh = 0: only θd matters
  EXPECT_TRUE(merlCellBelowHorizon(89, 89, 0));
}

TEST_F(NeuralBrdfTest, SaveRawKeepsMinusOneAndDoubles) {
  std::vector<double> values(3 * kN);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = (i % 7 == 0) ? -1.0 : 1.0 / 3.0 + i * 1e-9;
  const std::string file = (dir_ / "t.binary").string();
  MerlBrdf::saveRaw(file, values);
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(bytes.size(), 12 + values.size() * sizeof(double));
  int32_t dims[3];
  std::memcpy(dims, bytes.data(), 12);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  EXPECT_EQ(std::memcmp(bytes.data() + 12, values.data(), values.size() * sizeof(double)), 0);
  // MerlBrdf reads it, counting the −1 marks as negative entries.
  const MerlBrdf brdf = MerlBrdf::load(file);
  std::size_t marks = 0;
  for (std::size_t i = 0; i < values.size(); ++i) marks += values[i] < 0;
  EXPECT_EQ(brdf.negativeEntries(), marks);

  values[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(MerlBrdf::saveRaw(file, values), std::invalid_argument);
  values.pop_back();
  EXPECT_THROW(MerlBrdf::saveRaw(file, values), std::invalid_argument);
  EXPECT_THROW(MerlBrdf::saveRaw((dir_ / "no" / "dir" / "t.binary").string(), std::vector<double>(3 * kN, 1.0)),
               FileError);
  EXPECT_FALSE(fs::exists(dir_ / "no"));
}

TEST_F(NeuralBrdfTest, BundledFitsOfTheHundredMerlMaterials) {
  if (!fs::exists(kBundled)) GTEST_SKIP() << kBundled << " is not in the source tree";
  const std::vector<std::string> names = NeuralBrdf::materials(kBundled);
  EXPECT_EQ(names.size(), 100u);
  for (const char* m : {"nickel", "blue-metallic-paint", "specular-blue-phenolic", "alum-bronze"})
    EXPECT_TRUE(std::binary_search(names.begin(), names.end(), m)) << m;
  for (const std::string& m : names) {
    const NeuralBrdf net = NeuralBrdf::load(kBundled, m);
    // Finite; positive at the specular peak; away from it at most slightly negative (exp(x) − 1
    // of a fit: chrome-steel gives −5e-4 there). Fabrics are brighter off the peak than on it.
    const auto peak = net.evalHalfDiff(0.0, 0.3, kPi / 2);
    const auto off = net.evalHalfDiff(1.2, 0.3, kPi / 2);
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(peak[c]) && peak[c] > 0) << m << " channel " << c << ": " << peak[c];
      EXPECT_TRUE(std::isfinite(off[c]) && off[c] > -0.01) << m << " channel " << c << ": " << off[c];
    }
  }
  // Nickel is a metal: a strong peak.
  const NeuralBrdf nickel = NeuralBrdf::load(kBundled, "nickel");
  EXPECT_GT(nickel.evalHalfDiff(0.0, 0.3, kPi / 2)[1], 10 * nickel.evalHalfDiff(0.8, 0.3, kPi / 2)[1]);
}

}  // namespace

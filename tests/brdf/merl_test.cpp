// MerlBrdf: the .binary format (round trip, every malformed-file error), negative entries, the
// MERL cell indexing, nearest and trilinear evaluation, reciprocity, and the load time of a
// full-size file (reported, not asserted).

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "acdf/brdf/merl.h"

namespace {

using namespace acdf;
namespace fs = std::filesystem;
using Interp = MerlBrdf::Interpolation;

constexpr double kPi = std::numbers::pi;
constexpr std::size_t kN = MerlBrdf::kCells;
constexpr std::size_t kFileBytes = 12 + 3 * kN * sizeof(double);

// Three channels of raw values in file order.
struct Table {
  std::vector<double> c[3];
  MerlBrdf brdf() const { return MerlBrdf(c[0], c[1], c[2]); }
};

// Random raw values in [0, 3000), each exactly a float so a float round trip is exact.
Table randomTable(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 3000.0f);
  Table t;
  for (auto& ch : t.c) {
    ch.resize(kN);
    for (double& v : ch) v = u(rng);
  }
  return t;
}

// A reciprocal analytic BRDF of (θh, θd, φd mod π), tabulated at the cell centres.
double analytic(int channel, double thetaHalf, double thetaDiff, double phiDiff) {
  return 100.0 * (1 + channel) + 800.0 * std::exp(-8 * thetaHalf) + 50.0 * thetaDiff + 30.0 * std::cos(2 * phiDiff) +
         10.0 * std::sin(2 * phiDiff);
}
Table analyticTable() {
  Table t;
  for (auto& ch : t.c) ch.resize(kN);
  for (int h = 0; h < MerlBrdf::kThetaHalfCells; ++h)
    for (int d = 0; d < MerlBrdf::kThetaDiffCells; ++d)
      for (int p = 0; p < MerlBrdf::kPhiDiffCells; ++p)
        for (int c = 0; c < 3; ++c)
          t.c[c][MerlBrdf::flatIndex(h, d, p)] =
              analytic(c, MerlBrdf::thetaHalfCentre(h), MerlBrdf::thetaDiffCentre(d), MerlBrdf::phiDiffCentre(p));
  return t;
}

// The bytes of a .binary file.
std::vector<unsigned char> fileBytes(const Table& t, int32_t d0 = 90, int32_t d1 = 90, int32_t d2 = 180) {
  std::vector<unsigned char> bytes(kFileBytes);
  const int32_t dims[3] = {d0, d1, d2};
  std::memcpy(bytes.data(), dims, 12);
  for (int c = 0; c < 3; ++c) std::memcpy(bytes.data() + 12 + c * kN * 8, t.c[c].data(), kN * 8);
  return bytes;
}

void writeFile(const fs::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

void setDouble(std::vector<unsigned char>& bytes, int channel, std::size_t index, double v) {
  std::memcpy(bytes.data() + 12 + (channel * kN + index) * 8, &v, 8);
}

// The value nearest lookup must return for cell `index`: raw × channel scale, in float.
Rgb expectedCell(const MerlBrdf& b, std::size_t index) {
  return {static_cast<float>(b.value(0, index) * MerlBrdf::kChannelScale[0]),
          static_cast<float>(b.value(1, index) * MerlBrdf::kChannelScale[1]),
          static_cast<float>(b.value(2, index) * MerlBrdf::kChannelScale[2])};
}

void expectRgbNear(const Rgb& a, const Rgb& b, double relative, const std::string& where) {
  EXPECT_NEAR(a.r, b.r, relative * std::fabs(b.r) + 1e-30) << where;
  EXPECT_NEAR(a.g, b.g, relative * std::fabs(b.g) + 1e-30) << where;
  EXPECT_NEAR(a.b, b.b, relative * std::fabs(b.b) + 1e-30) << where;
}

class MerlFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("acdf_brdf_test_" + std::to_string(rd()) + std::to_string(rd()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path file(const std::string& name) const { return dir_ / name; }
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  // Expects load(path) to throw a FileError naming the file and containing `problem`.
  void expectLoadError(const fs::path& path, const std::string& problem) {
    try {
      (void)MerlBrdf::load(path);
      ADD_FAILURE() << "no error loading " << path << ", expected: " << problem;
    } catch (const FileError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(problem), std::string::npos) << what << "\n  expected: " << problem;
      EXPECT_EQ(e.file(), path.string());
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// Reading and writing

TEST_F(MerlFiles, SaveLoadRoundTrip) {
  const Table t = randomTable(1);
  const MerlBrdf a = t.brdf();
  const fs::path path = file("round trip.binary");  // a space, to be sure names pass through
  a.save(path);
  ASSERT_EQ(fs::file_size(path), kFileBytes);

  // The bytes are the format: header 90 90 180, then the channels as float64.
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bytes(kFileBytes);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(kFileBytes));
  EXPECT_EQ(bytes, fileBytes(t));

  const MerlBrdf b = MerlBrdf::load(path);
  EXPECT_EQ(b.negativeEntries(), 0u);
  for (int c = 0; c < 3; ++c) {
    ASSERT_TRUE(std::ranges::equal(a.channel(c), b.channel(c))) << "channel " << c;
    for (std::size_t i : {std::size_t{0}, std::size_t{12345}, kN - 1}) EXPECT_EQ(b.value(c, i), t.c[c][i]);
  }
  EXPECT_EQ(entries(), 1u) << "a temporary file was left behind";
}

TEST_F(MerlFiles, LoadRoundsDoublesToNearestFloat) {
  Table t = randomTable(2);
  t.c[1][7] = 0.1;  // not a float
  writeFile(file("x.binary"), fileBytes(t));
  EXPECT_EQ(MerlBrdf::load(file("x.binary")).value(1, 7), 0.1f);
}

TEST_F(MerlFiles, SaveReplacesAnExistingFile) {
  const fs::path path = file("brdf.binary");
  writeFile(path, {1, 2, 3});
  const MerlBrdf a = randomTable(3).brdf();
  a.save(path);
  EXPECT_TRUE(std::ranges::equal(MerlBrdf::load(path).channel(2), a.channel(2)));
  EXPECT_EQ(entries(), 1u);
}

TEST_F(MerlFiles, FailedSaveLeavesNoOutput) {
  const MerlBrdf a = randomTable(4).brdf();
  // Into a directory that does not exist.
  const fs::path missing = file("no such dir") / "brdf.binary";
  try {
    a.save(missing);
    ADD_FAILURE() << "save into a missing directory succeeded";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing));
  // Over a directory: the rename fails, the temporary is removed, the directory untouched.
  const fs::path target = file("target");
  fs::create_directory(target);
  writeFile(target / "keep", {42});
  EXPECT_THROW(a.save(target), FileError);
  EXPECT_TRUE(fs::is_directory(target));
  EXPECT_TRUE(fs::exists(target / "keep"));
  EXPECT_EQ(entries(), 1u) << "a temporary file was left behind";
}

// A signal that kills the program mid-write (here SIGXFSZ past a 1 MB file-size limit, as Ctrl-C
// would) must not leave the partial temporary behind (acdf/sampling/temporary_files.h); the child
// still dies of the signal.
TEST_F(MerlFiles, SignalDuringSaveLeavesNoTemporaryFile) {
  const MerlBrdf a = randomTable(6).brdf();
  const fs::path path = file("killed.binary");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlimit limit{1 << 20, 1 << 20};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      a.save(path);
    } catch (...) {
    }
    _exit(0);  // not reached: the write past the limit raises SIGXFSZ
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGXFSZ) << "status " << status;
  EXPECT_EQ(entries(), 0u) << "a temporary file was left behind";
}

TEST_F(MerlFiles, MissingFile) { expectLoadError(file("absent.binary"), "no such file"); }

TEST_F(MerlFiles, Directory) {
  fs::create_directory(file("dir.binary"));
  expectLoadError(file("dir.binary"), "is a directory");
}

TEST_F(MerlFiles, TruncatedHeader) {
  writeFile(file("empty.binary"), {});
  expectLoadError(file("empty.binary"), "truncated header");
  writeFile(file("short.binary"), {90, 0, 0, 0, 90, 0, 0, 0});
  expectLoadError(file("short.binary"), "truncated header: the file has 8 bytes");
}

TEST_F(MerlFiles, WrongDimensions) {
  const Table t = randomTable(5);
  writeFile(file("dims.binary"), fileBytes(t, 90, 90, 90));
  expectLoadError(file("dims.binary"), "wrong dimensions 90 x 90 x 90");
  // The right product from negative dimensions is still wrong.
  writeFile(file("negdims.binary"), fileBytes(t, -90, -90, 180));
  expectLoadError(file("negdims.binary"), "wrong dimensions -90 x -90 x 180");
  // A product that overflows int32 is not mistaken for the right one.
  writeFile(file("huge.binary"), fileBytes(t, 1 << 20, 1 << 20, 1 << 20));
  expectLoadError(file("huge.binary"), "wrong dimensions 1048576 x 1048576 x 1048576");
  // Nor one beyond int64 (signed overflow, found by fuzz/merl_fuzz.cpp; UBSan flags it).
  writeFile(file("huger.binary"), fileBytes(t, 2147483647, 2147483647, 2147483647));
  expectLoadError(file("huger.binary"), "wrong dimensions 2147483647 x 2147483647 x 2147483647");
}

TEST_F(MerlFiles, TruncatedData) {
  std::vector<unsigned char> bytes = fileBytes(randomTable(6));
  bytes.resize(bytes.size() - 8);
  writeFile(file("cut.binary"), bytes);
  expectLoadError(file("cut.binary"), "truncated data");
  bytes.resize(12);
  writeFile(file("header-only.binary"), bytes);
  expectLoadError(file("header-only.binary"), "truncated data: 0 bytes after the header");
}

TEST_F(MerlFiles, ExtraTrailingBytes) {
  std::vector<unsigned char> bytes = fileBytes(randomTable(7));
  bytes.push_back(0);
  writeFile(file("long.binary"), bytes);
  expectLoadError(file("long.binary"), "1 extra trailing bytes");
}

TEST_F(MerlFiles, NonFiniteValues) {
  const std::vector<unsigned char> good = fileBytes(randomTable(8));
  std::vector<unsigned char> bytes = good;
  setDouble(bytes, 1, 12345, std::numeric_limits<double>::quiet_NaN());
  writeFile(file("nan.binary"), bytes);
  expectLoadError(file("nan.binary"), "NaN in the green channel at index 12345");

  bytes = good;
  setDouble(bytes, 2, kN - 1, std::numeric_limits<double>::infinity());
  writeFile(file("inf.binary"), bytes);
  expectLoadError(file("inf.binary"),
                  "+Inf in the blue channel at index 1457999 (theta_h cell 89, theta_d cell 89, phi_d cell 179)");

  bytes = good;
  setDouble(bytes, 0, 0, -std::numeric_limits<double>::infinity());  // negative, but not a −1 marker
  writeFile(file("-inf.binary"), bytes);
  expectLoadError(file("-inf.binary"), "-Inf in the red channel at index 0");

  bytes = good;
  setDouble(bytes, 0, 3, 1e300);
  writeFile(file("big.binary"), bytes);
  expectLoadError(file("big.binary"), "value 1e+300 (beyond float range) in the red channel at index 3");
}

TEST_F(MerlFiles, NegativeEntriesReadAsZeroAndAreCounted) {
  Table t = randomTable(9);
  const std::size_t marked[] = {0, 1, 500, kN - 1};
  for (int c = 0; c < 3; ++c)
    for (std::size_t i : marked) t.c[c][i] = -1.0;
  t.c[1][77] = -0.5;
  writeFile(file("neg.binary"), fileBytes(t));
  const MerlBrdf b = MerlBrdf::load(file("neg.binary"));
  EXPECT_EQ(b.negativeEntries(), 3 * std::size(marked) + 1);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i : marked) EXPECT_EQ(b.value(c, i), 0.0f);
  EXPECT_EQ(b.value(1, 77), 0.0f);
  EXPECT_EQ(b.value(0, 77), static_cast<float>(t.c[0][77]));
  // The below-horizon cell evaluates to 0.
  const Rgb v =
      b.evalHalfDiff(MerlBrdf::thetaHalfCentre(89), MerlBrdf::thetaDiffCentre(89), MerlBrdf::phiDiffCentre(179));
  EXPECT_EQ(v, Rgb{});
  // The constructor treats them the same way.
  EXPECT_EQ(t.brdf().negativeEntries(), 3 * std::size(marked) + 1);
}

// ---------------------------------------------------------------------------------------------
// Construction

TEST(MerlBrdf, ConstructorValidates) {
  Table t = randomTable(10);
  t.c[2].pop_back();
  try {
    (void)t.brdf();
    ADD_FAILURE() << "short channel accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("blue channel has 1457999 values"), std::string::npos) << e.what();
  }
  t = randomTable(10);
  t.c[0][99] = std::numeric_limits<double>::quiet_NaN();
  try {
    (void)t.brdf();
    ADD_FAILURE() << "NaN accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("NaN in the red channel at index 99"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Indexing

TEST(MerlBrdf, CellIndices) {
  // θh: square-root spacing, clamped.
  EXPECT_EQ(MerlBrdf::thetaHalfIndex(0.0), 0);
  EXPECT_EQ(MerlBrdf::thetaHalfIndex(-0.3), 0);
  EXPECT_EQ(MerlBrdf::thetaHalfIndex(std::nan("")), 0);
  EXPECT_EQ(MerlBrdf::thetaHalfIndex(kPi / 2), 89);
  EXPECT_EQ(MerlBrdf::thetaHalfIndex(kPi), 89);
  EXPECT_EQ(MerlBrdf::thetaHalfIndex(kPi / 4), 63);  // √0.5 · 90 = 63.6
  for (int k = 0; k < 90; ++k) {
    EXPECT_EQ(MerlBrdf::thetaHalfIndex(MerlBrdf::thetaHalfCentre(k)), k);
    // Just inside the lower boundary (k/90)² · π/2.
    if (k > 0) {
      EXPECT_EQ(MerlBrdf::thetaHalfIndex(double(k) * k / 8100 * kPi / 2 * (1 + 1e-9)), k);
    }
  }
  // θd: linear, clamped.
  EXPECT_EQ(MerlBrdf::thetaDiffIndex(-1.0), 0);
  EXPECT_EQ(MerlBrdf::thetaDiffIndex(kPi / 4), 45);
  EXPECT_EQ(MerlBrdf::thetaDiffIndex(kPi / 2), 89);
  EXPECT_EQ(MerlBrdf::thetaDiffIndex(3.0), 89);
  for (int k = 0; k < 90; ++k) EXPECT_EQ(MerlBrdf::thetaDiffIndex(MerlBrdf::thetaDiffCentre(k)), k);
  // φd: folded into [0, π) by reciprocity.
  for (int k = 0; k < 180; ++k) {
    const double phi = MerlBrdf::phiDiffCentre(k);
    EXPECT_EQ(MerlBrdf::phiDiffIndex(phi), k);
    EXPECT_EQ(MerlBrdf::phiDiffIndex(phi - kPi), k);
    EXPECT_EQ(MerlBrdf::phiDiffIndex(phi + kPi), k);
  }
  EXPECT_EQ(MerlBrdf::phiDiffIndex(0.0), 0);
  EXPECT_EQ(MerlBrdf::phiDiffIndex(kPi), 0);
  EXPECT_EQ(MerlBrdf::phiDiffIndex(-kPi), 0);
  EXPECT_EQ(MerlBrdf::phiDiffIndex(-0.5 * kPi / 180), 179);
  EXPECT_EQ(MerlBrdf::phiDiffIndex(std::nan("")), 0);
  EXPECT_EQ(MerlBrdf::flatIndex(89, 89, 179), MerlBrdf::kCells - 1);
  EXPECT_EQ(MerlBrdf::flatIndex(1, 2, 3), std::size_t{1} * 90 * 180 + 2 * 180 + 3);
}

// ---------------------------------------------------------------------------------------------
// Evaluation

class MerlEval : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { brdf_ = std::make_unique<MerlBrdf>(randomTable(11).brdf()); }
  static void TearDownTestSuite() { brdf_.reset(); }
  static std::unique_ptr<MerlBrdf> brdf_;
};
std::unique_ptr<MerlBrdf> MerlEval::brdf_;

TEST_F(MerlEval, NearestAtCellCentresIsTheTable) {
  const MerlBrdf& b = *brdf_;
  for (int h = 0; h < 90; ++h)
    for (int d = 0; d < 90; ++d)
      for (int p = 0; p < 180; ++p) {
        const std::size_t i = MerlBrdf::flatIndex(h, d, p);
        const Rgb v =
            b.evalHalfDiff(MerlBrdf::thetaHalfCentre(h), MerlBrdf::thetaDiffCentre(d), MerlBrdf::phiDiffCentre(p));
        ASSERT_EQ(v, expectedCell(b, i)) << h << " " << d << " " << p;
      }
}

TEST_F(MerlEval, NearestFromDirectionsAtCellCentres) {
  // Every cell whose centre is a pair of upper-hemisphere directions, reached through eval(ωo, ωi)
  // at a random φh, and with ωi and ωo swapped.
  const MerlBrdf& b = *brdf_;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-kPi, kPi);
  std::size_t checked = 0;
  for (int h = 0; h < 90; h += 3)
    for (int d = 0; d < 90; ++d)
      for (int p = 0; p < 180; ++p) {
        const HalfDiffAngles a{MerlBrdf::thetaHalfCentre(h), u(rng), MerlBrdf::thetaDiffCentre(d),
                               MerlBrdf::phiDiffCentre(p)};
        const DirectionPair w = fromHalfDiff(a);
        if (w.wi.z < 1e-3 || w.wo.z < 1e-3) continue;
        const Rgb expected = expectedCell(b, MerlBrdf::flatIndex(h, d, p));
        ASSERT_EQ(b.eval(w.wo, w.wi), expected) << h << " " << d << " " << p;
        ASSERT_EQ(b.eval(w.wi, w.wo), expected) << h << " " << d << " " << p;
        ++checked;
      }
  EXPECT_GT(checked, 100000u);
}

TEST_F(MerlEval, TrilinearEqualsNearestAtCellCentres) {
  const MerlBrdf& b = *brdf_;
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  for (int h = 0; h < 90; ++h)
    for (int d = 0; d < 90; d += 7)
      for (int p = 0; p < 180; p += 5) {
        const double th = MerlBrdf::thetaHalfCentre(h), td = MerlBrdf::thetaDiffCentre(d),
                     pd = MerlBrdf::phiDiffCentre(p);
        expectRgbNear(trilinear.evalHalfDiff(th, td, pd), b.evalHalfDiff(th, td, pd), 1e-6,
                      std::to_string(h) + " " + std::to_string(d) + " " + std::to_string(p));
      }
}

TEST_F(MerlEval, TrilinearIsLinearInThetaDiffBetweenCentres) {
  const MerlBrdf& b = *brdf_;
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  const int h = 40, p = 100;
  const double th = MerlBrdf::thetaHalfCentre(h), pd = MerlBrdf::phiDiffCentre(p);
  for (int d = 0; d + 1 < 90; ++d) {
    const Rgb lo = expectedCell(b, MerlBrdf::flatIndex(h, d, p)),
              hi = expectedCell(b, MerlBrdf::flatIndex(h, d + 1, p));
    for (double t : {0.1, 0.25, 0.5, 0.8}) {
      const double td = MerlBrdf::thetaDiffCentre(d) + t * (kPi / 2) / 90;
      const Rgb expected{static_cast<float>((1 - t) * lo.r + t * hi.r), static_cast<float>((1 - t) * lo.g + t * hi.g),
                         static_cast<float>((1 - t) * lo.b + t * hi.b)};
      expectRgbNear(trilinear.evalHalfDiff(th, td, pd), expected, 1e-5,
                    "d = " + std::to_string(d) + ", t = " + std::to_string(t));
    }
  }
}

TEST_F(MerlEval, TrilinearIsLinearInSqrtThetaHalf) {
  // Halfway between two θh centres in √θh, not in θh.
  const MerlBrdf& b = *brdf_;
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  const int d = 30, p = 60;
  for (int h : {0, 10, 50, 88}) {
    const Rgb lo = expectedCell(b, MerlBrdf::flatIndex(h, d, p)),
              hi = expectedCell(b, MerlBrdf::flatIndex(h + 1, d, p));
    const double s = (h + 1.0) / 90;  // √(θh / (π/2)) halfway between the centres
    const Rgb expected{(lo.r + hi.r) / 2, (lo.g + hi.g) / 2, (lo.b + hi.b) / 2};
    expectRgbNear(trilinear.evalHalfDiff(s * s * kPi / 2, MerlBrdf::thetaDiffCentre(d), MerlBrdf::phiDiffCentre(p)),
                  expected, 1e-5, "h = " + std::to_string(h));
  }
}

TEST_F(MerlEval, TrilinearClampsAtTheThetaEnds) {
  const MerlBrdf& b = *brdf_;
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  const int h = 20, p = 33;
  const double th = MerlBrdf::thetaHalfCentre(h), pd = MerlBrdf::phiDiffCentre(p);
  const Rgb first = expectedCell(b, MerlBrdf::flatIndex(h, 0, p)),
            last = expectedCell(b, MerlBrdf::flatIndex(h, 89, p));
  for (double td : {0.0, 0.3 * (kPi / 2) / 90})
    expectRgbNear(trilinear.evalHalfDiff(th, td, pd), first, 1e-6, "low θd");
  for (double td : {MerlBrdf::thetaDiffCentre(89) + 1e-4, kPi / 2, 2.0})
    expectRgbNear(trilinear.evalHalfDiff(th, td, pd), last, 1e-6, "high θd");
  const Rgb h0 = expectedCell(b, MerlBrdf::flatIndex(0, 10, p)), h89 = expectedCell(b, MerlBrdf::flatIndex(89, 10, p));
  expectRgbNear(trilinear.evalHalfDiff(0.0, MerlBrdf::thetaDiffCentre(10), pd), h0, 1e-6, "θh = 0");
  expectRgbNear(trilinear.evalHalfDiff(kPi / 2, MerlBrdf::thetaDiffCentre(10), pd), h89, 1e-6, "θh = π/2");
}

TEST_F(MerlEval, TrilinearWrapsPhiDiffWithPeriodPi) {
  const MerlBrdf& b = *brdf_;
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  const int h = 12, d = 45;
  const double th = MerlBrdf::thetaHalfCentre(h), td = MerlBrdf::thetaDiffCentre(d);
  const Rgb c0 = expectedCell(b, MerlBrdf::flatIndex(h, d, 0)), c179 = expectedCell(b, MerlBrdf::flatIndex(h, d, 179));
  const Rgb mid{(c0.r + c179.r) / 2, (c0.g + c179.g) / 2, (c0.b + c179.b) / 2};
  for (double pd : {0.0, kPi, -kPi, 2 * kPi})
    expectRgbNear(trilinear.evalHalfDiff(th, td, pd), mid, 1e-5, "φd = " + std::to_string(pd));
  for (double pd : {0.001, 0.3, 1.7, 3.1}) {
    const Rgb v = trilinear.evalHalfDiff(th, td, pd);
    expectRgbNear(trilinear.evalHalfDiff(th, td, pd - kPi), v, 1e-6, "φd − π");
    expectRgbNear(trilinear.evalHalfDiff(th, td, pd + kPi), v, 1e-6, "φd + π");
  }
}

TEST_F(MerlEval, ZeroBelowTheHorizon) {
  const MerlBrdf& b = *brdf_;
  const Vec3d up{0, 0, 1}, below = sphericalDirection(2.0, 0.5), grazing{std::cos(1.0), std::sin(1.0), 0.0};
  for (Interp mode : {Interp::Nearest, Interp::Trilinear}) {
    const MerlBrdf m = b.withInterpolation(mode);
    EXPECT_NE(m.eval(up, up), Rgb{});
    EXPECT_EQ(m.eval(below, up), Rgb{});
    EXPECT_EQ(m.eval(up, below), Rgb{});
    EXPECT_EQ(m.eval(below, below), Rgb{});
    EXPECT_EQ(m.eval(up, grazing), Rgb{});
  }
}

// At exact normal incidence the lookup is deterministic: the φd = 0 cell, whatever the azimuth
// of the other direction (rounding used to pick cell 0 or 179 for the same θ).
TEST_F(MerlEval, NormalIncidenceLooksUpThePhiDiffZeroCell) {
  const MerlBrdf& b = *brdf_;
  const Vec3d normal{0, 0, 1};
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 20000; ++n) {
    const Vec3d w = sphericalDirection(std::acos(1 - 0.999 * u(rng)), (2 * u(rng) - 1) * kPi);
    const HalfDiffAngles a = toHalfDiff(normal, w);
    const Rgb expected = expectedCell(
        b, MerlBrdf::flatIndex(MerlBrdf::thetaHalfIndex(a.thetaHalf), MerlBrdf::thetaDiffIndex(a.thetaDiff), 0));
    ASSERT_EQ(b.eval(normal, w), expected) << n;
    ASSERT_EQ(b.eval(w, normal), expected) << n;
  }
}

// MerlBrdf::cellOf (no atan2) is the cell of the angles for every pair above the horizon: at
// random, at and a few ulps around every cell boundary of θh, θd and φd (the fold at φd = π and
// the seam at 0 = 2π included), on the normal, and for pairs not of unit length.
TEST(MerlBrdf, CellOfIsTheCellOfTheAngles) {
  int mismatches = 0, checked = 0;
  const auto check = [&](const Vec3d& wo, const Vec3d& wi) {
    if (!(wo.z > 0 && wi.z > 0)) return;
    ++checked;
    const std::size_t fast = MerlBrdf::cellOf(wo, wi), exact = MerlBrdf::cellByAngles(wo, wi);
    if (fast != exact && ++mismatches <= 10)
      ADD_FAILURE() << std::hexfloat << "wo = (" << wo.x << ", " << wo.y << ", " << wo.z << "), wi = (" << wi.x
                    << ", " << wi.y << ", " << wi.z << "): cell " << fast << " instead of " << exact;
  };
  // The pair and its neighbours one ulp away in each component of ωi.
  const auto checkAround = [&](const DirectionPair& p) {
    for (double dx : {-1.0, 0.0, 1.0})
      for (double dy : {-1.0, 0.0, 1.0})
        for (double dz : {-1.0, 0.0, 1.0}) {
          const auto step = [](double v, double d) { return d == 0 ? v : std::nextafter(v, d * INFINITY); };
          check(p.wo, {step(p.wi.x, dx), step(p.wi.y, dy), step(p.wi.z, dz)});
        }
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto hemisphere = [&] { return sphericalDirection(std::acos(unit(rng)), 2 * kPi * unit(rng)); };
  for (int i = 0; i < 1'000'000; ++i) {
    const Vec3d wo = hemisphere(), wi = hemisphere();
    check(wo, wi);
    if (i % 16 == 0) check(wo * (0.25 + 4 * unit(rng)), wi * (0.25 + 4 * unit(rng)));
  }
  // Angles at each boundary, shifted by relative amounts from below one ulp to well past the
  // lookup's margin, either way.
  const auto around = [](double boundary) {
    std::vector<double> angles{boundary};
    for (double shift : {1e-17, 1e-16, 3e-16, 1e-15, 1e-12, 1e-10, 1e-9, 2e-9, 1e-8})
      for (double sign : {-1.0, 1.0}) angles.push_back(boundary * (1 + sign * shift));
    return angles;
  };
  const auto pairAt = [](double thetaHalf, double phiHalf, double thetaDiff, double phiDiff) {
    return fromHalfDiff({thetaHalf, phiHalf, thetaDiff, phiDiff});
  };
  for (int k = 1; k < MerlBrdf::kThetaHalfCells; ++k) {
    const double s = static_cast<double>(k) / MerlBrdf::kThetaHalfCells;
    for (double thetaHalf : around(s * s * kPi / 2))
      for (int i = 0; i < 4; ++i)
        checkAround(pairAt(thetaHalf, 2 * kPi * unit(rng), 0.3 * unit(rng), 2 * kPi * unit(rng)));
  }
  for (int k = 1; k < MerlBrdf::kThetaDiffCells; ++k)
    for (double thetaDiff : around(k * kPi / 2 / MerlBrdf::kThetaDiffCells))
      for (int i = 0; i < 4; ++i)
        checkAround(pairAt(0.05 * unit(rng), 2 * kPi * unit(rng), thetaDiff, 2 * kPi * unit(rng)));
  std::vector<double> phiBoundaries{-kPi, 0.0, kPi, 2 * kPi};
  for (int k = 1; k < MerlBrdf::kPhiDiffCells; ++k)
    for (double offset : {0.0, kPi, -kPi}) phiBoundaries.push_back(offset + k * kPi / MerlBrdf::kPhiDiffCells);
  for (double boundary : phiBoundaries) {
    std::vector<double> phis = around(boundary);
    for (double tiny : {1e-300, 1e-17, 1e-16, 1e-12}) phis.insert(phis.end(), {boundary + tiny, boundary - tiny});
    for (double phiDiff : phis)
      for (int i = 0; i < 4; ++i)
        checkAround(pairAt(0.4 * unit(rng), 2 * kPi * unit(rng), 0.05 + 0.7 * unit(rng), phiDiff));
  }
  // On the normal, either or both; mirror pairs; grazing.
  for (int i = 0; i < 10'000; ++i) {
    const Vec3d w = hemisphere();
    check({0, 0, 1}, w);
    check(w, {0, 0, 1});
    check(w, w);
    check(w, {-w.x, -w.y, w.z});
    check(w, {w.x, w.y, 1e-12});
  }
  check({0, 0, 1}, {0, 0, 1});
  EXPECT_EQ(mismatches, 0) << "of " << checked;
  EXPECT_GT(checked, 2'000'000);
}

TEST(MerlBrdf, Reciprocity) {
  const MerlBrdf b = analyticTable().brdf();
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto direction = [&] { return sphericalDirection(std::acos(1 - 0.9999 * u(rng)), (2 * u(rng) - 1) * kPi); };
  for (int n = 0; n < 100000; ++n) {
    const Vec3d wi = direction(), wo = direction();
    ASSERT_EQ(b.eval(wo, wi), b.eval(wi, wo)) << n;
    const Rgb t1 = trilinear.eval(wo, wi), t2 = trilinear.eval(wi, wo);
    ASSERT_NEAR(t1.r, t2.r, 1e-6 * t1.r) << n;
    ASSERT_NEAR(t1.g, t2.g, 1e-6 * t1.g) << n;
    ASSERT_NEAR(t1.b, t2.b, 1e-6 * t1.b) << n;
  }
}

TEST(MerlBrdf, TrilinearFollowsASmoothTable) {
  // On the analytic table, trilinear lookups between centres stay close to the function (the
  // nearest lookup is off by up to half a cell's change).
  const MerlBrdf b = analyticTable().brdf();
  const MerlBrdf trilinear = b.withInterpolation(Interp::Trilinear);
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worstTrilinear = 0, worstNearest = 0;
  for (int n = 0; n < 20000; ++n) {
    const double th = u(rng) * kPi / 2 * 0.9 + 0.05, td = u(rng) * kPi / 2 * 0.9 + 0.05, pd = (2 * u(rng) - 1) * kPi;
    const double exact = analytic(0, th, td, pd) * MerlBrdf::kChannelScale[0];
    worstTrilinear = std::max(worstTrilinear, std::fabs(trilinear.evalHalfDiff(th, td, pd).r - exact) / exact);
    worstNearest = std::max(worstNearest, std::fabs(b.evalHalfDiff(th, td, pd).r - exact) / exact);
  }
  EXPECT_LT(worstTrilinear, 2e-3);
  EXPECT_LT(worstTrilinear, worstNearest / 5);
  RecordProperty("worst_relative_error_trilinear", std::to_string(worstTrilinear));
  RecordProperty("worst_relative_error_nearest", std::to_string(worstNearest));
}

TEST(Rgb, Luminance) {
  EXPECT_FLOAT_EQ((Rgb{1, 1, 1}.luminance()), 1.0f);
  EXPECT_FLOAT_EQ((Rgb{0, 1, 0}.luminance()), 0.7152f);
}

// ---------------------------------------------------------------------------------------------
// Load time of a full-size (35 MB) file against a plain read of it. Reported, not asserted: it
// depends on the machine and on the page cache.

TEST_F(MerlFiles, LoadTimeOfAFullSizeFile) {
  const fs::path path = file("full.binary");
  writeFile(path, fileBytes(randomTable(15)));
  using Clock = std::chrono::steady_clock;
  const auto plainRead = [&] {
    std::ifstream in(path, std::ios::binary);
    const auto buffer = std::make_unique_for_overwrite<char[]>(kFileBytes);
    in.read(buffer.get(), static_cast<std::streamsize>(kFileBytes));
    return in.gcount() == static_cast<std::streamsize>(kFileBytes);
  };
  double bestRead = 1e9, bestLoad = 1e9;
  ASSERT_TRUE(plainRead());  // warm the page cache for both
  for (int rep = 0; rep < 5; ++rep) {
    auto t0 = Clock::now();
    ASSERT_TRUE(plainRead());
    auto t1 = Clock::now();
    const MerlBrdf b = MerlBrdf::load(path);
    auto t2 = Clock::now();
    ASSERT_EQ(b.negativeEntries(), 0u);
    bestRead = std::min(bestRead, std::chrono::duration<double, std::milli>(t1 - t0).count());
    bestLoad = std::min(bestLoad, std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  std::cout << "[ measure  ] 35 MB MERL file, best of 5 (page cache warm): plain read " << bestRead
            << " ms, MerlBrdf::load " << bestLoad << " ms (" << bestLoad / bestRead << "x)\n";
  RecordProperty("plain_read_ms", std::to_string(bestRead));
  RecordProperty("merl_load_ms", std::to_string(bestLoad));
}

}  // namespace

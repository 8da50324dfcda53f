// Unit tests of the .npy reader and the input layer of the acdf program (apps/npy.h, input.h).

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app_test_util.h"
#include "errors.h"
#include "input.h"
#include "npy.h"

namespace acdf::apptest {
namespace {

using acdf::FileError;
using acdf::app::NpyDtype;
using acdf::app::readNpy;

class NpyReader : public TempDirTest {
 protected:
  // Writes `bytes` to `name` and expects readNpy to fail with a message "<path>: ..." containing
  // every one of `needles`.
  void expectError(const std::string& name, const std::string& bytes, std::initializer_list<std::string> needles) {
    const std::string file = path(name);
    writeFile(file, bytes);
    expectErrorAt(file, needles);
  }
  void expectErrorAt(const std::string& file, std::initializer_list<std::string> needles) {
    try {
      const auto array = readNpy(file);
      ADD_FAILURE() << "readNpy(" << file << ") succeeded with " << array.values.size() << " values";
    } catch (const FileError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file + ": ", 0), 0u) << "message does not start with the file: " << what;
      EXPECT_EQ(e.file(), file);
      for (char c : what) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20) << "control character in: " << what;
      for (const auto& needle : needles)
        EXPECT_NE(what.find(needle), std::string::npos) << "'" << needle << "' not in: " << what;
    }
  }
};

std::vector<float> iota(std::size_t n, float scale = 1.0f) {
  std::vector<float> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = scale * static_cast<float>(i) + 0.25f;
  return v;
}

// ---- valid files ---------------------------------------------------------------------------

TEST_F(NpyReader, ReadsFloat32OneDimension) {
  const auto values = iota(7);
  writeFile(path("a.npy"), npyF4({7}, values));
  const auto array = readNpy(path("a.npy"));
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{7}));
  EXPECT_EQ(array.dtype, NpyDtype::Float32);
  EXPECT_EQ(array.majorVersion, 1);
  EXPECT_EQ(array.values, values);
}

TEST_F(NpyReader, ReadsFloat64TwoDimensionsAndConverts) {
  std::vector<double> values(3 * 5);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = 0.1 * static_cast<double>(i);
  writeFile(path("b.npy"), npyF8({3, 5}, values));
  const auto array = readNpy(path("b.npy"));
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{3, 5}));
  EXPECT_EQ(array.dtype, NpyDtype::Float64);
  ASSERT_EQ(array.values.size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_EQ(array.values[i], static_cast<float>(values[i])) << i;
}

TEST_F(NpyReader, ReadsThreeAndFourDimensions) {
  const auto v3 = iota(2 * 3 * 4);
  writeFile(path("c3.npy"), npyF4({2, 3, 4}, v3));
  const auto a3 = readNpy(path("c3.npy"));
  EXPECT_EQ(a3.shape, (std::vector<std::size_t>{2, 3, 4}));
  EXPECT_EQ(a3.values, v3);

  std::vector<double> v4(2 * 2 * 3 * 2);
  for (std::size_t i = 0; i < v4.size(); ++i) v4[i] = static_cast<double>(i) * 1.5;
  writeFile(path("c4.npy"), npyF8({2, 2, 3, 2}, v4));
  const auto a4 = readNpy(path("c4.npy"));
  EXPECT_EQ(a4.shape, (std::vector<std::size_t>{2, 2, 3, 2}));
  ASSERT_EQ(a4.values.size(), v4.size());
  EXPECT_EQ(a4.values[23], 34.5f);
}

TEST_F(NpyReader, ReadsVersion2And3Headers) {
  const auto values = iota(6, 2.0f);
  writeFile(path("v2.npy"), npyF4({2, 3}, values, 2));
  const auto a2 = readNpy(path("v2.npy"));
  EXPECT_EQ(a2.majorVersion, 2);
  EXPECT_EQ(a2.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(a2.values, values);

  writeFile(path("v3.npy"), npyF4({6}, values, 3));
  const auto a3 = readNpy(path("v3.npy"));
  EXPECT_EQ(a3.majorVersion, 3);
  EXPECT_EQ(a3.values, values);
}

TEST_F(NpyReader, AcceptsHeaderVariants) {
  // Keys in another order, no trailing comma, no padding, Python 2 long suffixes.
  const auto values = iota(12);
  const std::string dict = "{'shape': (3L, 4L), 'fortran_order': False, 'descr': '<f4'}";
  std::string bytes = "\x93NUMPY";
  bytes += '\x01';
  bytes += '\x00';
  bytes += static_cast<char>(dict.size() + 1);
  bytes += '\x00';
  bytes += dict + "\n" + rawBytes(values);
  writeFile(path("variant.npy"), bytes);
  const auto array = readNpy(path("variant.npy"));
  EXPECT_EQ(array.shape, (std::vector<std::size_t>{3, 4}));
  EXPECT_EQ(array.values, values);
}

TEST_F(NpyReader, KeepsNegativeNanAndInfForTheEngineToReport) {
  const std::vector<float> values{1.0f, -2.0f, std::numeric_limits<float>::quiet_NaN(),
                                  std::numeric_limits<float>::infinity()};
  writeFile(path("raw.npy"), npyF4({4}, values));
  const auto array = readNpy(path("raw.npy"));
  EXPECT_EQ(array.values[1], -2.0f);
  EXPECT_TRUE(std::isnan(array.values[2]));
  EXPECT_TRUE(std::isinf(array.values[3]));
}

// ---- files that are not there or not files ---------------------------------------------------

TEST_F(NpyReader, MissingFile) { expectErrorAt(path("missing.npy"), {"no such file"}); }

TEST_F(NpyReader, Directory) {
  std::filesystem::create_directory(path("dir.npy"));
  expectErrorAt(path("dir.npy"), {"directory"});
}

TEST_F(NpyReader, EmptyFile) { expectError("empty.npy", "", {"empty"}); }

// ---- broken structure ------------------------------------------------------------------------

TEST_F(NpyReader, NotNpyMagic) { expectError("text.npy", "hello, world\n", {"not a .npy file"}); }

TEST_F(NpyReader, TruncatedInsideMagic) { expectError("t.npy", "\x93NUM", {"truncated"}); }

TEST_F(NpyReader, TruncatedInsideHeaderLength) {
  expectError("t.npy", std::string("\x93NUMPY\x01\x00\x40", 9), {"truncated", "header length"});
}

TEST_F(NpyReader, TruncatedInsideHeader) {
  const std::string whole = npyF4({4}, iota(4));
  expectError("t.npy", whole.substr(0, 40), {"truncated", "header"});
}

TEST_F(NpyReader, TruncatedData) {
  const std::string whole = npyF4({3, 4}, iota(12));
  expectError("t.npy", whole.substr(0, whole.size() - 5), {"truncated data", "(3, 4)", "48 bytes"});
}

TEST_F(NpyReader, HeaderOnlyNoData) {
  expectError("t.npy", npyPreamble(npyDict("<f8", {2})), {"truncated data", "16 bytes", "has 0"});
}

TEST_F(NpyReader, TrailingBytes) {
  expectError("x.npy", npyF4({4}, iota(4)) + "junk", {"4 unexpected bytes after the data"});
}

TEST_F(NpyReader, UnsupportedVersion) {
  expectError("v.npy", npyPreamble(npyDict("<f4", {1}), 4) + rawBytes(iota(1)), {"version 4.0"});
  expectError("v.npy", npyPreamble(npyDict("<f4", {1}), 1, 1) + rawBytes(iota(1)), {"version 1.1"});
}

TEST_F(NpyReader, BadHeaderSyntax) {
  expectError("h1.npy", npyPreamble("{'descr' '<f4'}") + rawBytes(iota(1)), {"bad .npy header", "':'"});
  expectError("h2.npy", npyPreamble("not a dict") + rawBytes(iota(1)), {"bad .npy header"});
  expectError("h3.npy", npyPreamble("{'descr': '<f4', 'fortran_order': False, 'shape': (2, x)}") + rawBytes(iota(2)),
              {"bad .npy header"});
  expectError("h4.npy",
              npyPreamble("{'descr': '<f4', 'fortran_order': False, 'shape': (2,)} trailing") + rawBytes(iota(2)),
              {"bad .npy header", "after the header dict"});
  expectError("h5.npy", npyPreamble("{'descr': '<f4', 'fortran_order': Maybe, 'shape': (2,)}") + rawBytes(iota(2)),
              {"bad .npy header", "fortran_order"});
}

TEST_F(NpyReader, BytesFromTheFileArePrintedEscaped) {
  expectError(
      "ctl.npy",
      npyPreamble(std::string("{'de\x0bscr\x85': '<f4', 'fortran_order': False, 'shape': (2,)}")) + rawBytes(iota(2)),
      {"unexpected key 'de\\x0bscr\\x85'"});
  expectError("ctl2.npy", npyPreamble(npyDict("<f\x0c", {2})) + rawBytes(iota(2)), {"unsupported dtype '<f\\x0c'"});
}

TEST_F(NpyReader, MissingAndUnknownKeys) {
  expectError("k1.npy", npyPreamble("{'descr': '<f4', 'fortran_order': False}") + rawBytes(iota(2)),
              {"no 'shape' key"});
  expectError("k2.npy", npyPreamble("{'shape': (2,), 'fortran_order': False}") + rawBytes(iota(2)), {"no 'descr' key"});
  expectError("k3.npy",
              npyPreamble("{'descr': '<f4', 'fortran_order': False, 'shape': (2,), 'extra': 1}") + rawBytes(iota(2)),
              {"bad .npy header"});
  expectError(
      "k4.npy",
      npyPreamble("{'descr': '<f4', 'descr': '<f4', 'fortran_order': False, 'shape': (2,)}") + rawBytes(iota(2)),
      {"duplicate key 'descr'"});
}

TEST_F(NpyReader, FortranOrder) {
  expectError("f.npy", npyPreamble(npyDict("<f4", {2, 2}, true)) + rawBytes(iota(4)), {"fortran_order is True"});
}

TEST_F(NpyReader, BigEndian) {
  expectError("be4.npy", npyPreamble(npyDict(">f4", {2})) + rawBytes(iota(2)), {"big-endian", "'>f4'"});
  expectError("be8.npy", npyPreamble(npyDict(">f8", {2})) + std::string(16, '\0'), {"big-endian", "'>f8'"});
}

TEST_F(NpyReader, OtherDtypes) {
  for (const char* descr : {"<i4", "<f2", "|u1", "<c8", "|b1", "<i8", "<U3"}) {
    SCOPED_TRACE(descr);
    expectError("d.npy", npyPreamble(npyDict(descr, {2})) + std::string(64, '\0'),
                {"unsupported dtype", std::string("'") + descr + "'", "'<f4'"});
  }
  expectError("s.npy",
              npyPreamble("{'descr': [('x', '<f4'), ('y', '<f4')], 'fortran_order': False, 'shape': (2,), }") +
                  rawBytes(iota(4)),
              {"unsupported dtype", "structured"});
}

TEST_F(NpyReader, TooManyDimensions) {
  expectError("d5.npy", npyF4({1, 2, 1, 2, 1}, iota(4)), {"5 dimensions", "(1, 2, 1, 2, 1)", "at most 4"});
}

TEST_F(NpyReader, ScalarArray) {
  expectError("d0.npy", npyPreamble("{'descr': '<f4', 'fortran_order': False, 'shape': (), }") + rawBytes(iota(1)),
              {"0-dimensional"});
}

TEST_F(NpyReader, ZeroSizeDimension) {
  expectError("z.npy", npyPreamble(npyDict("<f4", {3, 0})), {"dimension 1 has size 0", "(3, 0)"});
}

TEST_F(NpyReader, HugeShapeIsNotAllocated) {
  expectError("huge.npy", npyPreamble(npyDict("<f8", {100000, 100000, 100000})) + rawBytes(iota(4)),
              {"truncated data"});
  expectError("overflow.npy", npyPreamble(npyDict("<f8", {4294967296, 4294967296, 4294967296})) + rawBytes(iota(4)),
              {"too large"});
}

TEST_F(NpyReader, Float64OverflowingFloat) {
  std::vector<double> values{1.0, 2.0, 3.0, 1e300, 5.0, 6.0};
  expectError("o.npy", npyF8({2, 3}, values), {"index 3 (element [1, 0])", "overflows float32"});
  values = {1.0, -1e39};
  expectError("o2.npy", npyF8({2}, values), {"index 1", "overflows float32"});
}

// ---- the input layer: values go through the engine's own check ------------------------------

class InputLayer : public TempDirTest {
 protected:
  std::string valueError(const std::string& name, const std::string& bytes) {
    const std::string file = path(name);
    writeFile(file, bytes);
    try {
      const auto grid = acdf::app::readInputGrid(file);
      const auto axes = acdf::app::unitAxes(grid);
      acdf::app::checkValues(grid, axes);
    } catch (const FileError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(file + ": ", 0), 0u) << e.what();
      return e.problem();
    }
    ADD_FAILURE() << "no error for " << file;
    return {};
  }
};

TEST_F(InputLayer, NpyGridHasTheArrayShape) {
  writeFile(path("g.npy"), npyF4({2, 3, 4}, iota(24)));
  const auto grid = acdf::app::readInputGrid(path("g.npy"));
  EXPECT_EQ(grid.kind, acdf::app::InputGrid::Kind::Npy);
  EXPECT_EQ(grid.dims, (std::vector<std::size_t>{2, 3, 4}));
  EXPECT_EQ(grid.values.size(), 24u);
  const auto axes = acdf::app::unitAxes(grid);
  ASSERT_EQ(axes.size(), 3u);
  EXPECT_EQ(axes[2].cells(), 4u);
  EXPECT_EQ(axes[2].lo(), 0.0f);
  EXPECT_EQ(axes[2].hi(), 1.0f);
  EXPECT_NO_THROW(acdf::app::checkValues(grid, axes));
}

TEST_F(InputLayer, NpyMagicWinsOverTheExtension) {
  writeFile(path("array.bin"), npyF4({5}, iota(5)));
  const auto grid = acdf::app::readInputGrid(path("array.bin"));
  EXPECT_EQ(grid.kind, acdf::app::InputGrid::Kind::Npy);
  EXPECT_EQ(grid.values.size(), 5u);
}

TEST_F(InputLayer, NegativeNanInfNameTheIndex) {
  std::vector<float> v = iota(6);
  v[4] = -1.0f;
  std::string problem = valueError("neg.npy", npyF4({2, 3}, v));
  EXPECT_NE(problem.find("4"), std::string::npos) << problem;
  EXPECT_NE(problem.find("negative"), std::string::npos) << problem;

  v = iota(6);
  v[2] = std::numeric_limits<float>::quiet_NaN();
  problem = valueError("nan.npy", npyF4({6}, v));
  EXPECT_NE(problem.find("2"), std::string::npos) << problem;
  EXPECT_NE(problem.find("NaN"), std::string::npos) << problem;

  std::vector<double> d{1.0, 2.0, std::numeric_limits<double>::infinity()};
  problem = valueError("inf.npy", npyF8({3}, d));
  EXPECT_NE(problem.find("2"), std::string::npos) << problem;
  EXPECT_NE(problem.find("infinite"), std::string::npos) << problem;
}

TEST_F(InputLayer, NotAnImage) {
  const std::string file = path("notes.txt");
  writeFile(file, "just some text, not pixels\n");
  try {
    (void)acdf::app::readInputGrid(file);
    ADD_FAILURE() << "read a text file as an image";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(file + ": ", 0), 0u) << e.what();
    EXPECT_NE(e.problem().find("not an image"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace acdf::apptest

// Cascade serialization: round trips that sample, evaluate and invert bit for bit like the
// original (uniform, adaptive, mixed, conditioning dimensions, both conditional and tolerance
// rules, greedy budgets, slice grouping, zero-mass slices, 8/16/32-bit vertex indices), and
// reading corrupt data: every truncation and every single-byte change either throws
// SerializationError or gives a table that still samples inside its domain with positive pdf.

#include "acdf/sampling/cascade.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "acdf/sampling/byte_io.h"
#include "acdf/sampling/rng.h"

namespace {

using namespace acdf;
using DM = DimensionMethod;

// A bumpy positive function with zero regions (and, for the first slices, zero slices), so
// adaptive levels keep uneven point counts and some slices fall back to uniform.
std::vector<float> bumpyValues(const std::vector<uint32_t>& cells, std::size_t zeroSlices = 0) {
  std::size_t total = 1;
  for (uint32_t c : cells) total *= c;
  std::vector<float> values(total);
  const std::size_t slice = cells.back() * (cells.size() > 1 ? cells[cells.size() - 2] : 1);
  for (std::size_t i = 0; i < total; ++i) {
    const double t = static_cast<double>(i) / total;
    const double v = std::exp(-40.0 * (t - 0.3) * (t - 0.3)) + 0.5 * std::sin(37.0 * t) * std::sin(11.0 * t);
    values[i] = i / slice < zeroSlices ? 0.0f : static_cast<float>(std::max(0.0, v));
  }
  return values;
}

std::vector<GridAxis> axesOf(const std::vector<uint32_t>& cells) {
  std::vector<GridAxis> axes;
  for (std::size_t d = 0; d < cells.size(); ++d) axes.emplace_back(cells[d], -1.0f + d, 2.0f + 3.0f * d);
  return axes;
}

bool sameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// sample/pdf/invert of `copy` agree bit for bit with `original` for random and extreme variates
// in every slice, and pdf at random points (inside and outside the domain).
void expectIdentical(const Cascade& original, const Cascade& copy) {
  ASSERT_EQ(original.serialize(), copy.serialize());
  ASSERT_EQ(original.bytes(), copy.bytes());
  ASSERT_EQ(original.slices(), copy.slices());
  ASSERT_EQ(original.distinctSlices(), copy.distinctSlices());
  const std::size_t k = original.conditioningDims(), n = original.sampledDims();
  Pcg32 rng(7);
  std::vector<float> c(k), u(n), x(n), u1(n), u2(n);
  for (int i = 0; i < 4000; ++i) {
    for (std::size_t d = 0; d < k; ++d) {
      const GridAxis& a = original.axes()[d];
      c[d] = a.lo() + rng.nextFloat() * (a.hi() - a.lo());
    }
    for (float& v : u) v = i == 0 ? 0.0f : i == 1 ? kOneMinusEpsilon : rng.nextFloat();
    const SampleND s1 = original.sample(c, u), s2 = copy.sample(c, u);
    ASSERT_TRUE(sameBits(s1.pdf, s2.pdf)) << i;
    for (std::size_t d = 0; d < n; ++d) ASSERT_TRUE(sameBits(s1.x[d], s2.x[d])) << i;
    ASSERT_TRUE(sameBits(original.pdf(c, s1.point()), copy.pdf(c, s2.point())));
    original.invert(c, s1.point(), u1);
    copy.invert(c, s2.point(), u2);
    for (std::size_t d = 0; d < n; ++d) ASSERT_TRUE(sameBits(u1[d], u2[d]));
    for (std::size_t d = 0; d < n; ++d) {
      const GridAxis& a = original.axes()[k + d];
      x[d] = a.lo() + (rng.nextFloat() * 1.2f - 0.1f) * (a.hi() - a.lo());
    }
    ASSERT_TRUE(sameBits(original.pdf(c, x), copy.pdf(c, x)));
  }
  for (std::size_t s = 0; s < original.slices(); ++s) {
    ASSERT_EQ(original.isUniformFallback(s), copy.isUniformFallback(s));
    ASSERT_EQ(original.cellProbabilities(s), copy.cellProbabilities(s));
  }
}

struct Case {
  std::string name;
  std::vector<uint32_t> cells;
  CascadeOptions options;
  std::size_t zeroSlices = 0;
};

// Options set field by field (designated initializers would leave the rest to -Wextra warnings).
template <class Edit>
CascadeOptions optionsWith(Edit edit) {
  CascadeOptions o;
  edit(o);
  return o;
}

std::vector<Case> cases() {
  std::vector<Case> all;
  all.push_back({"uniform-2d", {16, 24}, optionsWith([](auto& o) { o.methods = {DM::Uniform, DM::Uniform}; })});
  all.push_back({"adaptive-2d", {32, 48}, {}});
  all.push_back({"adaptive-1d-16bit", {3000}, {}});
  all.push_back({"adaptive-1d-32bit", {70000}, optionsWith([](auto& o) { o.simplify.epsilon = 1e-2; })});
  all.push_back({"mixed-4d-conditioned",
                 {6, 5, 20, 12},
                 optionsWith([](auto& o) {
                   o.conditioningDims = 2;
                   o.methods = {DM::Adaptive, DM::Uniform};
                 }),
                 3});
  all.push_back({"uniform-then-adaptive-3d", {4, 10, 300}, optionsWith([](auto& o) {
                   o.conditioningDims = 1;
                   o.methods = {DM::Uniform, DM::Adaptive};
                 })});
  all.push_back({"average-of-normalized-mass-scaled-chi2",
                 {5, 30, 20},
                 optionsWith([](auto& o) {
                   o.conditioningDims = 1;
                   o.simplify.metric = ErrorMetric::ChiSquare;
                   o.simplify.epsilon = 1e-3;
                   o.simplify.weightBound = 0.0;
                   o.conditional = ConditionalRule::AverageOfNormalized;
                   o.tolerance = ConditionalTolerance::MassScaled;
                 }),
                 1});
  all.push_back({"greedy-budget", {40, 40}, optionsWith([](auto& o) {
                   o.simplify.method = Simplifier::GreedyRefinement;
                   o.simplify.metric = ErrorMetric::Perpendicular;
                   o.simplify.maxPoints = 12;
                 })});
  all.push_back({"slice-grouping",
                 {12, 16, 16},
                 optionsWith([](auto& o) {
                   o.conditioningDims = 1;
                   o.sliceGroupingTolerance = 0.5;
                 }),
                 4});
  return all;
}

CascadeOptions conditionedOn(uint32_t dims, double sliceGrouping = 0.0) {
  return optionsWith([&](auto& o) {
    o.conditioningDims = dims;
    o.sliceGroupingTolerance = sliceGrouping;
  });
}

TEST(CascadeSerialization, RoundTripsAreBitIdentical) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Cascade original(bumpyValues(c.cells, c.zeroSlices), axesOf(c.cells), c.options);
    const std::vector<std::byte> bytes = original.serialize();
    const Cascade copy = Cascade::deserialize(bytes);
    EXPECT_EQ(copy.options(), c.options);
    EXPECT_EQ(copy.axes(), original.axes());
    expectIdentical(original, copy);
  }
}

TEST(CascadeSerialization, CasesCoverGroupingFallbackAndEveryIndexWidth) {
  // Guards the round-trip cases above: they exercise what they claim to.
  const std::vector<Case> all = cases();
  auto build = [&](const std::string& name) {
    for (const Case& c : all)
      if (c.name == name) return Cascade(bumpyValues(c.cells, c.zeroSlices), axesOf(c.cells), c.options);
    throw std::logic_error(name);
  };
  const Cascade grouped = build("slice-grouping");
  EXPECT_LT(grouped.distinctSlices(), grouped.slices());
  EXPECT_TRUE(grouped.isUniformFallback(0));
  EXPECT_TRUE(build("mixed-4d-conditioned").isUniformFallback(2));
  // 1D tables of 3000 and 70000 cells use 16- and 32-bit indices (vertex_indices.h): bytes are
  // interior points × (4 + width) plus two starts and the integral.
  for (auto [name, width] : {std::pair{"adaptive-1d-16bit", 2u}, std::pair{"adaptive-1d-32bit", 4u}}) {
    const Cascade c = build(name);
    EXPECT_EQ(c.bytes(), (c.pointsPerDimension()[0] - 2) * (4 + width) + 2 * 4 + 8) << name;
  }
}

TEST(CascadeSerialization, ReadConsumesExactlyItsBytesInALargerStream) {
  const Cascade a(bumpyValues({8, 8}), axesOf({8, 8}));
  const Cascade b(bumpyValues({5, 9, 7}), axesOf({5, 9, 7}), conditionedOn(1));
  ByteWriter out;
  a.write(out);
  out.put<uint32_t>(12345);
  b.write(out);
  ByteReader in(out.bytes(), "stream");
  expectIdentical(a, Cascade::read(in));
  EXPECT_EQ(in.get<uint32_t>(), 12345u);
  expectIdentical(b, Cascade::read(in));
  in.expectEnd();
}

// The problem message of deserialize(bytes), or "" if it accepted them.
std::string problemOf(std::span<const std::byte> bytes) {
  try {
    Cascade::deserialize(bytes);
  } catch (const SerializationError& e) {
    return e.what();
  }
  return "";
}

// A 1D uniform cascade of 4 cells: 89 bytes of header, shape and options, then its 3 interior
// CDF values 0.1, 0.3, 0.6. Offsets follow the layout in cascade_io.cpp.
constexpr std::size_t kFirstCdfValue = 89;

std::vector<std::byte> smallUniform() {
  const float values[4] = {1, 2, 3, 4};
  return Cascade(values, {GridAxis(4)}, optionsWith([](auto& o) { o.methods = {DM::Uniform}; })).serialize();
}

void putFloat(std::vector<std::byte>& bytes, std::size_t offset, float v) {
  const auto bits = std::bit_cast<uint32_t>(v);
  for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<std::byte>(bits >> (8 * i));
}

void putDouble(std::vector<std::byte>& bytes, std::size_t offset, double v) {
  const auto bits = std::bit_cast<uint64_t>(v);
  for (int i = 0; i < 8; ++i) bytes[offset + i] = static_cast<std::byte>(bits >> (8 * i));
}

double getDouble(const std::vector<std::byte>& bytes, std::size_t offset) {
  uint64_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= static_cast<uint64_t>(bytes[offset + i]) << (8 * i);
  return std::bit_cast<double>(bits);
}

TEST(CascadeSerialization, RejectsInconsistentDataWithAClearMessage) {
  std::vector<std::byte> bytes = smallUniform();
  ASSERT_EQ(bytes.size(), kFirstCdfValue + 3 * 4);
  ASSERT_EQ(problemOf(bytes), "");

  auto expectProblem = [](const std::vector<std::byte>& b, const std::string& fragment) {
    const std::string problem = problemOf(b);
    EXPECT_NE(problem.find(fragment), std::string::npos) << "'" << problem << "' lacks '" << fragment << "'";
    EXPECT_EQ(problem.rfind("cascade: ", 0), 0u) << problem;
    EXPECT_EQ(problem.find('\n'), std::string::npos) << problem;
  };
  std::vector<std::byte> b = bytes;
  b[0] = std::byte{'X'};
  expectProblem(b, "wrong magic");
  b = bytes;
  b[4] = std::byte{9};
  expectProblem(b, "format version 9, this build reads 2");
  b = bytes;
  b.push_back(std::byte{0});
  expectProblem(b, "1 unexpected trailing bytes");
  b = bytes;
  b.resize(b.size() - 1);
  expectProblem(b, "truncated");
  b = bytes;
  putFloat(b, kFirstCdfValue + 1 * 4, 0.9f);  // F = 0, 0.1, 0.9, 0.6, 1
  expectProblem(b, "CDF value 0.600000 at point 3 is not >= the previous 0.900000");
  b = bytes;
  putFloat(b, kFirstCdfValue + 1 * 4, std::nanf(""));
  expectProblem(b, "CDF value nan at point 2");
  b = bytes;
  putFloat(b, kFirstCdfValue, -std::numeric_limits<float>::infinity());
  expectProblem(b, "is not >= the previous 0.0");
  b = bytes;
  putFloat(b, kFirstCdfValue + 2 * 4, 1.5f);
  expectProblem(b, "CDF value 1.500000 exceeds 1");
  b = bytes;
  b[kFirstCdfValue - 8] = std::byte{2};  // CDF value count
  expectProblem(b, "2 CDF values for 1 uniform CDFs of 4 cells");
  b = bytes;
  b[kFirstCdfValue - 1] = std::byte{0x7f};  // a count far beyond the bytes left: no allocation
  expectProblem(b, "entries of 4 bytes");
  b = bytes;
  b[10] = std::byte{0};  // the axis' cell count: 0
  expectProblem(b, "axis 0");
  // Options the writer never writes: the validator the constructor uses judges them too.
  constexpr std::size_t kEpsilon = 26, kSliceGroupingTolerance = 48;
  ASSERT_EQ(getDouble(bytes, kEpsilon), CascadeOptions{}.simplify.epsilon);
  ASSERT_EQ(getDouble(bytes, kSliceGroupingTolerance), 0.0);
  b = bytes;
  putDouble(b, kEpsilon, -1.0);
  expectProblem(b, "cascade: epsilon must be finite and >= 0, got -1");
  b = bytes;
  putDouble(b, kSliceGroupingTolerance, -1.0);
  expectProblem(b, "cascade: slice_grouping_tolerance must be finite and >= 0, got -1");
}

// Whatever a corrupt buffer turns into, it is an error or a table that samples like one.
void expectRejectedOrSound(std::span<const std::byte> bytes) {
  try {
    const Cascade c = Cascade::deserialize(bytes);
    std::vector<float> cond(c.conditioningDims()), u(c.sampledDims());
    for (std::size_t d = 0; d < cond.size(); ++d) cond[d] = c.axes()[d].innerLo();
    for (float v : {0.0f, 0.3f, 0.5f, kOneMinusEpsilon}) {
      std::fill(u.begin(), u.end(), v);
      const SampleND s = c.sample(cond, u);
      ASSERT_TRUE(s.pdf > 0.0f && std::isfinite(s.pdf));
      for (std::size_t d = 0; d < u.size(); ++d) ASSERT_TRUE(c.axes()[c.conditioningDims() + d].contains(s.x[d]));
      ASSERT_EQ(c.pdf(cond, s.point()), s.pdf);
    }
  } catch (const SerializationError&) {
  }
}

TEST(CascadeSerialization, EveryTruncationIsRejected) {
  for (const std::vector<std::byte>& bytes :
       {smallUniform(), Cascade(bumpyValues({3, 7, 6}, 1), axesOf({3, 7, 6}), conditionedOn(1)).serialize()}) {
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      EXPECT_NE(problemOf(std::span(bytes).first(n)), "") << n;
    }
  }
}

TEST(CascadeSerialization, EverySingleByteChangeIsRejectedOrHarmless) {
  const std::vector<std::vector<std::byte>> tables = {
      smallUniform(), Cascade(bumpyValues({3, 7, 6}, 1), axesOf({3, 7, 6}), conditionedOn(1)).serialize(),
      Cascade(bumpyValues({6, 5, 8}, 1), axesOf({6, 5, 8}), conditionedOn(1, 1.0)).serialize()};
  for (const std::vector<std::byte>& original : tables) {
    std::vector<std::byte> bytes = original;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      for (uint8_t change : {0x01, 0x80, 0xff}) {
        bytes[i] = original[i] ^ std::byte{change};
        expectRejectedOrSound(bytes);
        if (HasFatalFailure()) FAIL() << "byte " << i << " ^ " << int(change);
      }
      bytes[i] = original[i];
    }
  }
}

}  // namespace

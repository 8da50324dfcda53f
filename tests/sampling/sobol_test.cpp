// The Sobol generator (sobol.h): the published points, the net properties with and without
// scrambling, Owen scrambling's structure, the 2^-24 lattice, uniformity, determinism, and
// convergence against independent samples.

#include "acdf/sampling/sobol.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"
#include "acdf/test_support/chi_square_registry.h"

namespace {

using namespace acdf;

using Point2 = std::array<float, 2>;
using Sequence2D = std::function<Point2(uint32_t index)>;

// Dimensions 0 and 1 of the unscrambled sequence, as floats.
Point2 unscrambled(uint32_t i) { return {bitsToUnitFloat(sobolBits(i, 0)), bitsToUnitFloat(sobolBits(i, 1))}; }

// ---- The published sequence --------------------------------------------------------------------

// Joe & Kuo's points 0–15 (their Gray-code order) in dimensions 1–5 of new-joe-kuo-6.21201,
// times 16 (the first 16 points are multiples of 1/16), as their sobol.cc and SciPy's
// qmc.Sobol(d=5, scramble=False) print them.
constexpr uint32_t kPublished[5][16] = {
    {0, 8, 12, 4, 6, 14, 10, 2, 3, 11, 15, 7, 5, 13, 9, 1}, {0, 8, 4, 12, 6, 14, 2, 10, 5, 13, 1, 9, 3, 11, 7, 15},
    {0, 8, 4, 12, 10, 2, 14, 6, 15, 7, 11, 3, 5, 13, 1, 9}, {0, 8, 4, 12, 14, 6, 10, 2, 7, 15, 3, 11, 9, 1, 13, 5},
    {0, 8, 12, 4, 6, 14, 10, 2, 9, 1, 5, 13, 15, 7, 3, 11},
};

TEST(SobolSequence, FirstPointsOfDimensions0To4AreJoeKuos) {
  for (uint32_t d = 0; d < 5; ++d)
    for (uint32_t n = 0; n < 16; ++n) {
      const uint32_t gray = n ^ (n >> 1);
      EXPECT_EQ(sobolBits(gray, d), kPublished[d][n] << 28) << "dimension " << d << ", point " << n;
    }
}

// FNV-1a (64-bit) of each dimension's 32 generator-matrix columns (sobolBits(2^k, d), k = 0..31,
// little-endian bytes), from the direction numbers SciPy 1.10 computes from its copy of
// new-joe-kuo-6.21201 (scipy.stats._sobol._initialize_v(v, 64, 32); the same columns reproduce
// SciPy's first 4096 unscrambled points in all 64 dimensions).
constexpr uint64_t kColumnHashes[kSobolDimensions] = {
    0x3915025a5388cfc9ull, 0xe8679f76d0281c08ull, 0x307fd65fe400bbe2ull, 0x673d69b4b8aa06b5ull, 0xf70108b6525bbfdbull,
    0x957d5415f2c10a12ull, 0x48eebed41d1dfae8ull, 0xa748304c7ae60cd0ull, 0x8932f3e065565ff3ull, 0x9bbd5a06ada7585eull,
    0x02aab12c1958ee0bull, 0xdfa1aa0e95fe58a2ull, 0x9bf273ee8b0f7ac7ull, 0xe7b2264f4810420eull, 0x17227c5c26cf719dull,
    0x567abc2ad05dd60aull, 0xd7ad0ed4dddeaafeull, 0x7291387fa346df6aull, 0x29a314ecd70d1c12ull, 0x211347b4188bfa99ull,
    0xf79b1c96295601daull, 0xa82f78dd7dc7968bull, 0x12058c84275173b9ull, 0x6a8bc19cd07cb035ull, 0xbf26b135cbaa3167ull,
    0x4f4fe972279dc9ccull, 0x19481a2a83826841ull, 0xcd6826143c46adf9ull, 0x77659e2928938e12ull, 0xe756620d91600eb4ull,
    0xf2cae52f39c13213ull, 0x96ed93cb9c75e319ull, 0x09137d75f4a0f47aull, 0x368e3809ed79e8b3ull, 0xef5cd78dc293c08cull,
    0xa1993b7a5bf76903ull, 0x07206d69bd324011ull, 0xd948b24ae9fc68cdull, 0x368f787a7b79e400ull, 0x8f2e239749a370efull,
    0x5dd7f77fa31f683cull, 0x15930a0c6b32b54dull, 0xa6dd3e15e6b1158bull, 0x60bd2e9f64b13de7ull, 0x6b431decd08cfbb4ull,
    0xcb1417932a158bc9ull, 0xfd729f6ec54bf4f6ull, 0xbf953bf43b66ddb6ull, 0x006c19c0181bc3c4ull, 0x7241440670f4da51ull,
    0xbbb5887878b41707ull, 0xb20c7a202bd45ba1ull, 0xed141a8a6f361826ull, 0x5557f41e276fcaf6ull, 0x88e839018d2e7da5ull,
    0xcd5d6834feca656eull, 0x5d948bcd59700b91ull, 0xc4aba458ab47685bull, 0x8ebaf59a86b4bbffull, 0xd52dac70956337c5ull,
    0xa6104a8d976a98d0ull, 0x29c3021f94259f5full, 0x7d50a318916599fbull, 0x4dcdf3933b0c1da1ull,
};

TEST(SobolSequence, GeneratorMatricesOfAllDimensionsMatchSciPys) {
  for (uint32_t d = 0; d < kSobolDimensions; ++d) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (uint32_t k = 0; k < 32; ++k) {
      const uint32_t column = sobolBits(1u << k, d);
      for (uint32_t byte = 0; byte < 4; ++byte) h = (h ^ ((column >> (8 * byte)) & 0xffu)) * 0x100000001b3ull;
    }
    EXPECT_EQ(h, kColumnHashes[d]) << "dimension " << d;
  }
}

TEST(SobolSequence, IsLinearInTheIndexBits) {
  // sobolBits(a ^ b) = sobolBits(a) ^ sobolBits(b): the point is the matrix times the index.
  Pcg32 rng(5);
  for (int i = 0; i < 10'000; ++i) {
    const uint32_t a = rng.nextUint(), b = rng.nextUint(), d = rng.nextUint() % kSobolDimensions;
    ASSERT_EQ(sobolBits(a ^ b, d), sobolBits(a, d) ^ sobolBits(b, d)) << a << " " << b << " " << d;
  }
}

TEST(SobolSequence, EveryDimensionIsA01Sequence) {
  // Every aligned block of 2^m points puts one point in each interval [j/2^m, (j+1)/2^m).
  for (uint32_t d = 0; d < kSobolDimensions; ++d)
    for (uint32_t m = 0; m <= 12; ++m)
      for (uint32_t block : {0u, 1u, 7u, 0xfffffu >> m}) {
        std::vector<bool> hit(std::size_t{1} << m, false);
        for (uint32_t i = 0; i < (1u << m); ++i) {
          const uint32_t interval = m == 0 ? 0 : sobolBits((block << m) | i, d) >> (32 - m);
          ASSERT_FALSE(hit[interval]) << "dimension " << d << ", m " << m << ", block " << block;
          hit[interval] = true;
        }
      }
}

TEST(SobolSequence, RejectsDimensionsBeyondTheTable) {
  EXPECT_NO_THROW(sobolBits(3, kSobolDimensions - 1));
  EXPECT_THROW(sobolBits(3, kSobolDimensions), std::out_of_range);
  EXPECT_THROW(sobolSample(3, kSobolDimensions, 1), std::out_of_range);
  EXPECT_THROW(sobolSample(3, 0xffffffffu, 1), std::out_of_range);
  EXPECT_NO_THROW(paddedSobol2D(3, 0xffffffffu, 1));  // the padded sequence has no limit
}

// ---- (0,m,2)-nets ------------------------------------------------------------------------------

// Whether points first, first + 1, …, first + 2^m − 1 are a (0,m,2)-net: for every a = 0..m,
// each of the 2^a × 2^(m−a) elementary intervals holds exactly one point (m <= 24: the floats'
// leading digits are exact).
::testing::AssertionResult isNet(const Sequence2D& sequence, uint32_t first, uint32_t m) {
  const uint32_t n = 1u << m;
  std::vector<Point2> points(n);
  for (uint32_t i = 0; i < n; ++i) points[i] = sequence(first + i);
  std::vector<bool> hit(n);
  for (uint32_t a = 0; a <= m; ++a) {
    std::fill(hit.begin(), hit.end(), false);
    for (const Point2& p : points) {
      const auto column = static_cast<uint32_t>(std::ldexp(p[0], int(a)));
      const auto row = static_cast<uint32_t>(std::ldexp(p[1], int(m - a)));
      const uint32_t cell = (column << (m - a)) | row;
      if (hit[cell])
        return ::testing::AssertionFailure() << "points " << first << "+[0, 2^" << m << ") put two points in cell ("
                                             << column << ", " << row << ") of 2^" << a << " x 2^" << (m - a);
      hit[cell] = true;
    }
  }
  return ::testing::AssertionSuccess();
}

// Every m = 0..16 from index 0, and aligned blocks further along.
void expectNets(const Sequence2D& sequence) {
  for (uint32_t m = 0; m <= 16; ++m) EXPECT_TRUE(isNet(sequence, 0, m));
  for (uint32_t m : {3u, 8u, 11u})
    for (uint32_t block : {1u, 5u, 1000u}) EXPECT_TRUE(isNet(sequence, block << m, m));
}

TEST(SobolNet, FirstTwoDimensionsAre02Nets) { expectNets(unscrambled); }

TEST(SobolNet, OwenScramblingKeepsTheNets) {
  for (uint64_t seed : {0ull, 1ull, 0x5eedull, 0xfedcba9876543210ull})
    expectNets([seed](uint32_t i) { return Point2{sobolSample(i, 0, seed), sobolSample(i, 1, seed)}; });
}

TEST(SobolNet, PaddedComponentsAreNetsInEveryDimension) {
  for (uint32_t dimension : {0u, 1u, 64u, 1000u})
    for (uint64_t seed : {0ull, 0x5eedull}) expectNets([=](uint32_t i) { return paddedSobol2D(i, dimension, seed); });
}

TEST(SobolNet, TheCheckFindsNonNets) {
  // Independent points, and the pair of dimensions 0 and 2 (whose t is 1, not 0), are rejected.
  Pcg32 rng(1);
  EXPECT_FALSE(isNet([&](uint32_t) { return Point2{rng.nextFloat(), rng.nextFloat()}; }, 0, 8));
  EXPECT_FALSE(isNet(
      [](uint32_t i) {
        return Point2{bitsToUnitFloat(sobolBits(i, 0)), bitsToUnitFloat(sobolBits(i, 2))};
      },
      0, 8));
}

// ---- Owen scrambling ---------------------------------------------------------------------------

TEST(OwenScramble, KeepsTheFirstDifferingDigit) {
  // A nested permutation: values that share their first k digits and differ in digit k + 1 still
  // do afterwards, for every seed. So elementary intervals map onto elementary intervals, and
  // distinct values stay distinct: a bijection.
  Pcg32 rng(7);
  for (int i = 0; i < 200'000; ++i) {
    const uint32_t v = rng.nextUint(), seed = rng.nextUint();
    const int k = static_cast<int>(rng.nextUint() % 32);
    const uint32_t w = v ^ (0x80000000u >> k) ^ ((rng.nextUint() >> k) >> 1);  // same first k digits
    const uint32_t sv = owenScramble(v, seed), sw = owenScramble(w, seed);
    ASSERT_EQ(std::countl_zero(sv ^ sw), k) << std::hex << v << " " << w << " seed " << seed;
  }
}

TEST(OwenScramble, FlipsEachSubintervalIndependently) {
  // Unlike a random digital shift (one flip per digit), Owen scrambling flips digit k + 1 of the
  // two halves of an interval independently: over many seeds, the two flips agree half the time.
  // 100'000 seeds: a fair coin's agreement rate lies within ±0.01 (6 standard deviations).
  constexpr int kSeeds = 100'000;
  Pcg32 rng(11);
  for (int k = 1; k < 24; ++k) {
    const uint32_t prefix = rng.nextUint() & ~(0xffffffffu >> (k - 1));  // first k − 1 digits
    const uint32_t left = prefix, right = prefix | (0x80000000u >> (k - 1));
    const uint32_t digit = 0x80000000u >> k;
    int agree = 0;
    for (int s = 0; s < kSeeds; ++s) {
      const uint32_t seed = rng.nextUint();
      const bool flipLeft = (owenScramble(left, seed) ^ left) & digit;
      const bool flipRight = (owenScramble(right, seed) ^ right) & digit;
      agree += flipLeft == flipRight;
    }
    EXPECT_NEAR(double(agree) / kSeeds, 0.5, 0.01) << "digit " << k + 1;
  }
}

// ---- Range -------------------------------------------------------------------------------------

// Indices [0, 2^24) of any dimension are a (0,24,1)-net, and scrambling keeps that: each float of
// the 2^-24 lattice in [0, 1) occurs once. Checked through the extremes (0 and kOneMinusEpsilon
// are reached, 1 never is), every value on the lattice, and exactly 4096 values under each
// leading 12-digit prefix (a bitmap of 2^24 entries would spend its time in cache misses).
template <class Value>
void expectTheWholeLattice(const Value& value, const char* what) {
  std::vector<uint32_t> prefixCount(4096, 0);
  uint32_t offLattice = 0;
  float lowest = 1, highest = 0;
  for (uint32_t i = 0; i < (1u << 24); ++i) {
    const float x = value(i);
    lowest = std::min(lowest, x);
    highest = std::max(highest, x);
    if (!(x >= 0.0f && x < 1.0f)) {
      ++offLattice;
      continue;
    }
    const auto j = static_cast<uint32_t>(x * 0x1p24f);
    offLattice += float(j) * 0x1p-24f != x;
    ++prefixCount[j >> 12];
  }
  EXPECT_EQ(lowest, 0.0f) << what;
  EXPECT_EQ(highest, kOneMinusEpsilon) << what;
  EXPECT_EQ(offLattice, 0u) << what;
  EXPECT_EQ(std::count(prefixCount.begin(), prefixCount.end(), 4096u), 4096) << what;
}

TEST(SobolRange, EveryLatticeValueIn2To24Points) {
  for (uint32_t d : {0u, kSobolDimensions - 1})
    expectTheWholeLattice([d](uint32_t i) { return sobolSample(i, d, 0xabcdefull); }, "sobolSample");
  expectTheWholeLattice([](uint32_t i) { return paddedSobol1D(i, 3, 0xabcdefull); }, "paddedSobol1D");
  expectTheWholeLattice([](uint32_t i) { return paddedSobol2D(i, 4, 0xabcdefull)[1]; }, "paddedSobol2D y");
}

TEST(SobolRange, UnscrambledStartsAtZero) {
  for (uint32_t d = 0; d < kSobolDimensions; ++d) EXPECT_EQ(sobolBits(0, d), 0u);
  EXPECT_EQ(bitsToUnitFloat(0), 0.0f);
  EXPECT_EQ(bitsToUnitFloat(0xffffffffu), kOneMinusEpsilon);
}

// ---- Uniformity --------------------------------------------------------------------------------

// Pearson's test of counts in `bins` equal bins against the uniform distribution.
::testing::AssertionResult uniform(const std::vector<double>& observed) {
  double n = 0;
  for (double o : observed) n += o;
  const std::vector<double> expected(observed.size(), n / double(observed.size()));
  const ChiSquareResult r = chiSquareTest(observed, expected);
  const double alpha = test_support::chiSquareTestLevel();
  std::cout << "chi2=" << r.statistic << " dof=" << r.dof << " p=" << r.pvalue << "\n";
  if (r.pvalue >= alpha) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "chi2=" << r.statistic << " dof=" << r.dof << " p=" << r.pvalue
                                       << " < alpha=" << alpha;
}

uint32_t bin(float x, uint32_t bins) { return static_cast<uint32_t>(x * float(bins)); }

constexpr uint32_t kUniformitySamples = 1'000'000;

ACDF_CHI_SQUARE_TEST(SobolUniformity, OneSequenceFillsItsDimension, 3) {
  // 10^6 consecutive values (not a power of two) in 1000 bins, and the padded 2D points in 32².
  std::vector<double> global(1000), padded1(1000), padded2(32 * 32);
  for (uint32_t i = 0; i < kUniformitySamples; ++i) {
    global[bin(sobolSample(i, 7, 42), 1000)] += 1;
    padded1[bin(paddedSobol1D(i, 7, 42), 1000)] += 1;
    const Point2 p = paddedSobol2D(i, 8, 42);
    padded2[bin(p[0], 32) * 32 + bin(p[1], 32)] += 1;
  }
  EXPECT_TRUE(uniform(global));
  EXPECT_TRUE(uniform(padded1));
  EXPECT_TRUE(uniform(padded2));
}

ACDF_CHI_SQUARE_TEST(SobolUniformity, ScramblingRandomisesEachPoint, 6) {
  // One point under 10^6 seeds (consecutive integers: the seeds are hashed) is uniform, also the
  // first point, which every unscrambled dimension puts at 0.
  for (uint32_t index : {0u, 1u, 1029u}) {
    std::vector<double> global(1000), padded(32 * 32);
    for (uint32_t seed = 0; seed < kUniformitySamples; ++seed) {
      global[bin(sobolSample(index, 3, seed), 1000)] += 1;
      const Point2 p = paddedSobol2D(index, 5, seed);
      padded[bin(p[0], 32) * 32 + bin(p[1], 32)] += 1;
    }
    EXPECT_TRUE(uniform(global)) << "index " << index;
    EXPECT_TRUE(uniform(padded)) << "index " << index;
  }
}

// ---- Determinism -------------------------------------------------------------------------------

TEST(SobolDeterminism, SameArgumentsSameValuesOtherSeedsOtherValues) {
  int differentSeed = 0, differentPadded = 0, differentDimension = 0, total = 0;
  for (uint32_t i = 0; i < 4096; ++i)
    for (uint32_t d = 0; d < 4; ++d) {
      ++total;
      ASSERT_EQ(sobolSample(i, d, 7), sobolSample(i, d, 7));
      ASSERT_EQ(paddedSobol2D(i, d, 7), paddedSobol2D(i, d, 7));
      ASSERT_EQ(paddedSobol1D(i, d, 7), paddedSobol2D(i, d, 7)[0]);
      differentSeed += sobolSample(i, d, 7) != sobolSample(i, d, 8);
      differentPadded += paddedSobol2D(i, d, 7) != paddedSobol2D(i, d, 8);
      differentDimension += paddedSobol2D(i, d, 7) != paddedSobol2D(i, d + 4, 7);
    }
  // Two independent lattice values coincide with probability 2^-24.
  EXPECT_GE(differentSeed, total - 2);
  EXPECT_GE(differentPadded, total - 2);
  EXPECT_GE(differentDimension, total - 2);
}

// ---- Convergence -------------------------------------------------------------------------------

// ∫∫ x e^(xy) dx dy over the unit square is e − 2. Points on the 2^-24 lattice (floor of a
// uniform value) are uniform on the lattice, whose expectation of f is, by Euler–Maclaurin,
// the integral − h/2 · (∫ f(1,y) − f(0,y) dy + ∫ f(x,1) − f(x,0) dx) = (e − 2) − h/2 · (e − 1/2),
// h = 2^-24; against the plain integral this 1e-7 bias would flatten the Sobol curve at 2^14.
double smooth(Point2 p) { return double(p[0]) * std::exp(double(p[0]) * double(p[1])); }
const double kLatticeExpectation = (std::numbers::e - 2.0) - 0x1p-25 * (std::numbers::e - 0.5);

// Slope of log2(RMS error) against log2(N) for N = 2^6 … 2^14, RMS over 16 seeds; the points of
// `sequence(seed)` for that seed.
double convergenceSlope(const std::function<Sequence2D(uint64_t seed)>& sequence, double* rmsAtLargest) {
  constexpr uint32_t kMin = 6, kMax = 14, kSeeds = 16;
  std::vector<double> k, logRms;
  std::vector<double> squaredError(kMax + 1, 0.0);
  for (uint64_t s = 0; s < kSeeds; ++s) {
    const Sequence2D points = sequence(s);
    double sum = 0;
    uint32_t n = 0;
    for (uint32_t m = kMin; m <= kMax; ++m) {
      for (; n < (1u << m); ++n) sum += smooth(points(n));
      const double error = sum / double(n) - kLatticeExpectation;
      squaredError[m] += error * error;
    }
  }
  for (uint32_t m = kMin; m <= kMax; ++m) {
    k.push_back(m);
    logRms.push_back(0.5 * std::log2(squaredError[m] / kSeeds));
  }
  *rmsAtLargest = std::exp2(logRms.back());
  // Least-squares slope.
  const double count = double(k.size());
  double sk = 0, sr = 0, skk = 0, skr = 0;
  for (std::size_t i = 0; i < k.size(); ++i) {
    sk += k[i];
    sr += logRms[i];
    skk += k[i] * k[i];
    skr += k[i] * logRms[i];
  }
  return (count * skr - sk * sr) / (count * skk - sk * sk);
}

TEST(SobolConvergence, ScrambledPointsConvergeFasterThanIndependentOnes) {
  // Owen-scrambled nets integrate smooth functions with RMS error O(N^-1.5); independent points
  // with O(N^-0.5).
  double rmsGlobal = 0, rmsPadded = 0, rmsIndependent = 0;
  const double global = convergenceSlope(
      [](uint64_t seed) -> Sequence2D {
        return [seed](uint32_t i) { return Point2{sobolSample(i, 0, seed), sobolSample(i, 1, seed)}; };
      },
      &rmsGlobal);
  const double padded = convergenceSlope(
      [](uint64_t seed) -> Sequence2D { return [seed](uint32_t i) { return paddedSobol2D(i, 9, seed); }; }, &rmsPadded);
  const double independent = convergenceSlope(
      [](uint64_t seed) -> Sequence2D {
        auto rng = std::make_shared<Pcg32>(seed);
        return [rng](uint32_t) { return Point2{rng->nextFloat(), rng->nextFloat()}; };
      },
      &rmsIndependent);
  std::cout << "slopes: sobolSample " << global << ", paddedSobol2D " << padded << ", independent " << independent
            << "; RMS at 2^14: " << rmsGlobal << ", " << rmsPadded << ", " << rmsIndependent << "\n";
  EXPECT_LT(global, -0.9);
  EXPECT_LT(padded, -0.9);
  EXPECT_GT(independent, -0.7);  // the figure the check is meant to beat
  EXPECT_LT(independent, -0.3);
  EXPECT_LT(rmsGlobal, 0.05 * rmsIndependent);
  EXPECT_LT(rmsPadded, 0.05 * rmsIndependent);
}

}  // namespace

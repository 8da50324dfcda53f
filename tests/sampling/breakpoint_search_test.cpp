// The branch-free interval search of the piecewise-linear CDFs against std::upper_bound: the same
// index for every variate, on random tables and on the ones rounding and zero-mass cells make
// (runs of equal values, values of exactly 0 and 1), and never an interval of zero mass.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "acdf/sampling/rng.h"
#include "breakpoint_cdf.h"

namespace {

using namespace acdf;

std::size_t reference(const std::vector<float>& v, float u) {
  return static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), u) - v.begin());
}

// Every value of the table, the floats either side of it, the ends of [0, 1) and random u.
std::vector<float> variates(const std::vector<float>& v, Pcg32& rng) {
  std::vector<float> u = {0.0f, std::nextafter(0.0f, 1.0f), std::nextafter(1.0f, 0.0f), 0.5f};
  for (float x : v) {
    u.push_back(x);
    u.push_back(std::nextafter(x, -1.0f));
    u.push_back(std::nextafter(x, 2.0f));
  }
  for (int k = 0; k < 64; ++k) u.push_back(rng.nextFloat());
  return u;
}

// Interior values of a CDF over `n` intervals: random, with runs of equal values (zero-mass
// intervals) and, for odd seeds, leading zeros and trailing ones.
std::vector<float> table(std::size_t n, Pcg32& rng, bool ties, bool ends) {
  std::vector<float> v(n > 1 ? n - 1 : 0);
  for (float& x : v) x = rng.nextFloat();
  if (ties)
    for (std::size_t k = 1; k < v.size(); ++k)
      if (rng.nextUint() % 3 == 0) v[k] = v[k - 1];
  std::sort(v.begin(), v.end());
  if (ends && v.size() >= 4) {
    v[0] = v[1] = 0.0f;
    v[v.size() - 1] = v[v.size() - 2] = 1.0f;
  }
  return v;
}

void expectSearchMatches(const std::vector<float>& v, Pcg32& rng) {
  const detail::BreakpointCdf cdf{.interior = v.data(), .count = v.size() + 2, .cells = 0};
  for (float u : variates(v, rng)) {
    const std::size_t j = cdf.intervalOfVariate(u);
    ASSERT_EQ(j, reference(v, u)) << "u = " << u << ", " << v.size() << " interior values";
    if (u >= 0.0f && u < 1.0f) {
      EXPECT_LE(cdf.value(j), u);
      EXPECT_LT(u, cdf.value(j + 1));
      EXPECT_GT(cdf.mass(j), 0.0);
    }
  }
}

TEST(BreakpointSearch, MatchesUpperBoundOnRandomTables) {
  Pcg32 rng(7);
  for (std::size_t n = 1; n <= 70; ++n)
    for (int rep = 0; rep < 20; ++rep) expectSearchMatches(table(n, rng, false, false), rng);
  for (std::size_t n : {255u, 256u, 257u, 1000u, 4097u}) expectSearchMatches(table(n, rng, false, false), rng);
}

TEST(BreakpointSearch, MatchesUpperBoundWithTiesAndEnds) {
  Pcg32 rng(11);
  for (std::size_t n = 1; n <= 70; ++n)
    for (int rep = 0; rep < 20; ++rep) expectSearchMatches(table(n, rng, true, rep % 2 == 1), rng);
  for (std::size_t n : {255u, 256u, 257u, 1000u, 4097u}) expectSearchMatches(table(n, rng, true, true), rng);
  // All interior values equal: every interval but one has zero mass.
  for (float x : {0.0f, 0.25f, std::nextafter(1.0f, 0.0f), 1.0f})
    for (std::size_t n : {2u, 3u, 8u, 33u}) expectSearchMatches(std::vector<float>(n, x), rng);
}

}  // namespace

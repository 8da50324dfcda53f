// LocalEnvironmentTable: chi-square of local sampling at several normals (poles, horizon, normal
// cell edges) on generated maps and the shared real ones, every sample's pdf against pdf(), the
// pdf's integral, the cosine bound's guarantee (pdf > 0 wherever L · max(0, n · ω) > 0 for every
// normal of a cell), black and tiny maps, lazy and eager slice builds, sizes.

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "acdf/envmap/light_chi_square.h"
#include "acdf/envmap/local_environment_table.h"
#include "acdf/envmap/sun_sky.h"
#include "acdf/sampling/option_error.h"
#include "acdf/sampling/rng.h"
#include "acdf/test_support/chi_square_registry.h"
#include "envmap_test_util.h"

namespace {

using namespace acdf;
using namespace acdf::envmaptest;
using test_support::chiSquareTestLevel;

constexpr double kPi = std::numbers::pi;

// A low sun (10° up) over a sky and a dark ground: the cosine matters most for it.
std::shared_ptr<const EnvironmentMap> lowSun(uint32_t width, uint32_t height) {
  SunSkyParameters p = sunSkyPreset("noon");
  p.sunElevationDeg = 10;
  p.sunRadiusDeg = 3;
  p.sunIntensity = 1e3;
  return std::make_shared<const EnvironmentMap>(width, height, sunSkyImage(width, height, p).pixels);
}

// Partial blocks in both directions at the default B = 16 (200 × 100, 100 × 10).
const char* const kGeneratedMaps[] = {"low_sun_200x100", "one_lit_pixel_100x10", "tiny_3x2"};

std::shared_ptr<const EnvironmentMap> generatedMap(const std::string& name) {
  static std::map<std::string, std::shared_ptr<const EnvironmentMap>> cache;
  auto& map = cache[name];
  if (map) return map;
  if (name == "low_sun_200x100") map = lowSun(200, 100);
  if (name == "one_lit_pixel_100x10") map = onePixelMap(100, 10, 3, 71, 5.0f);
  if (name == "tiny_3x2") map = makeMap(3, 2, [](uint32_t r, uint32_t c) { return Rgb{1.0f + r + 2 * c, 1, 0.5f}; });
  return map;
}

// Normals in the map frame: the poles, on the horizon, inside a cell, and on a normal cell's
// corner (θ = 7 π / 32, φ = 20 · 2π / 64 at the default 32 × 64 grid).
const char* const kNormalNames[] = {"zenith", "nadir", "horizon", "cell_corner"};
Vec3d normalNamed(const std::string& name) {
  if (name == "zenith") return {0, 1, 0};
  if (name == "nadir") return {0, -1, 0};
  if (name == "horizon") return LatLongMapping::direction(kPi / 2, 1.3);
  return LatLongMapping::direction(7 * kPi / 32, 20 * 2 * kPi / 64);
}

SphereChiSquareReport chiSquare(const LocalEnvironmentTable& table, const Vec3d& n) {
  LightChiSquareOptions options;
  options.alpha = chiSquareTestLevel();
  return mapChiSquareTest(
      table.map().width(), table.map().height(),
      [&](float u0, float u1) {
        const LocalEnvironmentTable::Sample s = table.sample(n, u0, u1);
        return DirectionSample{s.direction, s.pdf};
      },
      [&](const Vec3d& w) { return table.pdf(n, w); }, options);
}

// Every sample of a 64 × 64 grid of variates (0 and the largest float below 1 included): a unit
// direction in the pixel it names, finite positive pdf equal to pdf(); and Σ pdf ΔΩ over the
// pixels (the pdf is constant per pixel) and the exact pixel probabilities both sum to 1.
void expectConsistent(const LocalEnvironmentTable& table, const Vec3d& n, const std::string& what) {
  const LatLongMapping& mapping = table.map().mapping();
  for (int a = 0; a < 64; ++a)
    for (int b = 0; b < 64; ++b) {
      const float u0 = a == 63 ? kOneMinusEpsilon : a / 63.0f, u1 = b == 63 ? kOneMinusEpsilon : b / 63.0f;
      const LocalEnvironmentTable::Sample s = table.sample(n, u0, u1);
      ASSERT_TRUE(s.pdf > 0 && std::isfinite(s.pdf)) << what << " u " << u0 << " " << u1;
      ASSERT_NEAR(length(s.direction), 1.0, 1e-12) << what;
      ASSERT_EQ(mapping.pixelOf(s.direction), s.pixel) << what;
      ASSERT_EQ(table.pdf(n, s.direction), s.pdf) << what << " u " << u0 << " " << u1;
      ASSERT_EQ(table.pdf(n, s.pixel), s.pdf) << what << " u " << u0 << " " << u1;
    }
  double integral = 0, probability = 0;
  for (uint32_t r = 0; r < mapping.height(); ++r)
    for (uint32_t c = 0; c < mapping.width(); ++c)
      integral += table.pdf(n, mapping.directionInPixel({r, c}, 0.5, 0.5)) * mapping.pixelSolidAngle(r);
  for (double p : table.pixelProbabilities(n)) probability += p;
  EXPECT_NEAR(integral, 1.0, 1e-5) << what;
  EXPECT_NEAR(probability, 1.0, 1e-9) << what;
}

// Plain and compensated tables alike.
class LocalGenerated : public ::testing::TestWithParam<std::tuple<const char*, const char*, bool>> {};

ACDF_CHI_SQUARE_TEST_P(LocalGenerated, SamplerMatchesItsPdf, 1) {
  const auto [name, normal, compensated] = GetParam();
  const LocalEnvironmentTable table(generatedMap(name), {}, {}, compensated);
  const std::string what = std::string(name) + (compensated ? " compensated" : "") + " n=" + normal;
  const Vec3d n = normalNamed(normal);
  expectConsistent(table, n, what);
  const SphereChiSquareReport report = chiSquare(table, n);
  std::cout << what << ": " << report.summary() << "\n";
  EXPECT_TRUE(report.passed()) << what << ": " << report.summary();
}

INSTANTIATE_TEST_SUITE_P(Maps, LocalGenerated,
                         ::testing::Combine(::testing::ValuesIn(kGeneratedMaps), ::testing::ValuesIn(kNormalNames),
                                            ::testing::Bool()),
                         [](const auto& info) {
                           return std::string(std::get<0>(info.param)) + "_" + std::get<1>(info.param) +
                                  (std::get<2>(info.param) ? "_compensated" : "");
                         });

// Compensation leaves pdf 0 on the blocks below the cell's mean, which the plain table samples,
// and adds none.
TEST(LocalCompensated, BlocksBelowTheMeanGetNothing) {
  const auto map = generatedMap("low_sun_200x100");
  const LocalEnvironmentOptions cells{.normalRows = 8, .normalColumns = 16, .blockSize = 8};
  const LocalEnvironmentTable plain(map, cells), compensated(map, cells, {}, true);
  EXPECT_TRUE(compensated.compensated());
  EXPECT_FALSE(plain.compensated());
  for (const char* name : kNormalNames) {
    const Vec3d n = normalNamed(name);
    const std::vector<double> p = plain.pixelProbabilities(n), q = compensated.pixelProbabilities(n);
    std::size_t dropped = 0, gained = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      dropped += p[i] > 0 && q[i] == 0;
      gained += q[i] > 0 && p[i] == 0;
    }
    EXPECT_GT(dropped, p.size() / 10) << name;
    EXPECT_EQ(gained, 0u) << name << ": compensation only removes";
  }
}

class LocalShared : public ::testing::TestWithParam<const char*> {};

ACDF_CHI_SQUARE_TEST_P(LocalShared, SamplerMatchesItsPdf, 2) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  const auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(GetParam())));
  const LocalEnvironmentTable table(map);
  for (const char* normal : {"horizon", "cell_corner"}) {
    const std::string what = std::string(GetParam()) + " n=" + normal;
    const SphereChiSquareReport report = chiSquare(table, normalNamed(normal));
    std::cout << what << ": " << report.summary() << "\n";
    EXPECT_TRUE(report.passed()) << what << ": " << report.summary();
  }
}

INSTANTIATE_TEST_SUITE_P(RealMaps, LocalShared, ::testing::Values(kSharedEnvmaps[0]), [](const auto& info) {
  std::string name = info.param;
  return name.substr(0, name.find('_'));
});

// The harness can fail: local samples judged against the pdf of another normal are rejected.
ACDF_CHI_SQUARE_TEST(LocalChiSquare, RejectsThePdfOfAnotherNormal, 1) {
  const LocalEnvironmentTable table(generatedMap("low_sun_200x100"));
  const Vec3d n = normalNamed("horizon"), other = LatLongMapping::direction(kPi / 2, 1.3 + kPi / 2);
  LightChiSquareOptions options;
  options.alpha = chiSquareTestLevel();
  const SphereChiSquareReport report = mapChiSquareTest(
      200, 100,
      [&](float u0, float u1) {
        const LocalEnvironmentTable::Sample s = table.sample(n, u0, u1);
        return DirectionSample{s.direction, table.pdf(other, s.direction)};
      },
      [&](const Vec3d& w) { return table.pdf(other, w); }, options);
  EXPECT_FALSE(report.chiSquarePassed()) << report.summary();
}

Vec3d randomDirection(Pcg32& rng) { return sampleUniformSphere(rng.nextFloat(), rng.nextFloat()); }

// A random point of the lat-long cell [θa, θb] × [φa, φb].
Vec3d randomInCell(Pcg32& rng, double thetaA, double thetaB, double phiA, double phiB) {
  return LatLongMapping::direction(thetaA + rng.nextDouble() * (thetaB - thetaA),
                                   phiA + rng.nextDouble() * (phiB - phiA));
}

// The bound itself: n · ω <= cosBound for random n in a normal cell and ω in a block, over cells
// of every size and latitude (the poles' included, whose radius is the widest).
TEST(LocalCosBound, BoundsTheCosineOverBothCells) {
  Pcg32 rng(17);
  uint64_t tight = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    auto cell = [&] {
      const double dt = kPi / (1 + (rng.nextUint() % (64))), dp = 2 * kPi / (1 + (rng.nextUint() % (64)));
      const double t0 = std::floor(rng.nextDouble() * kPi / dt) * dt,
                   p0 = std::floor(rng.nextDouble() * 2 * kPi / dp) * dp;
      return std::array<double, 4>{t0, std::min(kPi, t0 + dt), p0, p0 + dp};
    };
    const auto a = cell(), b = cell();
    const LocalEnvironmentTable::Cap ca = LocalEnvironmentTable::capOf(a[0], a[1], a[2], a[3]);
    const LocalEnvironmentTable::Cap cb = LocalEnvironmentTable::capOf(b[0], b[1], b[2], b[3]);
    const double bound = LocalEnvironmentTable::cosBound(ca.centre, ca.radius, cb.centre, cb.radius);
    for (int k = 0; k < 50; ++k) {
      const Vec3d n = randomInCell(rng, a[0], a[1], a[2], a[3]), w = randomInCell(rng, b[0], b[1], b[2], b[3]);
      const double c = dot(n, w);
      ASSERT_LE(c, bound + 1e-12) << "trial " << trial;
      if (c > 0) {
        ASSERT_GT(bound, 0) << "trial " << trial;
        tight += c > 0.9 * bound;
      }
    }
  }
  EXPECT_GT(tight, 1000u);  // not trivially loose
}

// cosBound is the formula of the header comment, bit for bit (its shortcut for blocks far below
// the horizon included), on random caps of every size and on caps facing away from each other.
TEST(LocalCosBound, IsTheAngleFormulaExactly) {
  auto formula = [](const Vec3d& a, double ra, const Vec3d& b, double rb) {
    const Vec3d c = cross(a, b);
    const double angle = std::max(0.0, std::atan2(length(c), dot(a, b)) - ra - rb - 1e-9);
    return angle >= kPi / 2 ? 0.0 : std::cos(angle);
  };
  Pcg32 rng(23);
  uint64_t zeros = 0, positives = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    const Vec3d a = randomDirection(rng);
    // Half the trials near the antipode of a, where the shortcut's threshold lies.
    const Vec3d b = trial % 2 ? randomDirection(rng) : normalize(-a + randomDirection(rng) * (0.3 * rng.nextDouble()));
    const double ra = rng.nextDouble() * 0.5 * (trial % 3), rb = rng.nextDouble() * 0.2 * (trial % 5 != 0);
    const double bound = LocalEnvironmentTable::cosBound(a, ra, b, rb);
    ASSERT_EQ(bound, formula(a, ra, b, rb)) << "trial " << trial;
    (bound == 0 ? zeros : positives) += 1;
  }
  // Straddling the horizon of the widened bound: ∠ = π/2 + radii + 1e-9 + δ.
  for (int trial = 0; trial < 2000; ++trial) {
    const double theta = rng.nextDouble() * kPi, phi = rng.nextDouble() * 2 * kPi;
    const double ra = rng.nextDouble() * 0.3, rb = rng.nextDouble() * 0.3;
    for (double delta : {-1e-10, -1e-12, 0.0, 1e-12, 1e-10}) {
      const double angle = kPi / 2 + ra + rb + 1e-9 + delta;
      const Vec3d a = LatLongMapping::direction(theta, phi);
      const Vec3d b = LatLongMapping::direction(theta + angle, phi);  // along the meridian, past the pole
      ASSERT_EQ(LocalEnvironmentTable::cosBound(a, ra, b, rb), formula(a, ra, b, rb)) << "trial " << trial;
    }
  }
  EXPECT_GT(zeros, 50000u);
  EXPECT_GT(positives, 50000u);
}

// sliceOf is the cell of LatLongMapping's θ and φ in the normal grid (pixelOf's own exactness is
// LatLong.PixelOfIsThePixelOfTheAngles').
TEST(LocalTable, SliceOfIsTheCellOfTheNormalsAngles) {
  const std::shared_ptr<const EnvironmentMap> map = smoothMap(16, 8);
  for (const auto& [rows, columns] : std::vector<std::pair<uint32_t, uint32_t>>{{32, 64}, {5, 7}, {1, 1}}) {
    const LocalEnvironmentTable table(map, {.normalRows = rows, .normalColumns = columns});
    Pcg32 rng(rows * 7919 + columns);
    for (int i = 0; i < 10000; ++i) {
      const Vec3d n = randomDirection(rng);
      const uint32_t r =
          std::min(static_cast<uint32_t>(LatLongMapping::theta(n) * (rows * std::numbers::inv_pi)), rows - 1);
      const uint32_t c =
          std::min(static_cast<uint32_t>(LatLongMapping::phi(n) * (columns * 0.5 * std::numbers::inv_pi)), columns - 1);
      ASSERT_EQ(table.sliceOf(n), std::size_t{r} * columns + c) << rows << "x" << columns;
    }
  }
}

// pdf > 0 wherever L(ω) max(0, n · ω) > 0, for random normals in a cell and random directions,
// on a map lit everywhere (every block has mass) and on the low sun, at two normal grids.
TEST(LocalTable, PositiveWhereverTheIntegrandIs) {
  for (const LocalEnvironmentOptions options :
       {LocalEnvironmentOptions{}, LocalEnvironmentOptions{.normalRows = 5, .normalColumns = 7, .blockSize = 8}}) {
    for (const auto& map : {smoothMap(128, 64), lowSun(200, 100)}) {
      const LocalEnvironmentTable table(map, options);
      Pcg32 rng(5);
      uint64_t checked = 0;
      for (int cell = 0; cell < 40; ++cell) {
        const uint32_t r = cell < 4 ? (cell % 2 ? options.normalRows - 1 : 0) : (rng.nextUint() % (options.normalRows));
        const uint32_t c = (rng.nextUint() % (options.normalColumns));
        const double t0 = kPi * r / options.normalRows, t1 = kPi * (r + 1) / options.normalRows;
        const double p0 = 2 * kPi * c / options.normalColumns, p1 = 2 * kPi * (c + 1) / options.normalColumns;
        for (int k = 0; k < 500; ++k) {
          const Vec3d n = randomInCell(rng, t0, t1, p0, p1), w = randomDirection(rng);
          if (dot(n, w) <= 0 || map->radiance(w).luminance() <= 0) continue;
          ++checked;
          ASSERT_GT(table.pdf(n, w), 0) << "cell " << r << "," << c;
        }
      }
      EXPECT_GT(checked, 5000u);
    }
  }
}

TEST(LocalTable, BlackMapEmitsNothing) {
  const LocalEnvironmentTable table(constantMap(64, 32, 0.0f));
  EXPECT_TRUE(table.emitsNothing());
  EXPECT_EQ(table.sample({0, 1, 0}, 0.3f, 0.6f).pdf, 0.0);
  EXPECT_EQ(table.pdf({0, 1, 0}, {1, 0, 0}), 0.0);
  table.buildAll();
  EXPECT_EQ(table.slicesBuilt(), 0u);
  EXPECT_TRUE(table.pixelProbabilities({0, 1, 0}).empty());
}

// Maps smaller than a block, and every normal cell of a coarse grid (the empty slices below a
// map lit from one side included).
TEST(LocalTable, TinyMaps) {
  const std::shared_ptr<const EnvironmentMap> maps[] = {makeMap(2, 1,
                                                                [](uint32_t, uint32_t c) {
                                                                  return Rgb{1.0f + c, 1, 1};
                                                                }),
                                                        generatedMap("tiny_3x2"),
                                                        makeMap(3, 2,
                                                                [](uint32_t r, uint32_t c) {
                                                                  return r == 0 && c == 2 ? Rgb{4, 4, 4} : Rgb{0, 0, 0};
                                                                }),
                                                        constantMap(1, 1)};
  for (const auto& map : maps) {
    const LocalEnvironmentTable table(map, {.normalRows = 4, .normalColumns = 8});
    for (uint32_t r = 0; r < 4; ++r)
      for (uint32_t c = 0; c < 8; ++c) {
        const Vec3d n = LatLongMapping::direction(kPi * (r + 0.5) / 4, 2 * kPi * (c + 0.5) / 8);
        expectConsistent(table, n, std::to_string(map->width()) + "x" + std::to_string(map->height()));
      }
    EXPECT_EQ(table.slicesBuilt(), 32u);
  }
}

TEST(LocalTable, LazyAndEagerBuilds) {
  const LocalEnvironmentTable table(generatedMap("low_sun_200x100"), {.normalRows = 8, .normalColumns = 16});
  EXPECT_EQ(table.slices(), 128u);
  EXPECT_EQ(table.slicesBuilt(), 0u);
  const std::size_t pixelTables = table.bytes();
  const Vec3d n{0.3, 0.8, -0.2};
  const LocalEnvironmentTable::Sample lazy = table.sample(n, 0.25f, 0.75f);
  EXPECT_EQ(table.slicesBuilt(), 1u);
  table.pdf(n, {1, 0, 0});
  EXPECT_EQ(table.slicesBuilt(), 1u);
  EXPECT_GT(table.bytes(), pixelTables);
  table.buildAll();
  EXPECT_EQ(table.slicesBuilt(), 128u);
  const LocalEnvironmentTable::Sample eager = table.sample(n, 0.25f, 0.75f);
  EXPECT_EQ(lazy.direction, eager.direction);
  EXPECT_EQ(lazy.pdf, eager.pdf);
  EXPECT_EQ(table.denseBytes(), 128u * 200 * 100 * 4);
}

TEST(LocalTable, RejectsBadOptions) {
  const auto map = constantMap(8, 4);
  auto expectOption = [&](const LocalEnvironmentOptions& o, const std::string& option,
                          const SimplifyOptions& simplify = {}) {
    try {
      LocalEnvironmentTable table(map, o, simplify);
      ADD_FAILURE() << option << " accepted";
    } catch (const OptionError& e) {
      EXPECT_EQ(e.option(), option) << e.what();
    }
  };
  expectOption({.normalRows = 0}, "normal_rows");
  expectOption({.normalColumns = 5000}, "normal_columns");
  expectOption({.blockSize = 0}, "block_size");
  expectOption({}, "epsilon", {.epsilon = -1});
  EXPECT_THROW(LocalEnvironmentTable(nullptr), std::invalid_argument);
}

// The sizes the design promises on a real 1024 × 512 map at 32 × 64 normal cells.
TEST(LocalTable, SharedMapSizes) {
  ACDF_SKIP_WITHOUT_SHARED_ENVMAPS();
  const auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(sharedEnvmap(kSharedEnvmaps[0])));
  const LocalEnvironmentTable table(map);
  const auto start = std::chrono::steady_clock::now();
  table.buildAll();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::cout << kSharedEnvmaps[0] << ": " << table.slicesBuilt() << " slices in " << ms << " ms, " << table.bytes()
            << " bytes (dense " << table.denseBytes() << ")\n";
  EXPECT_EQ(table.slicesBuilt(), 2048u);
  EXPECT_LE(table.bytes(), 32u << 20);
  EXPECT_GE(table.denseBytes(), 100 * table.bytes());
}

}  // namespace

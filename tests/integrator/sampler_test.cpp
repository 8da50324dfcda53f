// The sample sources: a pixel sample's values depend on the pixel, the sample index and the seed
// alone — not on the order pixel samples are asked for, on what was asked before, nor on which
// clone asks — and they lie in [0, 1). The Sobol source stratifies each decision over a pixel's
// samples and gives every vertex its own fixed dimensions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "acdf/integrator/sampler.h"
#include "acdf/integrator/scene.h"
#include "acdf/sampling/file_error.h"

namespace acdf {
namespace {

using PixelSample = std::tuple<uint32_t, uint32_t, uint32_t>;  // x, y, sample index

// The first values of a pixel sample, in the integrator's mix of calls: the pixel position, then
// per vertex a light 2D, a BSDF 2D and a roulette 1D.
std::vector<float> valuesOf(Sampler& sampler, const PixelSample& p, int vertices = 4) {
  const auto [x, y, s] = p;
  sampler.startPixelSample(x, y, s);
  const auto [px, py] = sampler.getPixel2D();
  std::vector<float> values{px, py};
  for (int v = 0; v < vertices; ++v) {
    sampler.startVertex(v);
    for (int twice = 0; twice < 2; ++twice) {
      const auto [u0, u1] = sampler.get2D();
      values.push_back(u0);
      values.push_back(u1);
    }
    values.push_back(sampler.get1D());
  }
  return values;
}

std::vector<PixelSample> pixelSamples() {
  std::vector<PixelSample> all;
  for (uint32_t y : {0u, 1u, 37u})
    for (uint32_t x : {0u, 1u, 63u})
      for (uint32_t s : {0u, 1u, 2u, 1000u}) all.emplace_back(x, y, s);
  return all;
}

class EverySampler : public ::testing::TestWithParam<SamplerKind> {};

TEST_P(EverySampler, ValuesDependOnThePixelSampleAloneNotOnTheOrderAsked) {
  const std::unique_ptr<Sampler> prototype = makeSampler(GetParam(), 7, 64);
  std::map<PixelSample, std::vector<float>> inOrder;
  {
    const auto sampler = prototype->clone();
    for (const PixelSample& p : pixelSamples()) inOrder[p] = valuesOf(*sampler, p);
  }
  // Shuffled, from another clone that first consumed values of other pixel samples, and asking
  // some of them for fewer dimensions (a path that ended early).
  std::vector<PixelSample> shuffled = pixelSamples();
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(3));
  const auto other = prototype->clone();
  for (std::size_t i = 0; i < shuffled.size(); ++i) {
    (void)valuesOf(*other, {5, 5, static_cast<uint32_t>(i)}, static_cast<int>(i % 3));
    const std::vector<float> values = valuesOf(*other, shuffled[i]);
    EXPECT_EQ(values, inOrder.at(shuffled[i]));
  }
  // A sampler made afresh with the same seed and frame agrees too.
  EXPECT_EQ(valuesOf(*makeSampler(GetParam(), 7, 64), {63, 37, 1000}), inOrder.at({63, 37, 1000}));
}

TEST_P(EverySampler, PixelsSamplesAndSeedsGetTheirOwnValues) {
  const std::unique_ptr<Sampler> samplerPtr = makeSampler(GetParam(), 7, 64),
                                 otherSeedPtr = makeSampler(GetParam(), 8, 64);
  Sampler &sampler = *samplerPtr, &otherSeed = *otherSeedPtr;
  std::map<std::vector<float>, PixelSample> seen;
  for (const PixelSample& p : pixelSamples()) {
    const std::vector<float> values = valuesOf(sampler, p);
    for (float v : values) {
      ASSERT_GE(v, 0.0f);
      ASSERT_LT(v, 1.0f);
    }
    EXPECT_TRUE(seen.emplace(values, p).second) << "two pixel samples with the same values";
    EXPECT_NE(valuesOf(otherSeed, p), values) << "the seed must matter";
  }
  // The frame's width numbers the pixels: the same (x, y) in a frame of another width is another
  // pixel.
  EXPECT_NE(valuesOf(*makeSampler(GetParam(), 7, 32), {0, 1, 0}), valuesOf(sampler, {0, 1, 0}));
}

INSTANTIATE_TEST_SUITE_P(Kinds, EverySampler, ::testing::Values(SamplerKind::Independent, SamplerKind::Sobol),
                         [](const auto& info) { return std::string(toString(info.param)); });

TEST(SamplerKind, NamesRoundTripAndUnknownNamesThrow) {
  for (SamplerKind k : {SamplerKind::Independent, SamplerKind::Sobol}) EXPECT_EQ(parseSamplerKind(toString(k)), k);
  EXPECT_THROW(parseSamplerKind("halton"), std::invalid_argument);
}

// Whether the 2^m points are a (0,m,2)-net: every elementary interval of area 2^-m, of every
// shape 2^-k × 2^-(m-k), holds exactly one.
bool isZeroNet(const std::vector<std::array<float, 2>>& points, int m) {
  for (int k = 0; k <= m; ++k) {
    std::set<std::pair<uint32_t, uint32_t>> cells;
    for (const auto& [u, v] : points)
      cells.emplace(static_cast<uint32_t>(u * float(1u << k)), static_cast<uint32_t>(v * float(1u << (m - k))));
    if (cells.size() != points.size()) return false;
  }
  return true;
}

// The first 2^m samples of one pixel, as `decision` reads them.
std::vector<std::array<float, 2>> pixelPoints(Sampler& sampler, int m,
                                              const std::function<std::array<float, 2>(Sampler&)>& decision) {
  std::vector<std::array<float, 2>> points;
  for (uint32_t s = 0; s < (1u << m); ++s) {
    sampler.startPixelSample(5, 9, s);
    points.push_back(decision(sampler));
  }
  return points;
}

TEST(SobolSampler, EveryDecisionOfAPixelIsStratified) {
  SobolSampler sampler(3, 64);
  const auto pixel = [](Sampler& s) { return s.getPixel2D(); };
  // Vertex 2's light and BSDF samples, after vertices 0 and 1 took their values.
  const auto light = [](Sampler& s) {
    for (uint32_t d = 0; d < 2; ++d) {
      s.startVertex(d);
      s.get2D(), s.get2D(), s.get1D();
    }
    s.startVertex(2);
    return s.get2D();
  };
  const auto bsdf = [&](Sampler& s) {
    (void)light(s);
    return s.get2D();
  };
  for (int m : {4, 6, 8}) {
    EXPECT_TRUE(isZeroNet(pixelPoints(sampler, m, pixel), m)) << "pixel position, 2^" << m;
    EXPECT_TRUE(isZeroNet(pixelPoints(sampler, m, light), m)) << "light sample, 2^" << m;
    EXPECT_TRUE(isZeroNet(pixelPoints(sampler, m, bsdf), m)) << "BSDF sample, 2^" << m;
  }
  // Independent values are not nets (the test can tell).
  IndependentSampler independent(3, 64);
  EXPECT_FALSE(isZeroNet(pixelPoints(independent, 6, pixel), 6));
}

TEST(SobolSampler, AVertexReadsItsOwnDimensionsWhateverThePathAskedBefore) {
  SobolSampler a(3, 64), b(3, 64);
  for (uint32_t s = 0; s < 64; ++s) {
    // Path a: vertices 0 and 1 made every call; path b: none (bsdf-only, or before roulette).
    a.startPixelSample(1, 2, s), b.startPixelSample(1, 2, s);
    (void)a.getPixel2D();
    for (uint32_t d = 0; d < 2; ++d) {
      a.startVertex(d);
      (void)a.get2D(), (void)a.get2D(), (void)a.get1D();
    }
    a.startVertex(2), b.startVertex(2);
    const auto first = a.get2D(), second = a.get2D();
    EXPECT_EQ(first, b.get2D());
    EXPECT_EQ(second, b.get2D());
    EXPECT_EQ(a.get1D(), b.get1D());
    // Within a vertex, the decisions read different components.
    EXPECT_NE(first, second);
    // And a vertex's first decision is not the next vertex's.
    a.startVertex(3);
    EXPECT_NE(a.get2D(), first);
  }
}

// Product sampling's candidates (getCandidates(M)) take the place of the light sample: the BSDF
// sample after them reads the same component as after a light sample. Candidate i of sample s is
// point M·s + i of the light's component, so 2^m candidates of 2^(m−2) samples are a (0,m,2)-net,
// and so are the resampling values (with their low bits dropped) of 2^m samples.
TEST(SobolSampler, ProductCandidatesAreStratifiedAndTakeTheLightSamplesPlace) {
  constexpr uint32_t M = 4;
  for (int m : {4, 6, 8}) {
    SobolSampler a(3, 64), b(3, 64);
    std::vector<std::array<float, 2>> candidates, resampling;
    for (uint32_t s = 0; s < (1u << m); ++s) {
      a.startPixelSample(5, 9, s), b.startPixelSample(5, 9, s);
      a.startVertex(1), b.startVertex(1);
      CandidateValues values = a.getCandidates(M);
      (void)b.get2D();
      EXPECT_EQ(a.get2D(), b.get2D()) << "the BSDF sample after the candidates";
      for (uint32_t i = 0; i < M; ++i)
        if (s < (1u << m) / M) candidates.push_back(values.point(i));
      const double u = values.resamplingValue();
      ASSERT_TRUE(u >= 0 && u < 1);
      resampling.push_back({static_cast<float>(std::ldexp(std::floor(std::ldexp(u, 24)), -24)), 0.5f});
    }
    EXPECT_TRUE(isZeroNet(candidates, m)) << "candidates, 2^" << m;
    std::vector<int> cells(1u << m, 0);
    for (const auto& r : resampling) ++cells[static_cast<std::size_t>(r[0] * (1u << m))];
    EXPECT_EQ(std::count(cells.begin(), cells.end(), 1), 1 << m) << "resampling values, 2^" << m;
  }
}

// Branch b of B at vertex 0 (after its light sample) reads, from its BSDF sample on, the values
// pixel sample B·s + b reads there: a pixel's branches are one stratified sequence, as its samples
// are, whatever an earlier branch asked. The independent source gives every branch new values.
TEST(SobolSampler, BranchesReadTheirOwnPointsOfEveryLaterDecision) {
  constexpr uint32_t B = 4;
  SobolSampler path(3, 64), reference(3, 64);
  std::vector<std::array<float, 2>> bsdf;
  for (uint32_t s = 0; s < 16; ++s) {
    path.startPixelSample(5, 9, s);
    path.startVertex(0);
    (void)path.get2D();
    for (uint32_t b = 0; b < B; ++b) {
      path.startBranch(b, B);
      reference.startPixelSample(5, 9, B * s + b);
      reference.startVertex(0);
      (void)reference.get2D();
      const auto first = path.get2D();
      EXPECT_EQ(first, reference.get2D()) << "vertex 0's BSDF sample, sample " << s << " branch " << b;
      bsdf.push_back(first);
      for (uint32_t d = 1; d < 3; ++d) {
        path.startVertex(d), reference.startVertex(d);
        EXPECT_EQ(path.get2D(), reference.get2D()) << "vertex " << d;
        EXPECT_EQ(path.get2D(), reference.get2D()) << "vertex " << d;
        EXPECT_EQ(path.get1D(), reference.get1D()) << "vertex " << d;
      }
    }
  }
  EXPECT_TRUE(isZeroNet(bsdf, 6)) << "the branches' BSDF samples of 16 pixel samples";

  IndependentSampler independent(3, 64);
  independent.startPixelSample(5, 9, 0);
  independent.startVertex(0);
  (void)independent.get2D();
  std::set<std::array<float, 2>> seen;
  for (uint32_t b = 0; b < B; ++b) {
    independent.startBranch(b, B);
    seen.insert(independent.get2D());
  }
  EXPECT_EQ(seen.size(), B);
}

// The scene's render.sampler, Sobol by default (it won at equal time, docs/performance.md), replaced by
// SceneOverrides::sampler (--sampler); a bad name is a FileError with its JSON path.
TEST(SceneSampler, FromTheSceneFileOrTheOverride) {
  nlohmann::json scene = {
      {"camera", {{"eye", {0, 0, 3}}, {"target", {0, 0, 0}}, {"fov", 30}, {"width", 4}, {"height", 4}}},
      {"environment", {{"type", "constant"}, {"radiance", 1}}},
      {"materials", {{"m", {{"type", "diffuse"}, {"albedo", 0.5}}}}},
      {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "m"}}}},
  };
  SceneAssets tables(TableCache::disabled());
  const auto load = [&](const SceneOverrides& overrides = {}) {
    return loadSceneText(scene.dump(), "scene.json", overrides, tables).settings.sampler;
  };
  EXPECT_EQ(load(), SamplerKind::Sobol);
  scene["render"] = {{"sampler", "independent"}};
  EXPECT_EQ(load(), SamplerKind::Independent);
  EXPECT_EQ(load({.sampler = SamplerKind::Sobol}), SamplerKind::Sobol);
  scene["render"]["sampler"] = "halton";
  try {
    (void)load();
    ADD_FAILURE() << "a bad sampler name loaded";
  } catch (const FileError& e) {
    EXPECT_EQ(e.problem(), "$.render.sampler: unknown sampler 'halton' (independent or sobol)");
  }
}

}  // namespace
}  // namespace acdf

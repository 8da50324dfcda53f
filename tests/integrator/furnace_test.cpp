// Furnace tests: scenes whose exact image is known.
//  - A diffuse sphere of albedo ρ under a constant environment L reflects ρL towards every
//    pixel (a convex shape sees only the sky), for every MIS mode × environment strategy, and
//    under product direct lighting for every environment strategy × mixture.
//  - A measured-material sphere under a constant white environment shows, at each pixel, the
//    material's directional albedo for that pixel's ωo, computed here by brute-force quadrature.

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/frame.h"
#include "render_test_util.h"

namespace acdf {
namespace {

using rendertest::furnaceScene;
using rendertest::renderScene;

// Every strategy the scene file and the CLI accept, so a strategy added to EnvironmentSampling is
// not forgotten here.
std::vector<std::string> environmentStrategies() {
  std::vector<std::string> names;
  for (EnvironmentSampling s : kEnvironmentSamplings) names.emplace_back(toString(s));
  return names;
}

struct Combination {
  std::string mis, env;
};

class DiffuseFurnace : public ::testing::TestWithParam<Combination> {};

// Samples per pixel of a 24 × 24 image whose mean tells a 1 % bias from noise: light-only half
// wastes its samples below the horizon and needs four times as many.
uint32_t sppToSeeABias(const std::string& mis) { return mis == "light-only" ? 512 : 128; }

// The images of this program that expectUniformImage judges, each on three channels: the family
// whose image-mean tests share the level kFamilyAlpha (Šidák).
uint32_t judgedImages();
constexpr double kFamilyAlpha = 0.01;

// z with P(|N(0, 1)| > z) = alpha.
double twoSidedNormalBound(double alpha) {
  double lo = 0, hi = 40;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::numbers::sqrt2) > alpha ? lo : hi) = mid;
  }
  return hi;
}

// The estimator is unbiased: the image mean, whose standard error pools every pixel's, is within
// the Šidák-corrected bound of the family (about 4 standard errors), which an estimator biased by
// 1 % exceeds on every strategy here. Each pixel is within 6 of its own standard errors: not a
// test of bias (a few hundred pixels, each's error estimated from a few dozen samples, would
// fail a tighter bound by chance), but of broken pixels (black, doubled, NaN). Zero-variance
// strategies (BSDF sampling of a diffuse surface under a constant sky) leave only rounding.
void expectUniformImage(const Film& film, const Rgb& expected) {
  auto check = [](double value, double exact, double se, double sigmas, const std::string& what) {
    EXPECT_LE(std::abs(value - exact), sigmas * se + 1e-6 * exact)
        << what << ": " << value << " vs " << exact << " (standard error " << se << ")";
  };
  for (uint32_t y = 0; y < film.height(); ++y)
    for (uint32_t x = 0; x < film.width(); ++x) {
      const Rgb m = film.mean(x, y), se = film.standardError(x, y);
      const std::string where = "pixel " + std::to_string(x) + "," + std::to_string(y);
      check(m.r, expected.r, se.r, 6, where + " red");
      check(m.g, expected.g, se.g, 6, where + " green");
      check(m.b, expected.b, se.b, 6, where + " blue");
    }
  static const double bound = twoSidedNormalBound(sidakAlpha(kFamilyAlpha, 3 * judgedImages()));
  const rendertest::ImageMean mean = rendertest::imageMean(film);
  check(mean.mean.r, expected.r, mean.standardError.r, bound, "image red");
  check(mean.mean.g, expected.g, mean.standardError.g, bound, "image green");
  check(mean.mean.b, expected.b, mean.standardError.b, bound, "image blue");
}

const Rgb kAlbedo{0.8f, 0.5f, 0.2f}, kRadiance{1.0f, 2.0f, 0.5f};
const nlohmann::json kDiffuse = {{"type", "diffuse"}, {"albedo", {kAlbedo.r, kAlbedo.g, kAlbedo.b}}};

TEST_P(DiffuseFurnace, RendersAlbedoTimesRadiance) {
  SceneOverrides overrides;
  overrides.mis = parseMisMode(GetParam().mis);
  overrides.envSampling = parseEnvironmentSampling(GetParam().env);
  expectUniformImage(renderScene(furnaceScene(kDiffuse, kRadiance, 24, sppToSeeABias(GetParam().mis)), overrides).film,
                     kAlbedo * kRadiance);
}

std::vector<Combination> everyCombination() {
  std::vector<Combination> all;
  for (const char* mis : {"power", "balance", "bsdf-only", "light-only"})
    for (const std::string& env : environmentStrategies()) all.push_back({mis, env});
  return all;
}

INSTANTIATE_TEST_SUITE_P(EveryStrategy, DiffuseFurnace, ::testing::ValuesIn(everyCombination()), [](const auto& info) {
  std::string name = info.param.mis + "_" + info.param.env;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
});

// Product direct lighting (resampled f·L·cos) on every environment strategy and at both ends of
// the mixture: light candidates alone (which need the complete table), BSDF candidates alone, and
// half of each (where a compensated table may leave directions to the BSDF).
struct ProductCombination {
  std::string env;
  double bsdfFraction;
};

class ProductDiffuseFurnace : public ::testing::TestWithParam<ProductCombination> {};

TEST_P(ProductDiffuseFurnace, RendersAlbedoTimesRadiance) {
  nlohmann::json scene = furnaceScene(kDiffuse, kRadiance, 24, 128);
  scene["render"]["direct"] = "product";
  scene["render"]["candidates"] = 4;
  scene["render"]["bsdf_fraction"] = GetParam().bsdfFraction;
  SceneOverrides overrides;
  overrides.envSampling = parseEnvironmentSampling(GetParam().env);
  expectUniformImage(renderScene(scene, overrides).film, kAlbedo * kRadiance);
}

std::vector<ProductCombination> everyProductCombination() {
  std::vector<ProductCombination> all;
  for (const std::string& env : environmentStrategies())
    for (double b : {0.0, 0.5, 1.0}) all.push_back({env, b});
  return all;
}

INSTANTIATE_TEST_SUITE_P(EveryStrategy, ProductDiffuseFurnace, ::testing::ValuesIn(everyProductCombination()),
                         [](const auto& info) {
                           std::string name = info.param.env + "_bsdf" +
                                              std::to_string(static_cast<int>(info.param.bsdfFraction * 10));
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

// Under Sobol samples, per MIS mode, with an environment strategy that leaves variance (uniform
// sphere samples of a constant sky weigh cosθ).
class SobolDiffuseFurnace : public ::testing::TestWithParam<std::string> {};

SceneOverrides sobolOverrides(SamplerKind sampler, const std::string& mis) {
  SceneOverrides overrides;
  overrides.sampler = sampler;
  overrides.mis = parseMisMode(mis);
  overrides.envSampling = EnvironmentSampling::UniformSphere;
  return overrides;
}

TEST_P(SobolDiffuseFurnace, RendersAlbedoTimesRadiance) {
  expectUniformImage(
      renderScene(furnaceScene(kDiffuse, kRadiance, 24, sppToSeeABias(GetParam())),
                  sobolOverrides(SamplerKind::Sobol, GetParam()))
          .film,
      kAlbedo * kRadiance);
}

const std::vector<std::string> kMisModes = {"power", "balance", "bsdf-only", "light-only"};

// Guided by what the render learned, of the light alone and of the paths too, under power MIS
// and with light sampling alone.
const std::vector<std::pair<std::string, std::string>> kGuidedCombinations = {
    {"light", "power"}, {"light", "light-only"}, {"paths", "power"}, {"paths", "light-only"}};

uint32_t judgedImages() {
  return static_cast<uint32_t>(everyCombination().size() + everyProductCombination().size() + kMisModes.size() +
                               kGuidedCombinations.size());
}

INSTANTIATE_TEST_SUITE_P(EveryMisMode, SobolDiffuseFurnace, ::testing::ValuesIn(kMisModes), [](const auto& info) {
  std::string name = info.param;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
});

// The point of Sobol samples: at 64 spp the pixels' actual error (known here) is far below the
// independent samples' for the same scene, light sampling a uniform sphere (a smooth integrand but
// for the horizon): 0.011 against 0.15 rms in green.
TEST(SobolFurnace, StratifiedPixelsAreCloserToTheAnswer) {
  const Rgb expected = kAlbedo * kRadiance;
  auto rmsError = [&](SamplerKind sampler) {
    const Film film =
        renderScene(furnaceScene(kDiffuse, kRadiance, 12, 64), sobolOverrides(sampler, "light-only")).film;
    double sum = 0;
    for (uint32_t y = 0; y < film.height(); ++y)
      for (uint32_t x = 0; x < film.width(); ++x) sum += std::pow(double(film.mean(x, y).g) - expected.g, 2);
    return std::sqrt(sum / (film.width() * film.height()));
  };
  const double independent = rmsError(SamplerKind::Independent), sobol = rmsError(SamplerKind::Sobol);
  EXPECT_LT(sobol, 0.25 * independent) << "rms pixel error " << sobol << " (Sobol) vs " << independent
                                      << " (independent)";
}

// ∫ f(ωo, ωi) cosθi dωi over the hemisphere by the midpoint rule in (cosθi, φi) (dω = dcosθ dφ),
// per channel, in double.
std::array<double, 3> directionalAlbedo(const BrdfModel& brdf, const Vec3d& wo, int cosCells, int phiCells) {
  std::array<double, 3> sum{};
  for (int i = 0; i < cosCells; ++i) {
    const double cosTheta = (i + 0.5) / cosCells, sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    for (int j = 0; j < phiCells; ++j) {
      const double phi = 2.0 * std::numbers::pi * (j + 0.5) / phiCells;
      const Vec3d wi{sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
      const Rgb f = brdf.eval(wo, wi);
      sum[0] += f.r * cosTheta, sum[1] += f.g * cosTheta, sum[2] += f.b * cosTheta;
    }
  }
  for (double& s : sum) s *= 2.0 * std::numbers::pi / (static_cast<double>(cosCells) * phiCells);
  return sum;
}

TEST(MeasuredFurnace, MatchesBruteForceDirectionalAlbedo) {
  // The rough aluminium preset, an isotropic adaptive table (a 4D one takes seconds to build).
  const nlohmann::json material = {{"type", "measured"},
                                   {"preset", "rough-aluminium"},
                                   {"sampling", "adaptive"},
                                   {"table", {{"layout", "isotropic"}}}};
  const uint32_t size = 16;
  const nlohmann::json scene = furnaceScene(material, Rgb{1, 1, 1}, size, 1);
  SceneAssets tables(TableCache::disabled());
  const Scene loaded = loadSceneText(scene.dump(), std::string(ACDF_SOURCE_DIR) + "/test.json", {}, tables);
  const auto brdf = tables.merlPreset("rough-aluminium", MerlBrdf::Interpolation::Nearest);

  // A few pixels from the centre (ωo near the normal) to the edge (grazing).
  const std::vector<std::array<uint32_t, 2>> pixels = {{8, 8}, {3, 8}, {0, 0}};
  const uint32_t spp = rendertest::kSanitized ? 2000 : 20000;
  const int strata = 4, cosCells = rendertest::kSanitized ? 96 : 256;
  for (const auto& [px, py] : pixels) {
    SceneOverrides overrides;
    overrides.crop = CropWindow{px, py, px + 1, py + 1};
    overrides.spp = spp;
    const auto r = rendertest::renderScene(scene, overrides);
    // The pixel's expected value: the albedo averaged over its area (strata² positions).
    std::array<double, 3> expected{};
    for (int sy = 0; sy < strata; ++sy)
      for (int sx = 0; sx < strata; ++sx) {
        const Ray ray = loaded.camera->generateRay(px + (sx + 0.5) / strata, py + (sy + 0.5) / strata);
        const auto hit = loaded.geometry->intersect(ray);
        ASSERT_TRUE(hit.has_value());
        const Vec3d wo = Frame(hit->normal, hit->tangentHint).toLocal(-ray.direction);
        const std::array<double, 3> albedo = directionalAlbedo(*brdf, wo, cosCells, 2 * cosCells);
        for (int c = 0; c < 3; ++c) expected[c] += albedo[c] / (strata * strata);
      }
    const Rgb m = r.film.mean(0, 0), se = r.film.standardError(0, 0);
    // 3 standard errors of the render, plus 0.5% for the quadrature of a table that is
    // piecewise constant in the half/difference angles.
    for (auto [value, exact, error] :
         {std::tuple{m.r, expected[0], se.r}, std::tuple{m.g, expected[1], se.g}, std::tuple{m.b, expected[2], se.b}})
      EXPECT_NEAR(value, exact, 3 * error + 0.005 * exact) << "pixel " << px << "," << py;
  }
}

class GuidedDiffuseFurnace : public ::testing::TestWithParam<std::pair<std::string, std::string>> {};

TEST_P(GuidedDiffuseFurnace, RendersAlbedoTimesRadiance) {
  SceneOverrides overrides = sobolOverrides(SamplerKind::Independent, GetParam().second);
  overrides.guiding = parseGuidingMode(GetParam().first);
  const rendertest::Rendered rendered =
      renderScene(furnaceScene(kDiffuse, kRadiance, 24, sppToSeeABias(GetParam().second)), overrides);
  EXPECT_TRUE(rendered.stats.guiding.guided);
  expectUniformImage(rendered.film, kAlbedo * kRadiance);
}

INSTANTIATE_TEST_SUITE_P(EveryGuidingMode, GuidedDiffuseFurnace, ::testing::ValuesIn(kGuidedCombinations),
                         [](const auto& info) {
                           std::string name = info.param.first + "_" + info.param.second;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace acdf

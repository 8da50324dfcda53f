// makeBrdfSampler, the one way a BRDF sampler is chosen by name, and the models' own samplers.

#include <memory>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/brdf_chi_square.h"
#include "acdf/brdf/brdf_sampler_factory.h"
#include "acdf/brdf/lambertian.h"
#include "acdf/brdf/rgl.h"
#include "acdf/brdf/rgl_synthesis.h"

namespace acdf {
namespace {

std::shared_ptr<const RglBrdf> smallRgl() {
  const RglSynthesisOptions small{.thetaIn = 4, .ndf = 32, .vndf = 32, .reflectance = 16};
  const TensorFile t = synthesizeRgl(AnalyticBrdf::preset("gold"), small, "gold");
  return std::make_shared<const RglBrdf>(TensorFile::parse(t.serialize(), "gold.bsdf"), "gold.bsdf");
}

TabulatedBrdfOptions smallTable() {
  TabulatedBrdfOptions o;
  o.layout = TabulatedBrdfOptions::Layout::Isotropic;
  o.thetaOutCells = 4;
  o.thetaHalfCells = 16;
  o.phiHalfCells = 8;
  return o;
}

TEST(BrdfSamplerFactory, NamesRoundTrip) {
  for (BrdfSampling s : {BrdfSampling::Cosine, BrdfSampling::Uniform, BrdfSampling::Adaptive, BrdfSampling::Native})
    EXPECT_EQ(parseBrdfSampling(toString(s)), s);
  EXPECT_EQ(toString(BrdfSampling::Native), "rgl");
  EXPECT_THROW(parseBrdfSampling("warps"), std::invalid_argument);
}

TEST(BrdfSamplerFactory, NativeIsTheModelsOwnSampler) {
  const std::shared_ptr<const BrdfModel> rgl = smallRgl();
  EXPECT_EQ(makeBrdfSampler(rgl, BrdfSampling::Native)->name(), "rgl");
  const std::shared_ptr<const BrdfModel> ggx =
      std::make_shared<const AnalyticBrdf>(AnalyticBrdf::conductor(0.2, {0.9, 0.8, 0.5}));
  EXPECT_EQ(makeBrdfSampler(ggx, BrdfSampling::Native)->name(), "ggx");
  const std::shared_ptr<const BrdfModel> lambertian = std::make_shared<const LambertianBrdf>(Rgb{0.5f, 0.5f, 0.5f});
  EXPECT_EQ(lambertian->nativeSampler(lambertian), nullptr);
  EXPECT_THROW(makeBrdfSampler(lambertian, BrdfSampling::Native), std::invalid_argument);
  // The sampler shares the model it is asked for: `self` must be that model.
  EXPECT_THROW(rgl->nativeSampler(ggx), std::invalid_argument);
}

TEST(BrdfSamplerFactory, TableStrategiesSetTheMethod) {
  const std::shared_ptr<const BrdfModel> ggx =
      std::make_shared<const AnalyticBrdf>(AnalyticBrdf::conductor(0.3, {0.9, 0.8, 0.5}));
  EXPECT_EQ(makeBrdfSampler(ggx, BrdfSampling::Cosine)->name(), "cosine");
  EXPECT_EQ(makeBrdfSampler(ggx, BrdfSampling::Uniform, smallTable())->name(), "uniform-iso");
  EXPECT_EQ(makeBrdfSampler(ggx, BrdfSampling::Adaptive, smallTable())->name(), "adaptive-iso");
  TabulatedBrdfOptions bad = smallTable();
  bad.cosineWeight = 2;
  EXPECT_ANY_THROW(makeBrdfSampler(ggx, BrdfSampling::Adaptive, bad));
}

// Every sampler the factory makes describes its density, so the chi-square test knows it: the
// bin probabilities sum to 1 (the cosine part above the horizon, the reflected rest anywhere).
TEST(BrdfSamplerFactory, EverySamplerDescribesItsDensityForTheChiSquareTest) {
  const std::shared_ptr<const BrdfModel> rgl = smallRgl();
  SphereChiSquareOptions o;
  o.thetaBins = 16;
  o.phiBins = 32;
  o.equalAreaRows = true;
  o.subPoints = 2;
  const Vec3d wo = normalize(Vec3d{0.4, 0.1, 0.9});
  for (BrdfSampling s : {BrdfSampling::Cosine, BrdfSampling::Uniform, BrdfSampling::Adaptive, BrdfSampling::Native}) {
    const auto sampler = makeBrdfSampler(rgl, s, smallTable());
    const std::vector<double> p = brdfBinProbabilities(*sampler, wo, o);
    double total = 0;
    for (double v : p) total += v;
    EXPECT_NEAR(total, 1.0, 2e-3) << toString(s);
    EXPECT_EQ(sampler->halfVectorDensity(wo).cosineShare == 1.0, s == BrdfSampling::Cosine) << toString(s);
  }
}

}  // namespace
}  // namespace acdf

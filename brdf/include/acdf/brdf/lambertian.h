#pragma once
// The Lambertian BRDF f = ρ/π, the renderer's diffuse material: a model with the same interface
// as the measured ones, sampled by CosineBrdfSampler with the weight ρ (up to float rounding).

#include <string>

#include "acdf/brdf/brdf_model.h"

namespace acdf {

class LambertianBrdf final : public BrdfModel {
 public:
  // Throws std::invalid_argument unless every channel of the albedo is in [0, 1].
  explicit LambertianBrdf(const Rgb& albedo);

  const Rgb& albedo() const { return albedo_; }

  Rgb eval(const Vec3d& wo, const Vec3d& wi) const override;
  bool isotropic() const override { return true; }
  // No data; "lambertian albedo=...".
  std::string addToKey(ContentHash& content) const override;

 private:
  Rgb albedo_;
};

}  // namespace acdf

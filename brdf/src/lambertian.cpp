#include "acdf/brdf/lambertian.h"

#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace acdf {

LambertianBrdf::LambertianBrdf(const Rgb& albedo) : albedo_(albedo) {
  for (float v : {albedo.r, albedo.g, albedo.b})
    if (!(v >= 0.0f && v <= 1.0f)) throw std::invalid_argument("Lambertian BRDF: albedo outside [0, 1]");
}

Rgb LambertianBrdf::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0 && wi.z > 0)) return {};
  return albedo_ * std::numbers::inv_pi_v<float>;
}

std::string LambertianBrdf::addToKey(ContentHash&) const {
  return fmt::format("lambertian albedo={:a},{:a},{:a}", albedo_.r, albedo_.g, albedo_.b);
}

}  // namespace acdf

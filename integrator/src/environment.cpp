#include "acdf/integrator/environment.h"

#include <stdexcept>

namespace acdf {

namespace {
constexpr std::string_view kUniformSphere = "uniform-sphere";
}

EnvironmentStrategy parseEnvironmentStrategy(std::string_view name) {
  if (name == kUniformSphere) return std::nullopt;
  try {
    return parseEnvironmentSampling(name);
  } catch (const std::invalid_argument& e) {
    // The table strategies' parser names its own list, which grows with EnvironmentSampling.
    throw std::invalid_argument(std::string(e.what()) + "; or uniform-sphere");
  }
}

std::string toString(const EnvironmentStrategy& strategy) {
  return strategy ? std::string(toString(*strategy)) : std::string(kUniformSphere);
}

Environment::Environment(std::shared_ptr<const EnvironmentMap> map, Rotation worldFromMap, float scale,
                         EnvironmentStrategy strategy, std::shared_ptr<const EnvironmentLight> light)
    : map_(std::move(map)), worldFromMap_(worldFromMap), scale_(scale), strategy_(strategy), light_(std::move(light)) {
  if (strategy_ && !light_) throw std::invalid_argument("Environment: a table strategy needs its EnvironmentLight");
}

Color Environment::eval(const Vec3d& w) const { return Color(map_->radiance(worldFromMap_.applyInverse(w))) * scale_; }

LightSample Environment::sample(float u0, float u1) const {
  if (!strategy_) {
    const Vec3d w = sampleUniformSphere(u0, u1);
    return {w, eval(w), kUniformSpherePdf};
  }
  const EnvironmentSample s = light_->sample(u0, u1);
  return {s.direction, Color(s.radiance), s.pdf};
}

double Environment::pdf(const Vec3d& w) const { return strategy_ ? light_->pdf(w) : kUniformSpherePdf; }

}  // namespace acdf

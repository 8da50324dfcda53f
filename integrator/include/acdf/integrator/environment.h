#pragma once
// The scene's light: radiance arriving from infinitely far away, from an environment map (file,
// rotation about the up axis +Y, scale) or a constant (a small uniform map, so every table
// strategy applies to it too). World frame: +Y up, the map frame of lat_long.h.
//
// Sampling strategies for next-event estimation:
//   uniform-sphere  directions uniform on the sphere, pdf 1/(4π): no table at all;
//   the EnvironmentSampling strategies (uniform, alias, adaptive, compensated, ...): the
//   EnvironmentLight's table, which the caller builds (TableProvider) only when chosen.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "acdf/envmap/environment_light.h"
#include "acdf/integrator/color.h"

namespace acdf {

// nullopt is uniform-sphere sampling.
using EnvironmentStrategy = std::optional<EnvironmentSampling>;

// "uniform-sphere" or a name parseEnvironmentSampling accepts; throws std::invalid_argument.
EnvironmentStrategy parseEnvironmentStrategy(std::string_view name);
std::string toString(const EnvironmentStrategy& strategy);

struct LightSample {
  Vec3d direction;  // world, unit
  Color radiance;
  double pdf = 0;  // per steradian; 0: no sample
};

class Environment {
 public:
  // `light`: the sampling table, required unless the strategy is uniform-sphere; it must light
  // `map` with the same rotation and scale.
  Environment(std::shared_ptr<const EnvironmentMap> map, Rotation worldFromMap, float scale,
              EnvironmentStrategy strategy, std::shared_ptr<const EnvironmentLight> light);

  Color eval(const Vec3d& w) const;
  LightSample sample(float u0, float u1) const;
  double pdf(const Vec3d& w) const;

  const EnvironmentStrategy& strategy() const { return strategy_; }
  // Bytes of the sampling table (0 for uniform-sphere sampling).
  std::size_t tableBytes() const { return light_ ? light_->tableBytes() : 0; }
  // True when the strategy may give pdf 0 where the radiance is not 0 (compensated): usable
  // under MIS only.
  bool needsMis() const { return strategy_ == EnvironmentSampling::Compensated && !light_->compensationFellBack(); }

 private:
  std::shared_ptr<const EnvironmentMap> map_;
  Rotation worldFromMap_;
  double scale_;
  EnvironmentStrategy strategy_;
  std::shared_ptr<const EnvironmentLight> light_;
};

}  // namespace acdf

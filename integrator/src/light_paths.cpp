#include "acdf/integrator/light_paths.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "acdf/sampling/rng.h"
#include "parallel.h"

namespace acdf {

LightPathSource::LightPathSource(const Scene& scene) : scene_(scene) {
  const EnvironmentLight& light = *scene.environment;
  const std::vector<Portal>& portals = light.options().portals;
  for (std::size_t i = 0; i < portals.size(); ++i) {
    const double power = light.portalTable(i).table().mass({0, 1, 0, 1});
    const double area = length(cross(portals[i].edgeU, portals[i].edgeV));
    if (!(power > 0) || !(area > 0)) continue;
    total_ += power * area;
    portals_.push_back({i, power, total_});
  }
}

double LightPathSource::density(const Vec3d& position, const Vec3d& normal, const Vec3d& toLight) const {
  const EnvironmentLight& light = *scene_.environment;
  double sum = 0;
  for (const Entry& e : portals_) {
    const PortalTable& table = light.portalTable(e.index);
    const std::optional<WindowedTable2D::Window> window = table.windowFrom(position);
    if (!window) continue;
    // Positive only for a direction leaving through the rectangle, whose cosine is then positive.
    const double through = table.densityThrough(*window, toLight);
    if (through > 0) sum += through / -dot(toLight, table.normal());
  }
  return sum * std::abs(dot(normal, toLight)) / total_;
}

std::optional<LightVertex> LightPathSource::trace(uint64_t seed, uint32_t sampleIndex, uint32_t path) const {
  Pcg32 random(mixSeed(mixSeed(seed) ^ mixSeed(sampleIndex)), path);
  const double pick = random.nextDouble() * total_;
  const Entry& e = *std::min(std::upper_bound(portals_.begin(), portals_.end(), pick,
                                              [](double v, const Entry& entry) { return v < entry.cumulative; }),
                             portals_.end() - 1);
  const EnvironmentLight& light = *scene_.environment;
  const PortalTable& table = light.portalTable(e.index);
  const double s = random.nextDouble(), t = random.nextDouble();
  const Portal& portal = light.options().portals[e.index];
  const Vec3d start = portal.corner + portal.edgeU * s + portal.edgeV * t;
  const double a = random.nextDouble(), b = random.nextDouble();
  const Vec3d toLight = table.sample({{0, 1, 0, 1}, e.power}, a, b);
  if (scene_.geometry->occluded({start, toLight}, std::numeric_limits<double>::infinity())) return std::nullopt;
  const std::optional<SurfaceHit> hit = scene_.geometry->intersect({start, -toLight});
  if (!hit) return std::nullopt;
  LightVertex v;
  v.hit = *hit;
  v.toLight = toLight;
  v.density = density(hit->position, hit->normal, toLight);
  if (!(v.density > 0) || !std::isfinite(v.density)) return std::nullopt;
  v.radianceOverPdf = light.eval(toLight) * static_cast<float>(std::abs(dot(hit->normal, toLight)) / v.density);
  LightSampleContext context{.allowIncompletePdf = allowsIncompleteLightPdf(scene_.settings)};
  light.moveTo(context, hit->position, hit->normal);
  v.lightPdf = light.pdf(context, toLight);
  return v;
}

LightPathPool::LightPathPool(const LightPathSource& source, uint64_t seed, uint32_t sampleIndex, uint32_t attempts)
    : source_(source) {
  std::vector<std::optional<LightVertex>> traced(attempts);
  forEachInParallel(attempts, [&](std::size_t i) { traced[i] = source.trace(seed, sampleIndex, static_cast<uint32_t>(i)); });
  for (const auto& v : traced)
    if (v) vertices_.push_back(*v);
  successShare_ = attempts > 0 ? static_cast<double>(vertices_.size()) / attempts : 0.0;
}

}  // namespace acdf

#pragma once
// Light paths through the portals, for connections from the camera's paths (Veach 1997, ch. 10:
// bidirectional path tracing's strategy with two light vertices, one of them on the map).
//
// Behind a window or a door ajar much of the light reaches the room's surfaces as a bright patch
// (the sun through the opening), and reaches the camera only after one more bounce off it. Path
// tracing finds that patch by a BSDF sample from a vertex that happens to point at it, then lights
// it by a light sample through the portal: rare and bright, so fireflies over the whole room. A
// light path starts at the opening instead: a portal i with probability ∝ its area A_i times the
// light through its plane P_i, a point uniform on it, and a direction ω out through it with density
// p_i(ω) = luminance(ω) / P_i (its PortalTable over the whole square); the ray along −ω finds the
// room's vertex y the light reaches (the path fails where ω is blocked outside or the ray finds
// nothing). Per unit area at y and per steradian of ω that is
//
//   p_C(y, ω) = Σ_i [y → ω crosses portal i] luminance_i(ω) |n_y · ω| / (|n_i · ω| Σ_j P_j A_j),
//
// the sum over the portals the ray from y along ω passes through (LightPathSource::density). A
// camera path's vertex x connects to one vertex y of the light paths of its sample index (one pool
// of `attempts` paths, y uniform over the successful ones, times successes / attempts: the same as
// one light path), with one shadow ray x ↔ y:
//
//   T f_x(x → y) cosθ_x · cosθ_y / |x − y|² · f_y(y → x, ω) · L(ω) |n_y · ω| / p_C(y, ω) · w_C.
//
// The same path x → y → ω is also found by path tracing: x's BSDF sample reaching y (area density
// a = p_bsdf,x(x → y) cosθ_y / |x − y|²) followed by y's light sample (a · p_light,y(ω)) or by y's
// BSDF sample escaping (a · p_bsdf,y(ω)). The three weights are the MIS heuristic over those three
// densities (path_integrator.h), each side computing the same three, so they sum to 1 on every
// such path and the estimate is unbiased whatever the pool holds.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "acdf/integrator/camera.h"
#include "acdf/integrator/scene.h"

namespace acdf {

// Where a light path reaches the room: its first surface.
struct LightVertex {
  SurfaceHit hit;  // its normal on the side the light arrived from
  Vec3d toLight;   // ω: towards the map, unit
  // L(ω) |n · ω| / p_C(y, ω): the light arriving at y over the density the path was drawn with.
  Rgb radianceOverPdf;
  double density = 0;    // p_C(y, ω)
  double lightPdf = 0;   // the environment light's density of ω from y (its light samples' there)
};

// The portals of a scene's light as the starts of light paths.
class LightPathSource {
 public:
  // The light's portals, if it has any with light through them (else empty()).
  explicit LightPathSource(const Scene& scene);
  bool empty() const { return portals_.empty(); }

  // p_C(y, ω) above, for a vertex at `position` with normal `normal` (either side) and ω `toLight`.
  double density(const Vec3d& position, const Vec3d& normal, const Vec3d& toLight) const;

  // Light path number `path` of the pool of sample index `sampleIndex` under `seed`: its vertex, or
  // none where the path failed. Depends on these alone (not on the thread, nor on other paths).
  std::optional<LightVertex> trace(uint64_t seed, uint32_t sampleIndex, uint32_t path) const;

 private:
  struct Entry {
    std::size_t index;  // in the light's portals
    double power;       // P_i: the light through the whole plane
    double cumulative;  // Σ_{j <= i} P_j A_j
  };
  const Scene& scene_;
  std::vector<Entry> portals_;
  double total_ = 0;  // Σ_j P_j A_j
};

// The light paths of one sample index: what the camera's paths of that index connect to.
class LightPathPool {
 public:
  // `attempts` paths of `source` (not empty), traced in parallel.
  LightPathPool(const LightPathSource& source, uint64_t seed, uint32_t sampleIndex, uint32_t attempts);

  // The vertex a variate u in [0, 1) picks (none when every path failed), and the factor
  // successes / attempts its estimate takes. The pick starts loading the vertex: a pool is
  // megabytes and the vertex a cache miss (7 % of a render of the room), which the work between
  // the pick and the connection (the light sample's shadow ray) then hides.
  const LightVertex* pick(float u) const {
    if (vertices_.empty()) return nullptr;
    const auto i = static_cast<std::size_t>(u * static_cast<float>(vertices_.size()));
    const LightVertex* vertex = &vertices_[std::min(i, vertices_.size() - 1)];
    for (std::size_t line = 0; line < sizeof(LightVertex); line += 64)
      __builtin_prefetch(reinterpret_cast<const char*>(vertex) + line);
    return vertex;
  }
  double successShare() const { return successShare_; }
  const LightPathSource& source() const { return source_; }
  std::span<const LightVertex> vertices() const { return vertices_; }

 private:
  const LightPathSource& source_;
  std::vector<LightVertex> vertices_;
  double successShare_ = 0;
};

}  // namespace acdf

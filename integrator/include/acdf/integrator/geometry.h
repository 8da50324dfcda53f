#pragma once
// The scene's surfaces and ray queries against them, through Embree 3 (spheres as Embree's
// sphere points, triangles for quads and meshes). Embree traces in float; the hit point, normal
// and tangent are recomputed here in double from the shape's own description.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "acdf/integrator/camera.h"
#include "acdf/sampling/sphere.h"

// Embree's handles, so users of this header need not include <embree3/rtcore.h>.
using RTCDevice = struct RTCDeviceTy*;
using RTCScene = struct RTCSceneTy*;

namespace acdf {

struct Sphere {
  Vec3d center;
  double radius = 1;
  uint32_t material = 0;
};

struct TriangleMesh {
  std::vector<Vec3d> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  uint32_t material = 0;
  // The shading frame's tangent hint (frame.h); none: derived from the normal alone.
  std::optional<Vec3d> tangent;
};

struct SurfaceHit {
  double distance = 0;
  Vec3d position;
  Vec3d normal;       // geometric, unit, facing the side the ray came from
  Vec3d tangentHint;  // for the shading frame (frame.h); may be zero
  uint32_t material = 0;
};

class Geometry {
 public:
  // Throws std::invalid_argument for a non-positive radius or a vertex index out of range;
  // std::runtime_error if Embree fails. Degenerate (zero-area) triangles are dropped: they can
  // never be hit, and OBJ exporters leave them in.
  Geometry(std::vector<Sphere> spheres, std::vector<TriangleMesh> meshes);
  ~Geometry();
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;

  // The closest hit with distance in (0, ∞), if any.
  std::optional<SurfaceHit> intersect(const Ray& ray) const;
  // True if anything is hit along the ray at a distance in (0, maxDistance).
  bool occluded(const Ray& ray, double maxDistance) const;

  // A point just off the surface on the side of `direction`, to start the next ray from without
  // hitting the surface itself again (Embree's float hit points are off by ~1e-7 × |p|).
  static Vec3d offsetOrigin(const SurfaceHit& hit, const Vec3d& direction);

 private:
  SurfaceHit sphereHit(const Ray& ray, double t, uint32_t index) const;
  SurfaceHit triangleHit(const Ray& ray, double t, uint32_t mesh, uint32_t triangle) const;

  std::vector<Sphere> spheres_;
  std::vector<TriangleMesh> meshes_;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  unsigned sphereGeometryId_ = ~0u;
  std::vector<unsigned> meshGeometryIds_;  // Embree geometry id → mesh index, by position
};

}  // namespace acdf

#pragma once
// The openings of an enclosure (windows, doors, the gap of a door ajar), found by tracing, so that a
// room lights through its windows with portals nobody declared.
//
// From surface points the camera sees (a jittered grid of camera rays), directions are traced
// cosine-distributed about each point's normal. The ones that hit nothing leave the scene; they
// are followed to where they cross the box around every point hit (those seen and those the
// directions hit: in a room, its walls). On each face of the box the crossings are gathered into
// connected regions of a grid, and each region's bounding rectangle, facing into the box, becomes
// an opening. A scene is an enclosure, and its openings are used, only if fewer than
// kMaxEscapedShare of the directions leave it: under an open sky most do, and the map's own table
// already draws where they go.
//
// Why a guess is safe: portals are one technique among others (EnvironmentLight::sample: under
// MIS the BSDF samples cover what they miss, else the table in a one-sample mixture), so a
// rectangle too large, too small or misplaced changes the variance, never the mean.
// The search uses a fixed seed and the full frame (not the crop, not the render's seed), so every
// render of a scene, and every crop of a frame, gets the same openings.

#include <cstdint>
#include <vector>

#include "acdf/envmap/environment_light.h"
#include "acdf/integrator/camera.h"
#include "acdf/integrator/geometry.h"

namespace acdf {

// Above this share of escaping directions the scene is open and no opening is used.
inline constexpr double kMaxEscapedShare = 0.25;

struct OpeningSearch {
  uint32_t points = 0;   // surface points the camera sees, traced from
  uint64_t rays = 0;     // directions traced from them
  uint64_t escaped = 0;  // of those, the ones that hit nothing
  // The openings found, largest (by escaping directions) first, at most PortalsSeen::kCapacity;
  // empty when the scene is open (escaped ≥ kMaxEscapedShare × rays) or nothing escapes.
  std::vector<Portal> openings;

  double escapedShare() const { return rays > 0 ? static_cast<double>(escaped) / static_cast<double>(rays) : 0.0; }
};

OpeningSearch findOpenings(const Geometry& geometry, const Camera& camera);

}  // namespace acdf

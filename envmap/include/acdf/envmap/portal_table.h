#pragma once
// The map as seen through one portal (Bitterli et al. 2015, "Portal-masked environment map
// sampling"; pbrt-v4's PortalImageInfiniteLight): the directions that leave the room through the
// portal's plane, parametrized by the unit square so that from any point on the room's side the
// portal covers an axis-aligned window of it, and the map's light over that square in an adaptive
// WindowedTable2D. A sample from a point is the table's sample in its window: a direction through
// the portal with density proportional to the map's luminance there, where a direction uniform in
// the portal's solid angle (SphericalRectangle) would miss a sun seen through a window.
//
// The square. In the portal's frame (ê_u, ê_v along its edges, n̂ = ê_u × ê_v into the room) a
// direction d leaving the room has d_n = −d · n̂ > 0 and
//   a = (1 + s) / 2,  s = d_u / √(d_u² + d_n²),     b = (1 + t) / 2,  t = d_v / √(d_v² + d_n²),
// the sines of its angles from −n̂ in the planes (ê_u, n̂) and (ê_v, n̂) (pbrt-v4 keeps the angles;
// their sines need no atan). Both depend on d_u / d_n and d_v / d_n alone, and from a point p with
// h = (p − corner) · n̂ > 0 the portal's points have d_n = h and d_u, d_v spanning
// [(corner − p) · ê_u, that + |edgeU|] and the same along ê_v: an axis-aligned window.
// Solid angle per unit of the square, for unit d:
//   dω / (da db) = 4 (d_u² + d_n²)^{3/2} (d_v² + d_n²)^{3/2} / d_n³
// (4 at the middle, growing towards the square's corners only, integrably). The table's function
// is the map's luminance times that Jacobian, so a window's mass is ∫ luminance dω through it.

#include <optional>

#include "acdf/envmap/environment_map.h"
#include "acdf/sampling/simplify.h"
#include "acdf/sampling/sphere.h"
#include "acdf/sampling/transform.h"
#include "acdf/sampling/windowed_table_2d.h"

namespace acdf {

struct Portal;

class PortalTable {
 public:
  // The portal's table of `map` placed by worldFromMap (the light's placement), on a square of
  // fine cells as fine as the map's pixels at the portal's normal, simplified by `options`.
  PortalTable(const Portal& portal, const EnvironmentMap& map, const Rotation& worldFromMap,
              const SimplifyOptions& options);

  // What the portal shows from a point: its window of the square, and the luminance through it.
  struct View {
    WindowedTable2D::Window window{};
    double power = 0;  // mass(window); 0 when the portal is not sampled from there
  };
  // From `position` (world frame). power is 0 behind the portal (or in its plane), and where the
  // window holds less than kMinShare of the light through the whole plane: the summed-area
  // table's differences have no correct digit left there.
  View viewFrom(const Vec3d& position) const;
  // The window alone: the square's directions that leave from `position` through the portal's
  // rectangle; none behind the portal or in its plane.
  std::optional<WindowedTable2D::Window> windowFrom(const Vec3d& position) const;
  static constexpr double kMinShare = 1e-12;

  // A world direction through the view's window with density ∝ luminance; its density per
  // steradian is density(w) / view.power (the caller finds it again from the direction).
  Vec3d sample(const View& view, double u0, double u1) const;
  // The table's function per steradian at the world direction w (unit): luminance-like, 0 for a
  // direction not leaving through the plane or outside `window`.
  double densityThrough(const WindowedTable2D::Window& window, const Vec3d& w) const;

  const WindowedTable2D& table() const { return table_; }
  // The frame: ê_u, ê_v, n̂ and the corner (the arrays a sampler written elsewhere needs).
  const Vec3d& corner() const { return corner_; }
  const Vec3d& axisU() const { return axisU_; }
  const Vec3d& axisV() const { return axisV_; }
  const Vec3d& normal() const { return normal_; }
  double lengthU() const { return lengthU_; }
  double lengthV() const { return lengthV_; }
  // The least power a view is sampled with (kMinShare of the whole square's).
  double minPower() const { return minPower_; }

 private:
  // The square's (a, b) of a unit world direction and its Jacobian, or none if it does not leave.
  struct Coordinates {
    double a, b, jacobian;
  };
  std::optional<Coordinates> coordinatesOf(const Vec3d& w) const;
  Vec3d directionAt(double a, double b) const;
  static WindowedTable2D build(const PortalTable& frame, const EnvironmentMap& map, const Rotation& worldFromMap,
                               const SimplifyOptions& options);

  Vec3d corner_, axisU_, axisV_, normal_;
  double lengthU_, lengthV_;
  WindowedTable2D table_;
  double minPower_;  // kMinShare of the whole square's mass
};

}  // namespace acdf

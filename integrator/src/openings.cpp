#include "acdf/integrator/openings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>

#include <tbb/parallel_for.h>

#include "acdf/sampling/frame.h"
#include "acdf/sampling/rng.h"

namespace acdf {

namespace {

// 48 × 36 points × 32 directions a round: about 57k rays (20–40 ms on 2 cores). Rounds go on
// until kEnoughEscapes directions escaped (a door ajar lets out 0.2 % of them) or kMaxRounds.
constexpr uint32_t kPointColumns = 48, kPointRows = 36;
constexpr uint32_t kDirectionRows = 4, kDirectionColumns = 8;  // stratified, jittered
constexpr uint32_t kMaxRounds = 8;
constexpr uint64_t kEnoughEscapes = 1000;
// A face's grid has about this many crossings per cell (at most 32 cells a side): coarse enough
// that the crossings of one opening connect, fine enough to part two windows of one wall.
constexpr double kCrossingsPerCell = 4;
constexpr uint32_t kMaxFaceCells = 32;
// An opening that lets out less than this share of the escaping directions is left to the other
// techniques (BSDF samples under MIS, else the table):
// behind the door ajar, the strip under its gap (15 % of them) raised the variance per sample
// from 2.8 to 3.8 beside the gap's own portal.
constexpr double kMinOpeningShare = 0.2;
constexpr uint64_t kSeed = 0x6f70656e696e6773ULL;

double& component(Vec3d& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
double component(const Vec3d& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }
Vec3d unitAxis(int axis) { return {axis == 0 ? 1.0 : 0.0, axis == 1 ? 1.0 : 0.0, axis == 2 ? 1.0 : 0.0}; }

struct Box {
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3d hi = lo * -1.0;
  void add(const Vec3d& p) {
    for (int a = 0; a < 3; ++a) {
      component(lo, a) = std::min(component(lo, a), component(p, a));
      component(hi, a) = std::max(component(hi, a), component(p, a));
    }
  }
  void add(const Box& b) {
    if (b.lo.x <= b.hi.x) add(b.lo), add(b.hi);
  }
};

struct Escape {
  Vec3d origin, direction;
};

// What one row of points traced in one round: the box of its hits and its escaping directions.
struct RowTrace {
  uint64_t rays = 0;
  Box box;
  std::vector<Escape> escapes;
};

// The surface points one row of the grid of camera rays sees.
std::vector<SurfaceHit> pointsOfRow(const Geometry& geometry, const Camera& camera, uint32_t row) {
  std::vector<SurfaceHit> points;
  Pcg32 rng(kSeed, row);
  for (uint32_t column = 0; column < kPointColumns; ++column) {
    const double x = (column + rng.nextDouble()) / kPointColumns * camera.width();
    const double y = (row + rng.nextDouble()) / kPointRows * camera.height();
    if (const std::optional<SurfaceHit> seen = geometry.intersect(camera.generateRay(x, y))) points.push_back(*seen);
  }
  return points;
}

RowTrace traceRow(const Geometry& geometry, const std::vector<SurfaceHit>& points, uint64_t stream) {
  RowTrace trace;
  Pcg32 rng(kSeed, stream);
  for (const SurfaceHit& seen : points) {
    trace.box.add(seen.position);
    const Frame frame(seen.normal);
    for (uint32_t i = 0; i < kDirectionRows; ++i)
      for (uint32_t j = 0; j < kDirectionColumns; ++j) {
        const Vec3d local = sampleCosineHemisphere((i + rng.nextDouble()) / kDirectionRows,
                                                   (j + rng.nextDouble()) / kDirectionColumns);
        const Vec3d direction = frame.toWorld(local);
        const Ray ray{Geometry::offsetOrigin(seen, direction), direction};
        ++trace.rays;
        if (const std::optional<SurfaceHit> hit = geometry.intersect(ray))
          trace.box.add(hit->position);
        else
          trace.escapes.push_back({ray.origin, direction});
      }
  }
  return trace;
}

// The bounds of crossings in a face's plane, and how many.
struct Rectangle {
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  uint64_t crossings = 0;

  void add(const std::array<double, 2>& p) {
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    ++crossings;
  }
  double area() const { return (hi[0] - lo[0]) * (hi[1] - lo[1]); }
};

// The face of the box an escaping direction leaves it through: 2 × axis, + 1 on the axis's high
// side. Its origin is inside the box.
std::optional<int> faceLeft(const Box& box, const Escape& e) {
  std::optional<int> face;
  double tExit = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    const double d = component(e.direction, a);
    if (d == 0) continue;
    const int side = d > 0 ? 1 : 0;
    const double t = std::max(0.0, (component(side ? box.hi : box.lo, a) - component(e.origin, a)) / d);
    if (t < tExit) tExit = t, face = 2 * a + side;
  }
  return face;
}

// Where an escaping direction crosses the plane at `level` on `axis`, in the plane's coordinates
// (the other two axes in order); none if its origin is not on the inner side (`side` 1: below).
std::optional<std::array<double, 2>> crossing(const Escape& e, int axis, int side, double level) {
  const double o = component(e.origin, axis), d = component(e.direction, axis);
  if (!(side ? o < level && d > 0 : o > level && d < 0)) return std::nullopt;
  const Vec3d p = e.origin + e.direction * ((level - o) / d);
  return std::array<double, 2>{component(p, (axis + 1) % 3), component(p, (axis + 2) % 3)};
}

// The plane parallel to a face, at most kPlaneDepth of the box's depth inside it, where the
// directions leaving through the face pass in the smallest rectangle, as long as it is in front of
// 95 % of their origins: an opening set back from the box's face (a door ajar swings out beyond
// its wall) is met where it is, not where its light has spread. Then one step further in: a
// portal a hair outside its wall would have the wall's sunlit outer face on its inner side, and
// points there would draw their light samples through it edge-on (measured: 1.5× the variance
// behind the door ajar).
constexpr double kPlaneDepth = 0.1;
constexpr int kPlaneSteps = 32;

double planeOf(const std::vector<const Escape*>& leaving, int axis, int side, const Box& box) {
  const double face = component(side ? box.hi : box.lo, axis);
  const double depth = kPlaneDepth * (component(box.hi, axis) - component(box.lo, axis));
  const auto levelAt = [&](int k) { return face + (side ? -depth : depth) * k / kPlaneSteps; };
  int best = 0, deepest = 0;
  double bestArea = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kPlaneSteps; ++k) {
    Rectangle inFront;
    for (const Escape* e : leaving)
      if (const auto p = crossing(*e, axis, side, levelAt(k))) inFront.add(*p);
    if (static_cast<double>(inFront.crossings) < 0.95 * static_cast<double>(leaving.size())) break;
    deepest = k;
    if (inFront.area() < bestArea) best = k, bestArea = inFront.area();
  }
  return levelAt(std::min(best + 1, deepest));
}

// The connected regions (8-neighbours) of a face's grid cells that crossings fell in, each with
// the bounding rectangle of its crossings (face coordinates: the face's other two axes, in order).
std::vector<Rectangle> regionsOf(const std::vector<std::array<double, 2>>& points, const double lo[2],
                              const double hi[2]) {
  const uint32_t cells = std::clamp(
      static_cast<uint32_t>(std::sqrt(static_cast<double>(points.size()) / kCrossingsPerCell)), 1u, kMaxFaceCells);
  auto cellOf = [&](const std::array<double, 2>& p, int k) {
    const double extent = hi[k] - lo[k];
    if (!(extent > 0)) return 0u;
    return std::min(cells - 1, static_cast<uint32_t>(std::max(0.0, (p[k] - lo[k]) / extent * cells)));
  };
  std::vector<int> label(cells * cells, -1);  // -1 empty, -2 occupied, else the region
  std::vector<uint32_t> cellOfPoint(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    cellOfPoint[i] = cellOf(points[i], 0) * cells + cellOf(points[i], 1);
    label[cellOfPoint[i]] = -2;
  }
  int regions = 0;
  std::vector<uint32_t> stack;
  for (uint32_t start = 0; start < label.size(); ++start) {
    if (label[start] != -2) continue;
    label[start] = regions;
    stack.assign(1, start);
    while (!stack.empty()) {
      const uint32_t cell = stack.back();
      stack.pop_back();
      const int r = static_cast<int>(cell / cells), s = static_cast<int>(cell % cells);
      for (int dr = -1; dr <= 1; ++dr)
        for (int ds = -1; ds <= 1; ++ds) {
          const int nr = r + dr, ns = s + ds;
          if (nr < 0 || ns < 0 || nr >= static_cast<int>(cells) || ns >= static_cast<int>(cells)) continue;
          const uint32_t next = static_cast<uint32_t>(nr) * cells + static_cast<uint32_t>(ns);
          if (label[next] == -2) label[next] = regions, stack.push_back(next);
        }
    }
    ++regions;
  }
  std::vector<Rectangle> found(static_cast<std::size_t>(regions));
  for (std::size_t i = 0; i < points.size(); ++i) found[static_cast<std::size_t>(label[cellOfPoint[i]])].add(points[i]);
  return found;
}

}  // namespace

OpeningSearch findOpenings(const Geometry& geometry, const Camera& camera) {
  std::vector<std::vector<SurfaceHit>> points(kPointRows);
  tbb::parallel_for(uint32_t{0}, kPointRows,
                    [&](uint32_t row) { points[row] = pointsOfRow(geometry, camera, row); });
  OpeningSearch search;
  for (const auto& row : points) search.points += static_cast<uint32_t>(row.size());

  Box box;
  std::vector<Escape> escapes;
  std::vector<RowTrace> rows(kPointRows);
  for (uint32_t round = 0; round < kMaxRounds; ++round) {
    tbb::parallel_for(uint32_t{0}, kPointRows, [&](uint32_t row) {
      rows[row] = traceRow(geometry, points[row], uint64_t{round} * kPointRows + row + kPointRows);
    });
    for (const RowTrace& row : rows) {
      search.rays += row.rays;
      box.add(row.box);
      escapes.insert(escapes.end(), row.escapes.begin(), row.escapes.end());
    }
    search.escaped = escapes.size();
    if (search.rays == 0 || escapes.size() >= kEnoughEscapes || search.escapedShare() >= kMaxEscapedShare) break;
  }
  if (escapes.empty() || search.escapedShare() >= kMaxEscapedShare) return search;

  std::array<std::vector<const Escape*>, 6> leaving;
  for (const Escape& e : escapes)
    if (const std::optional<int> face = faceLeft(box, e)) leaving[static_cast<std::size_t>(*face)].push_back(&e);

  struct Found {
    Portal portal;
    uint64_t crossings;
  };
  std::vector<Found> found;
  for (int face = 0; face < 6; ++face) {
    const auto& through = leaving[static_cast<std::size_t>(face)];
    if (through.empty()) continue;
    const int axis = face / 2, side = face % 2;
    const int axes[2] = {(axis + 1) % 3, (axis + 2) % 3};
    const double lo[2] = {component(box.lo, axes[0]), component(box.lo, axes[1])};
    const double hi[2] = {component(box.hi, axes[0]), component(box.hi, axes[1])};
    const double level = planeOf(through, axis, side, box);
    std::vector<std::array<double, 2>> points;
    for (const Escape* e : through)
      if (const auto p = crossing(*e, axis, side, level)) points.push_back(*p);
    for (const Rectangle& region : regionsOf(points, lo, hi)) {
      if (static_cast<double>(region.crossings) < kMinOpeningShare * static_cast<double>(escapes.size())) continue;
      // A margin for the edges the crossings fall short of: about the gap n uniform points leave
      // at each end, and at least a thousandth of the face.
      Vec3d corner, edges[2];
      component(corner, axis) = level;
      for (int k = 0; k < 2; ++k) {
        const double margin =
            2.0 * (region.hi[k] - region.lo[k]) / static_cast<double>(region.crossings) + 1e-3 * (hi[k] - lo[k]);
        const double from = std::max(lo[k], region.lo[k] - margin), to = std::min(hi[k], region.hi[k] + margin);
        component(corner, axes[k]) = from;
        edges[k] = unitAxis(axes[k]) * (to - from);
      }
      // Light passes into the box: edge_u × edge_v points inwards.
      const Vec3d inwards = unitAxis(axis) * (side ? -1.0 : 1.0);
      Portal portal{corner, edges[0], edges[1]};
      if (dot(cross(portal.edgeU, portal.edgeV), inwards) < 0) std::swap(portal.edgeU, portal.edgeV);
      if (!portalProblem(portal)) found.push_back({portal, region.crossings});
    }
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const Found& a, const Found& b) { return a.crossings > b.crossings; });
  if (found.size() > PortalsSeen::kCapacity) found.resize(PortalsSeen::kCapacity);
  for (const Found& f : found) search.openings.push_back(f.portal);
  return search;
}

}  // namespace acdf

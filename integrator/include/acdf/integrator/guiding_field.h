#pragma once
// Path guiding's learned radiance field (Müller, Gross & Novák 2017, "Practical Path Guiding"): a
// spatial binary tree over the points paths visited, and in each of its leaves a distribution of
// directions proportional to the radiance that arrived there, learned from the paths of a
// previous pass.
//
// Directions. The sphere is mapped to the unit square by the cylindrical equal-area map
//   (s, t) = ((cos θ + 1) / 2, φ / 2π)        (θ from world +z, φ from +x towards +y),
// whose area element is dω = 4π ds dt, so a density on the square is one on the sphere over 4π.
//
// A leaf's distribution. Each record of a path vertex that fell in the leaf carries the radiance
// estimate L̂ that arrived along the direction the path took and that direction's density p; its
// energy L̂ / p, summed over the records in a cell of the square, is an unbiased estimate (up to one
// factor common to the leaf) of the radiance integrated over the cell's directions, whatever
// distribution the directions came from. A quadtree over the square splits every node holding
// more than `splitEnergy` of the leaf's energy (and at least `minRecordsToSplit` records), down to
// `maxDirectionalDepth`. Its leaves, numbered in depth-first order, form one piecewise-constant 1D
// distribution of the library (PiecewiseConstant1D over [0, leaves), a unit cell per quadtree leaf
// with the leaf's energy): sample() inverts it with u0, whose position inside the chosen unit cell
// and u1 then place the point uniformly in the quadtree leaf's square. So
//   p(ω) = P(leaf) / area(leaf) / 4π,
// where P is the 1D distribution's cell probability, which pdf() finds again by descending the
// quadtree. Cells no record reached have density 0: the field is only ever sampled in a mixture
// with the BSDF, which covers every direction the BSDF reflects into.
//
// The spatial trees. Radiance learned on one side of a surface says little about the other, and a
// leaf that mixed a floor with a wall would send the floor's paths into the wall's half of the
// sphere, below the floor. So each record carries its surface normal's bucket (the normal's
// largest axis and its sign, normalBucket()) and every bucket has its own tree. In each, records
// are split at the midpoint of their box's longest axis until a node
// holds at most `maxRecordsPerLeaf` records (or reaches kMaxSpatialDepth). A point outside the box
// of the records still finds a leaf (the closest along each split). A leaf whose records carry no
// energy has no distribution.
//
// Deterministic: the field depends only on the records and their order, and is built in parallel
// over the spatial leaves, each from its own records.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/sphere.h"

namespace acdf {

// What one path vertex learned: where it was, the direction it continued along, and the energy
// L̂ / p of that direction (luminance of the incident radiance estimate over its density).
struct GuidingRecord {
  float position[3];
  float s, t;  // the direction on the equal-area square
  float energy;
  uint8_t normalBucket;  // normalBucket() of the surface normal there
};

// Which of the six normal buckets a (nonzero) surface normal falls in: 2 · axis + (component < 0).
uint8_t normalBucket(const Vec3d& normal);
// The record of a point with surface normal `normal` that learned `energy` along unit `direction`.
GuidingRecord guidingRecord(const Vec3d& position, const Vec3d& normal, const Vec3d& direction, double energy);

// The equal-area square of a unit direction, and back.
std::array<double, 2> equalAreaSquare(const Vec3d& direction);
Vec3d equalAreaDirection(double s, double t);

struct GuidingFieldOptions {
  std::size_t maxRecordsPerLeaf = 4000;
  double splitEnergy = 0.01;  // a quadtree node's share of its spatial leaf's energy above which it splits
  uint32_t maxDirectionalDepth = 10;
  uint32_t minRecordsToSplit = 32;
};

// A distribution of directions over the whole sphere (world frame), one spatial leaf's.
class DirectionalDistribution {
 public:
  // The records' directions and energies (reordered); their total energy must be positive and finite.
  DirectionalDistribution(std::span<GuidingRecord> records, const GuidingFieldOptions& options);

  struct DirectionAndPdf {
    Vec3d direction;  // unit
    double pdf = 0;   // per steradian, > 0
  };
  // u0, u1 in [0, 1).
  DirectionAndPdf sample(float u0, float u1) const;
  double pdf(const Vec3d& direction) const;

  std::size_t leaves() const { return leafCells_.size(); }
  std::size_t bytes() const;

 private:
  struct Node {
    // Children (0 = none: a leaf) in the order (s low, t low), (s high, t low), (s low, t high),
    // (s high, t high); a leaf's index among the leaves.
    uint32_t child[4] = {0, 0, 0, 0};
    uint32_t leaf = 0;
  };
  struct Square {
    double s0, t0, size;
  };
  uint32_t build(std::span<GuidingRecord> records, Square square, uint32_t depth, double total,
                 const GuidingFieldOptions& options, std::vector<float>& energies);
  // The leaf holding (s, t).
  uint32_t leafAt(double s, double t) const;

  std::vector<Node> nodes_;
  std::vector<Square> leafCells_;
  std::vector<double> leafDensities_;  // per steradian
  std::optional<PiecewiseConstant1D> leafDistribution_;
};

class GuidingField {
 public:
  // Throws std::invalid_argument for a record whose normal bucket is not one of normalBucket()'s.
  GuidingField(std::vector<GuidingRecord> records, const GuidingFieldOptions& options = {});

  // The distribution of the spatial leaf holding `position` in the tree of `normal`'s bucket; none
  // where that leaf learned nothing.
  const DirectionalDistribution* at(const Vec3d& position, const Vec3d& normal) const;

  std::size_t spatialLeaves() const { return leaves_.size(); }
  std::size_t bytes() const;

  static constexpr uint32_t kMaxSpatialDepth = 40;

 private:
  struct Node {
    uint32_t child[2] = {0, 0};  // both 0: a leaf
    uint8_t axis = 0;
    float split = 0;
    uint32_t leaf = 0;  // index into leaves_
  };
  struct Box {
    float lo[3], hi[3];
  };
  uint32_t build(std::span<GuidingRecord> records, Box box, uint32_t depth, std::size_t maxRecords,
                 std::vector<std::span<GuidingRecord>>& leafRecords);

  static constexpr uint32_t kNoTree = ~0u;
  static constexpr std::size_t kBuckets = 6;
  std::array<uint32_t, kBuckets> roots_;  // per normal bucket; kNoTree without records
  std::vector<Node> nodes_;
  std::vector<std::optional<DirectionalDistribution>> leaves_;
};

}  // namespace acdf

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
// Storage. A guided vertex looks up its spatial leaf and then samples and evaluates that leaf's
// distribution, so all of them sit in shared arrays (DirectionalDistributions) rather than each in
// its own heap blocks: a spatial node takes 16 bytes with its children adjacent, a quadtree's inner
// node holds its four children's entries, a cell (16 bytes) its square as integers (exact: dyadic,
// at most kMaxDirectionalDepth bits) beside its density, and the 1D CDFs follow one another.
//
// Deterministic: the field depends only on the records and their order, and is built in parallel
// over the spatial leaves, each from its own records.

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "acdf/sampling/grid_axis.h"
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

class DirectionalDistributions;

// A distribution of directions over the whole sphere (world frame), one spatial leaf's: a view of
// its part of the DirectionalDistributions that hold it. A default one is none (false).
class DirectionalDistribution {
 public:
  DirectionalDistribution() = default;
  explicit operator bool() const { return parts_ != nullptr; }

  struct DirectionAndPdf {
    Vec3d direction;  // unit
    double pdf = 0;   // per steradian, > 0
  };
  // u0, u1 in [0, 1).
  DirectionAndPdf sample(float u0, float u1) const;
  double pdf(const Vec3d& direction) const;

  std::size_t leaves() const { return parts_->axis.cells(); }

 private:
  friend class DirectionalDistributions;
  // Where the distribution sits in its DirectionalDistributions, and the axis its CDF is over.
  struct Parts {
    uint32_t firstNode, firstCell, firstCdf;  // the root, when there are inner nodes, is the first
    GridAxis axis;                            // a unit cell per quadtree leaf
  };
  DirectionalDistribution(const DirectionalDistributions& all, const Parts& parts) : all_(&all), parts_(&parts) {}

  const DirectionalDistributions* all_ = nullptr;
  const Parts* parts_ = nullptr;
};

// Many directional distributions in shared arrays, so that a guided sample reads a few adjacent
// cache lines, not a scatter of per-leaf heap blocks: the quadtrees' inner nodes, their leaves'
// cells and the 1D CDFs over the cells, each distribution a contiguous range of each.
class DirectionalDistributions {
 public:
  // One distribution per record set, built in parallel; each set's records are reordered, and
  // their total energy must be positive and finite. Throws std::invalid_argument when it is not or
  // when options.maxDirectionalDepth exceeds kMaxDirectionalDepth.
  DirectionalDistributions(std::span<const std::span<GuidingRecord>> recordSets, const GuidingFieldOptions& options);

  DirectionalDistribution operator[](std::size_t set) const { return {*this, parts_[set]}; }
  std::size_t bytes() const;

  // Deep enough for any use, shallow enough that a cell's corner takes 24 bits.
  static constexpr uint32_t kMaxDirectionalDepth = 24;

 private:
  friend class DirectionalDistribution;
  struct Built;
  // An inner node of a quadtree. Children in the order (s low, t low), (s high, t low),
  // (s low, t high), (s high, t high); each an inner node's index, or kCell plus a cell's index,
  // both counted from the distribution's first.
  struct QuadNode {
    uint32_t child[4];
  };
  static constexpr uint32_t kCell = 1u << 31;
  // A quadtree leaf: its density and its square [s0, s0 + size) × [t0, t0 + size), corner and size
  // exact, being dyadic: the corner in units of 2^-kMaxDirectionalDepth, the size 2^-depth. 16
  // bytes rather than 24 with float corners: the cells are most of the field.
  struct Cell {
    double density;  // per steradian
    uint32_t s0 : 24, depth : 8;
    uint32_t t0;
    // 2^-depth from its exponent bits: no libm call on the sampling path.
    double size() const { return std::bit_cast<double>(static_cast<uint64_t>(1023 - depth) << 52); }
  };
  static constexpr double kCellUnit = 1.0 / (1u << kMaxDirectionalDepth);

  std::vector<DirectionalDistribution::Parts> parts_;  // per distribution
  std::vector<QuadNode> nodes_;
  std::vector<Cell> cells_;
  std::vector<float> cdfs_;  // each distribution's cells + 1 values, as PiecewiseConstant1D::cdf()
};

class GuidingField {
 public:
  // Throws std::invalid_argument for a record whose normal bucket is not one of normalBucket()'s.
  GuidingField(std::vector<GuidingRecord> records, const GuidingFieldOptions& options = {});

  // The distribution of the spatial leaf holding `position` in the tree of `normal`'s bucket; none
  // where that leaf learned nothing.
  DirectionalDistribution at(const Vec3d& position, const Vec3d& normal) const;

  std::size_t spatialLeaves() const { return spatialLeaves_; }
  std::size_t bytes() const;

  static constexpr uint32_t kMaxSpatialDepth = 40;

 private:
  // An inner node splits `axis` at `split`, its children adjacent from `index` (below the split
  // first); a leaf's `index` is its distribution's, kNoDistribution where it learned nothing. The
  // split is kept as a double, as the positions compared with it are: a float would cost a
  // conversion on each level of the descent's dependency chain.
  struct Node {
    double split = 0;
    uint32_t axisAndIndex = kLeaf;  // the axis in the low 2 bits (kLeaf for a leaf), the index above
    uint32_t axis() const { return axisAndIndex & 3; }
    uint32_t index() const { return axisAndIndex >> 2; }
    static Node leaf(uint32_t index) { return {0, index << 2 | kLeaf}; }
  };
  static constexpr uint32_t kLeaf = 3;
  static constexpr uint32_t kNoDistribution = (1u << 30) - 1;
  struct Box {
    float lo[3], hi[3];
  };
  void build(uint32_t node, std::span<GuidingRecord> records, Box box, uint32_t depth, std::size_t maxRecords,
             std::vector<std::span<GuidingRecord>>& leafRecords);

  static constexpr uint32_t kNoTree = ~0u;
  static constexpr std::size_t kBuckets = 6;
  std::array<uint32_t, kBuckets> roots_;  // per normal bucket; kNoTree without records
  std::vector<Node> nodes_;
  std::size_t spatialLeaves_ = 0;
  std::optional<DirectionalDistributions> distributions_;
};

}  // namespace acdf

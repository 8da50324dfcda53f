#include "acdf/integrator/guiding_field.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "acdf/sampling/piecewise_constant_1d.h"

namespace acdf {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kFourPi = 4.0 * std::numbers::pi;

// The largest double below 1: a coordinate of the square is in [0, 1).
double belowOne(double x) { return std::min(x, 0x1.fffffffffffffp-1); }

double energyOf(std::span<const GuidingRecord> records) {
  double energy = 0;
  for (const GuidingRecord& r : records) energy += r.energy;
  return energy;
}
}  // namespace

std::array<double, 2> equalAreaSquare(const Vec3d& direction) {
  const double s = (std::clamp(direction.z, -1.0, 1.0) + 1.0) * 0.5;
  return {belowOne(std::max(0.0, s)), belowOne(azimuth(direction) / kTwoPi)};
}

Vec3d equalAreaDirection(double s, double t) {
  const double cosTheta = std::clamp(2.0 * s - 1.0, -1.0, 1.0);
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  const double phi = kTwoPi * t;
  return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

uint8_t normalBucket(const Vec3d& normal) {
  const double a[3] = {std::abs(normal.x), std::abs(normal.y), std::abs(normal.z)};
  const int axis = a[0] >= a[1] && a[0] >= a[2] ? 0 : a[1] >= a[2] ? 1 : 2;
  const double component = axis == 0 ? normal.x : axis == 1 ? normal.y : normal.z;
  return static_cast<uint8_t>(2 * axis + (component < 0 ? 1 : 0));
}

GuidingRecord guidingRecord(const Vec3d& position, const Vec3d& normal, const Vec3d& direction, double energy) {
  const auto [s, t] = equalAreaSquare(direction);
  return {{static_cast<float>(position.x), static_cast<float>(position.y), static_cast<float>(position.z)},
          static_cast<float>(s),
          static_cast<float>(t),
          static_cast<float>(energy),
          normalBucket(normal)};
}

// ---- DirectionalDistributions ----

// One distribution built alone (in parallel with the others), before it joins the shared arrays:
// its quadtree's inner nodes and its cells in depth-first order, the first node the root.
struct DirectionalDistributions::Built {
  std::vector<QuadNode> nodes;
  std::vector<Cell> cells;
  std::vector<float> energies;  // per cell, a share of the total
  std::optional<PiecewiseConstant1D> cellDistribution;

  Built(std::span<GuidingRecord> records, const GuidingFieldOptions& options) {
    const double total = energyOf(records);
    if (!(total > 0) || !std::isfinite(total))
      throw std::invalid_argument("a directional distribution needs a positive, finite total energy");
    nodes.reserve(64);
    build(records, 0, 0, 1, 0, total, options);
    cellDistribution.emplace(energies, 0.0f, static_cast<float>(energies.size()));
    // Each cell's density, found once: sample() and pdf() read the same value.
    for (std::size_t cell = 0; cell < cells.size(); ++cell) {
      const double size = cells[cell].size();
      cells[cell].density = cellDistribution->pdf(static_cast<float>(cell) + 0.5f) / (size * size) / kFourPi;
    }
  }

  // The entry for the node over the square [s0, s0 + size) × [t0, t0 + size): kCell plus a cell's
  // index, or an inner node's.
  uint32_t build(std::span<GuidingRecord> records, double s0, double t0, double size, uint32_t depth, double total,
                 const GuidingFieldOptions& options) {
    const double energy = energyOf(records);
    if (depth >= options.maxDirectionalDepth || records.size() < options.minRecordsToSplit ||
        !(energy > options.splitEnergy * total)) {
      cells.push_back({0, static_cast<uint32_t>(s0 / kCellUnit), depth, static_cast<uint32_t>(t0 / kCellUnit)});
      energies.push_back(static_cast<float>(energy / total));
      return kCell | static_cast<uint32_t>(cells.size() - 1);
    }
    const auto index = static_cast<uint32_t>(nodes.size());
    nodes.emplace_back();
    const double half = size * 0.5, sMid = s0 + half, tMid = t0 + half;
    // Partition into the four quadrants in child order: first by t, then each half by s.
    const auto highT =
        std::partition(records.begin(), records.end(), [&](const GuidingRecord& r) { return r.t < tMid; });
    const auto lowTHighS = std::partition(records.begin(), highT, [&](const GuidingRecord& r) { return r.s < sMid; });
    const auto highTHighS = std::partition(highT, records.end(), [&](const GuidingRecord& r) { return r.s < sMid; });
    const std::span<GuidingRecord> parts[4] = {{records.begin(), lowTHighS},
                                               {lowTHighS, highT},
                                               {highT, highTHighS},
                                               {highTHighS, records.end()}};
    const double corners[4][2] = {{s0, t0}, {sMid, t0}, {s0, tMid}, {sMid, tMid}};
    for (int c = 0; c < 4; ++c) {
      const uint32_t child = build(parts[c], corners[c][0], corners[c][1], half, depth + 1, total, options);
      nodes[index].child[c] = child;
    }
    return index;
  }
};

DirectionalDistributions::DirectionalDistributions(std::span<const std::span<GuidingRecord>> recordSets,
                                                   const GuidingFieldOptions& options) {
  if (options.maxDirectionalDepth > kMaxDirectionalDepth)
    throw std::invalid_argument("the directional quadtrees' depth is at most " + std::to_string(kMaxDirectionalDepth));
  std::vector<std::optional<Built>> built(recordSets.size());
  tbb::parallel_for(std::size_t{0}, recordSets.size(),
                    [&](std::size_t i) { built[i].emplace(recordSets[i], options); });
  parts_.reserve(built.size());
  for (std::optional<Built>& b : built) {
    parts_.push_back({static_cast<uint32_t>(nodes_.size()), static_cast<uint32_t>(cells_.size()),
                      static_cast<uint32_t>(cdfs_.size()), b->cellDistribution->axis()});
    nodes_.insert(nodes_.end(), b->nodes.begin(), b->nodes.end());
    cells_.insert(cells_.end(), b->cells.begin(), b->cells.end());
    const std::span<const float> cdf = b->cellDistribution->cdf();
    cdfs_.insert(cdfs_.end(), cdf.begin(), cdf.end());
    b.reset();
  }
}

std::size_t DirectionalDistributions::bytes() const {
  return parts_.size() * sizeof(parts_[0]) + nodes_.size() * sizeof(QuadNode) + cells_.size() * sizeof(Cell) +
         cdfs_.size() * sizeof(float);
}

// ---- DirectionalDistribution ----

DirectionalDistribution::DirectionAndPdf DirectionalDistribution::sample(float u0, float u1) const {
  const uint32_t cells = parts_->axis.cells();
  const Sample1D chosen =
      PiecewiseConstant1D::sample({all_->cdfs_.data() + parts_->firstCdf, cells + 1u}, parts_->axis, u0);
  const auto cell = std::min(static_cast<uint32_t>(chosen.x), cells - 1);
  const DirectionalDistributions::Cell& square = all_->cells_[parts_->firstCell + cell];
  // A point a hair inside the cell's square, so that the direction made from it (rounded) maps back
  // into the same cell for pdf(); the density this leaves out, 4e-7 of the cell's, is below the
  // table's float rounding.
  constexpr double kMargin = 1e-7;
  auto inside = [&](double f) { return kMargin + (1.0 - 2.0 * kMargin) * std::clamp(f, 0.0, 1.0); };
  constexpr double kUnit = DirectionalDistributions::kCellUnit;
  const double size = square.size();
  const double s = square.s0 * kUnit + size * inside(static_cast<double>(chosen.x) - cell);
  const double t = square.t0 * kUnit + size * inside(u1);
  return {equalAreaDirection(s, t), square.density};
}

double DirectionalDistribution::pdf(const Vec3d& direction) const {
  const auto [s, t] = equalAreaSquare(direction);
  const DirectionalDistributions::Cell* cells = all_->cells_.data() + parts_->firstCell;
  if (parts_->axis.cells() == 1) return cells[0].density;
  const DirectionalDistributions::QuadNode* nodes = all_->nodes_.data() + parts_->firstNode;
  uint32_t entry = 0;  // the root
  double s0 = 0, t0 = 0, half = 0.5;
  do {
    const bool highS = s >= s0 + half, highT = t >= t0 + half;
    entry = nodes[entry].child[(highT ? 2 : 0) + (highS ? 1 : 0)];
    s0 += highS ? half : 0;
    t0 += highT ? half : 0;
    half *= 0.5;
  } while (!(entry & DirectionalDistributions::kCell));
  return cells[entry & ~DirectionalDistributions::kCell].density;
}

// ---- GuidingField ----

GuidingField::GuidingField(std::vector<GuidingRecord> records, const GuidingFieldOptions& options) {
  roots_.fill(kNoTree);
  // Records grouped by bucket (a counting sort: each group in its original order), each group's box.
  std::array<std::size_t, kBuckets + 1> start{};
  std::array<Box, kBuckets> boxes;
  for (const GuidingRecord& r : records) {
    if (r.normalBucket >= kBuckets) throw std::invalid_argument("a guiding record's normal bucket is out of range");
    Box& box = boxes[r.normalBucket];
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = start[r.normalBucket + 1] == 0 ? r.position[a] : std::min(box.lo[a], r.position[a]);
      box.hi[a] = start[r.normalBucket + 1] == 0 ? r.position[a] : std::max(box.hi[a], r.position[a]);
    }
    ++start[r.normalBucket + 1];
  }
  for (std::size_t b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
  std::vector<GuidingRecord> grouped(records.size());
  std::array<std::size_t, kBuckets> next;
  std::copy(start.begin(), start.end() - 1, next.begin());
  for (const GuidingRecord& r : records) grouped[next[r.normalBucket]++] = r;
  records = {};
  std::vector<std::span<GuidingRecord>> leafRecords;
  for (std::size_t b = 0; b < kBuckets; ++b)
    if (start[b + 1] > start[b]) {
      roots_[b] = static_cast<uint32_t>(nodes_.size());
      nodes_.emplace_back();
      build(roots_[b], {grouped.begin() + start[b], grouped.begin() + start[b + 1]}, boxes[b], 0,
            std::max<std::size_t>(1, options.maxRecordsPerLeaf), leafRecords);
    }
  spatialLeaves_ = leafRecords.size();
  // The leaves that learned something get distributions, numbered in leaf order.
  std::vector<std::span<GuidingRecord>> learned;
  std::vector<uint32_t> distributionOf(leafRecords.size(), kNoDistribution);
  for (std::size_t i = 0; i < leafRecords.size(); ++i) {
    const double energy = energyOf(leafRecords[i]);
    if (energy > 0 && std::isfinite(energy)) {
      distributionOf[i] = static_cast<uint32_t>(learned.size());
      learned.push_back(leafRecords[i]);
    }
  }
  for (Node& node : nodes_)
    if (node.axis() == kLeaf) node = Node::leaf(distributionOf[node.index()]);
  distributions_.emplace(learned, options);
}

// Makes nodes_[node] the tree over `records` in `box`, its leaves' indices those of their records
// in `leafRecords`.
void GuidingField::build(uint32_t node, std::span<GuidingRecord> records, Box box, uint32_t depth,
                         std::size_t maxRecords, std::vector<std::span<GuidingRecord>>& leafRecords) {
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
  const float split = 0.5f * (box.lo[axis] + box.hi[axis]);
  if (records.size() <= maxRecords || depth >= kMaxSpatialDepth || !(split > box.lo[axis] && split < box.hi[axis])) {
    nodes_[node] = Node::leaf(static_cast<uint32_t>(leafRecords.size()));
    leafRecords.push_back(records);
    return;
  }
  const auto high = std::partition(records.begin(), records.end(),
                                   [&](const GuidingRecord& r) { return r.position[axis] < split; });
  Box low = box, upper = box;
  low.hi[axis] = split;
  upper.lo[axis] = split;
  const auto children = static_cast<uint32_t>(nodes_.size());
  nodes_.resize(nodes_.size() + 2);
  nodes_[node] = {split, children << 2 | static_cast<uint32_t>(axis)};
  build(children, {records.begin(), high}, low, depth + 1, maxRecords, leafRecords);
  build(children + 1, {high, records.end()}, upper, depth + 1, maxRecords, leafRecords);
}

DirectionalDistribution GuidingField::at(const Vec3d& position, const Vec3d& normal) const {
  uint32_t node = roots_[normalBucket(normal)];
  if (node == kNoTree) return {};
  const double p[3] = {position.x, position.y, position.z};
  Node n = nodes_[node];
  while (n.axis() != kLeaf) n = nodes_[n.index() + (p[n.axis()] < n.split ? 0 : 1)];
  const uint32_t index = n.index();
  return index == kNoDistribution ? DirectionalDistribution{} : (*distributions_)[index];
}

std::size_t GuidingField::bytes() const { return nodes_.size() * sizeof(Node) + distributions_->bytes(); }

}  // namespace acdf

#include "acdf/integrator/guiding_field.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace acdf {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kFourPi = 4.0 * std::numbers::pi;

// The largest double below 1: a coordinate of the square is in [0, 1).
double belowOne(double x) { return std::min(x, 0x1.fffffffffffffp-1); }
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

// ---- DirectionalDistribution ----

DirectionalDistribution::DirectionalDistribution(std::span<GuidingRecord> records,
                                                 const GuidingFieldOptions& options) {
  double total = 0;
  for (const GuidingRecord& r : records) total += r.energy;
  if (!(total > 0) || !std::isfinite(total))
    throw std::invalid_argument("a directional distribution needs a positive, finite total energy");
  std::vector<float> energies;
  nodes_.reserve(64);
  build(records, {0, 0, 1}, 0, total, options, energies);
  leafDistribution_.emplace(energies, 0.0f, static_cast<float>(energies.size()));
  // Each leaf's density, found once: sample() and pdf() read the same value.
  leafDensities_.reserve(leafCells_.size());
  for (std::size_t leaf = 0; leaf < leafCells_.size(); ++leaf) {
    const double size = leafCells_[leaf].size;
    leafDensities_.push_back(leafDistribution_->pdf(static_cast<float>(leaf) + 0.5f) / (size * size) / kFourPi);
  }
}

uint32_t DirectionalDistribution::build(std::span<GuidingRecord> records, Square square, uint32_t depth,
                                        double total, const GuidingFieldOptions& options,
                                        std::vector<float>& energies) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  double energy = 0;
  for (const GuidingRecord& r : records) energy += r.energy;
  if (depth >= options.maxDirectionalDepth || records.size() < options.minRecordsToSplit ||
      !(energy > options.splitEnergy * total)) {
    nodes_[index].leaf = static_cast<uint32_t>(leafCells_.size());
    leafCells_.push_back(square);
    energies.push_back(static_cast<float>(energy / total));
    return index;
  }
  const double half = square.size * 0.5, sMid = square.s0 + half, tMid = square.t0 + half;
  // Partition into the four quadrants in child order: first by t, then each half by s.
  const auto highT = std::partition(records.begin(), records.end(), [&](const GuidingRecord& r) { return r.t < tMid; });
  const auto lowTHighS = std::partition(records.begin(), highT, [&](const GuidingRecord& r) { return r.s < sMid; });
  const auto highTHighS = std::partition(highT, records.end(), [&](const GuidingRecord& r) { return r.s < sMid; });
  const std::span<GuidingRecord> parts[4] = {{records.begin(), lowTHighS},
                                             {lowTHighS, highT},
                                             {highT, highTHighS},
                                             {highTHighS, records.end()}};
  const Square squares[4] = {
      {square.s0, square.t0, half}, {sMid, square.t0, half}, {square.s0, tMid, half}, {sMid, tMid, half}};
  for (int c = 0; c < 4; ++c) {
    const uint32_t child = build(parts[c], squares[c], depth + 1, total, options, energies);
    nodes_[index].child[c] = child;
  }
  return index;
}

uint32_t DirectionalDistribution::leafAt(double s, double t) const {
  uint32_t node = 0;
  Square square{0, 0, 1};
  while (nodes_[node].child[0] != 0) {
    const double half = square.size * 0.5;
    const bool highS = s >= square.s0 + half, highT = t >= square.t0 + half;
    node = nodes_[node].child[(highT ? 2 : 0) + (highS ? 1 : 0)];
    square = {square.s0 + (highS ? half : 0), square.t0 + (highT ? half : 0), half};
  }
  return nodes_[node].leaf;
}

DirectionalDistribution::DirectionAndPdf DirectionalDistribution::sample(float u0, float u1) const {
  const Sample1D chosen = leafDistribution_->sample(u0);
  const auto leaf = std::min(static_cast<uint32_t>(chosen.x), static_cast<uint32_t>(leafCells_.size() - 1));
  const Square& square = leafCells_[leaf];
  // A point a hair inside the leaf's square, so that the direction made from it (rounded) maps back
  // into the same leaf for pdf(); the density this leaves out, 4e-7 of the leaf's, is below the
  // table's float rounding.
  constexpr double kMargin = 1e-7;
  auto inside = [&](double f) { return kMargin + (1.0 - 2.0 * kMargin) * std::clamp(f, 0.0, 1.0); };
  const double s = square.s0 + square.size * inside(static_cast<double>(chosen.x) - leaf);
  const double t = square.t0 + square.size * inside(u1);
  return {equalAreaDirection(s, t), leafDensities_[leaf]};
}

double DirectionalDistribution::pdf(const Vec3d& direction) const {
  const auto [s, t] = equalAreaSquare(direction);
  return leafDensities_[leafAt(s, t)];
}

std::size_t DirectionalDistribution::bytes() const {
  return nodes_.size() * sizeof(Node) + leafCells_.size() * sizeof(Square) + leafDensities_.size() * sizeof(double) +
         leafDistribution_->bytes();
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
    if (start[b + 1] > start[b])
      roots_[b] = build({grouped.begin() + start[b], grouped.begin() + start[b + 1]}, boxes[b], 0,
                        std::max<std::size_t>(1, options.maxRecordsPerLeaf), leafRecords);
  leaves_.resize(leafRecords.size());
  tbb::parallel_for(std::size_t{0}, leafRecords.size(), [&](std::size_t i) {
    double energy = 0;
    for (const GuidingRecord& r : leafRecords[i]) energy += r.energy;
    if (energy > 0 && std::isfinite(energy)) leaves_[i].emplace(leafRecords[i], options);
  });
}

uint32_t GuidingField::build(std::span<GuidingRecord> records, Box box, uint32_t depth, std::size_t maxRecords,
                             std::vector<std::span<GuidingRecord>>& leafRecords) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
  const float split = 0.5f * (box.lo[axis] + box.hi[axis]);
  if (records.size() <= maxRecords || depth >= kMaxSpatialDepth || !(split > box.lo[axis] && split < box.hi[axis])) {
    nodes_[index].leaf = static_cast<uint32_t>(leafRecords.size());
    leafRecords.push_back(records);
    return index;
  }
  const auto high = std::partition(records.begin(), records.end(),
                                   [&](const GuidingRecord& r) { return r.position[axis] < split; });
  Box low = box, upper = box;
  low.hi[axis] = split;
  upper.lo[axis] = split;
  nodes_[index].axis = static_cast<uint8_t>(axis);
  nodes_[index].split = split;
  const uint32_t lowChild = build({records.begin(), high}, low, depth + 1, maxRecords, leafRecords);
  const uint32_t highChild = build({high, records.end()}, upper, depth + 1, maxRecords, leafRecords);
  nodes_[index].child[0] = lowChild;
  nodes_[index].child[1] = highChild;
  return index;
}

const DirectionalDistribution* GuidingField::at(const Vec3d& position, const Vec3d& normal) const {
  uint32_t node = roots_[normalBucket(normal)];
  if (node == kNoTree) return nullptr;
  const double p[3] = {position.x, position.y, position.z};
  while (nodes_[node].child[0] != 0) node = nodes_[node].child[p[nodes_[node].axis] < nodes_[node].split ? 0 : 1];
  const std::optional<DirectionalDistribution>& leaf = leaves_[nodes_[node].leaf];
  return leaf ? &*leaf : nullptr;
}

std::size_t GuidingField::bytes() const {
  std::size_t total = nodes_.size() * sizeof(Node) + leaves_.size() * sizeof(leaves_[0]);
  for (const auto& leaf : leaves_)
    if (leaf) total += leaf->bytes();
  return total;
}

}  // namespace acdf

#include "acdf/sampling/alias_table_1d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "acdf/sampling/grid_check.h"

namespace acdf {

AliasTable::AliasTable(std::span<const float> weights) {
  if (weights.empty()) throw std::invalid_argument("alias table: needs at least one weight");
  if (weights.size() > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("alias table: more than 2^32-1 cells");
  }
  checkNonNegativeFinite(weights);
  const std::size_t n = weights.size();
  for (float w : weights) integral_ += w;

  // Vose (1991): scale probabilities to mean 1, then pair each under-full cell with an over-full
  // one that lends it the rest of its slot.
  std::vector<double> scaled(n);
  for (std::size_t i = 0; i < n; ++i) {
    scaled[i] = integral_ > 0.0 ? weights[i] / integral_ * static_cast<double>(n) : 1.0;
  }
  cells_.resize(n);
  std::vector<uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    cells_[i] = {1.0f, static_cast<float>(scaled[i] / static_cast<double>(n)), static_cast<uint32_t>(i)};
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    const uint32_t s = small.back(), l = large.back();
    small.pop_back();
    large.pop_back();
    cells_[s].accept = static_cast<float>(scaled[s]);
    cells_[s].alias = l;
    scaled[l] -= 1.0 - scaled[s];
    (scaled[l] < 1.0 ? small : large).push_back(l);
  }
  // Leftovers of either list are full up to rounding: keep accept = 1. A zero-probability cell can
  // only be left over through rounding; never let it be returned.
  const uint32_t someReachable = static_cast<uint32_t>(
      std::max_element(cells_.begin(), cells_.end(),
                       [](const Cell& a, const Cell& b) { return a.probability < b.probability; }) -
      cells_.begin());
  for (Cell& c : cells_) {
    if (c.probability == 0.0f && c.accept > 0.0f) c = {0.0f, 0.0f, someReachable};
  }
}

std::size_t AliasTable::slotOf(float u, double& fraction) const {
  const double scaled = static_cast<double>(clampUnit(u)) * static_cast<double>(cells_.size());
  const auto i = std::min(static_cast<std::size_t>(scaled), cells_.size() - 1);
  fraction = scaled - static_cast<double>(i);
  return i;
}

// Keeps the slot's own cell if the fraction is below its acceptance probability, else takes its
// alias; remapped is the fraction rescaled to [0,1) within the branch taken.
AliasTable::Discrete AliasTable::accept(std::size_t slot, double fraction) const {
  const Cell& c = cells_[slot];
  if (fraction < c.accept) {
    return {static_cast<uint32_t>(slot), c.probability,
            std::min(static_cast<float>(fraction / c.accept), kOneMinusEpsilon)};
  }
  const float remapped = static_cast<float>((fraction - c.accept) / (1.0 - c.accept));
  return {c.alias, cells_[c.alias].probability, std::min(remapped, kOneMinusEpsilon)};
}

AliasTable::Discrete AliasTable::sample(float u) const {
  double fraction;
  const std::size_t slot = slotOf(u, fraction);
  return accept(slot, fraction);
}

AliasTable::Discrete AliasTable::sample(float uCell, float uAccept) const {
  double unused;
  return accept(slotOf(uCell, unused), clampUnit(uAccept));
}

float AliasTable::cellFraction(float uCell) const {
  double fraction;
  slotOf(uCell, fraction);
  return std::min(static_cast<float>(fraction), kOneMinusEpsilon);
}

AliasTable1D::AliasTable1D(std::span<const float> function, float lo, float hi)
    : axis_(static_cast<uint32_t>(function.size()), lo, hi), table_(function) {}

Sample1D AliasTable1D::sample(float u) const {
  const AliasTable::Discrete d = table_.sample(u);
  const float x = axis_.place(d.index, d.index + 1, d.remapped);
  return {x, clampDensity(axis_.density(d.probability, 1))};
}

float AliasTable1D::pdf(float x) const {
  if (!axis_.contains(x)) return 0.0f;
  return clampDensity(axis_.density(table_.probability(axis_.cellOf(x)), 1));
}

}  // namespace acdf

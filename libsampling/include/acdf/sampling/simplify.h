#pragma once
// Curve simplification of a tabulated CDF: choose the grid vertices an adaptive CDF keeps.
//
// Input is the uniform table's CDF: n+1 non-decreasing values F[0] = 0 ... F[n] = 1 at the grid
// vertices 0..n. Output is a sorted subset of those vertices, always containing 0 and n; the
// adaptive CDF interpolates F linearly between them, so its pdf is piecewise constant on the
// kept intervals and every stored CDF value is one of the uniform table's values.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "acdf/sampling/option_error.h"

namespace acdf {

enum class Simplifier : uint8_t {
  // Douglas–Peucker (1973): split a segment at its worst vertex while the error exceeds ε.
  DouglasPeucker,
  // Greedy global refinement (Lawrence et al. 2005): always split the worst segment of the whole
  // curve next, using a priority queue; stops at the point budget or when the error is <= ε.
  GreedyRefinement,
};

enum class ErrorMetric : uint8_t {
  Vertical,       // |F(k) - line(k)|: the CDF-value (L∞) error, in probability.
  Perpendicular,  // distance to the line in the unit square (x = k/n, y = F).
  // The interval's contribution to the χ²-divergence Σ p²/q − 1 of the simplified distribution
  // from the uniform table, the relative variance the simplification adds to an importance
  // sampling estimator: for [a, b) of mass P = F[b] − F[a] spread evenly over its cells,
  // (b − a) · Σ p_k² / P − P, with p_k = F[k+1] − F[k] (sums in double). ε bounds each
  // interval, so a simplified 1D CDF's divergence is at most (its intervals) × ε. Intervals are
  // split where the vertical metric splits them (see simplify.cpp for why).
  ChiSquare,
};

struct SimplifyOptions {
  Simplifier method = Simplifier::DouglasPeucker;
  ErrorMetric metric = ErrorMetric::Vertical;
  double epsilon = 2e-3;  // largest error left in the simplified CDF, in `metric`'s units; >= 0
  // Greedy refinement only: stop once this many points are kept (0 = no budget). The weight bound
  // below may add points beyond the budget: it is a guarantee, the budget is a target.
  uint32_t maxPoints = 0;
  // ρ: after simplification, while some original cell has p_cell / p_adaptive > ρ inside an
  // interval, split that interval at its worst vertex. Bounds the sample weight the compression
  // can add, so it cannot create fireflies. A Cascade applies it to whole cells of the grid, not
  // only to each 1D CDF (see cascade.h). 0 disables the bound; otherwise must be >= 1.
  double weightBound = 4.0;

  bool operator==(const SimplifyOptions&) const = default;
};

// The one check of these options, for every caller (constructors, the command line, the scene
// loader, the table cache reader). Throws OptionError (option_error.h) on inconsistent options:
// ε negative or not finite, ρ in (0, 1), an unknown metric, a budget below 2, a budget with
// Douglas–Peucker.
void validate(const SimplifyOptions& options);

// cdf: n+1 values as described above (n >= 1). Returns the kept vertices, sorted, with 0 and n.
std::vector<uint32_t> simplifyCdf(std::span<const float> cdf, const SimplifyOptions& options);

// The interior vertex of [a, b] (b - a >= 2) farthest from the chord of the CDF (the split of
// every metric); the middle vertex when the CDF is linear there. Used to split an interval that
// breaks the weight bound.
uint32_t worstVertex(std::span<const float> cdf, uint32_t a, uint32_t b, ErrorMetric metric);

// The one spelling of each value, used by the command line, the JSON outputs and the table cache
// keys: "douglas-peucker", "greedy"; "vertical", "perpendicular", "chi-square". parse throws
// std::invalid_argument for any other name.
std::string_view toString(Simplifier s);
std::string_view toString(ErrorMetric m);
Simplifier parseSimplifier(std::string_view name);
ErrorMetric parseErrorMetric(std::string_view name);

}  // namespace acdf

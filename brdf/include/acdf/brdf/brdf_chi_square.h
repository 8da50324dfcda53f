#pragma once
// The chi-square goodness-of-fit test of a BRDF sampler at one outgoing direction: do its sampled
// ωi follow its own pdf(ωo, ·) over the sphere? Used by the tests and by `acdf chi2 --brdf`.
//
// Expected bin probabilities are integrated where the density is simple rather than by
// quadrature over ωi, which misses sharp specular peaks (and the reflection's stretching near
// ωo·ωh = 0) by up to a percent: the cosine part in closed form, and a tabulated sampler's half-
// vector density over its own table cells — constant per steradian on each — with
// subPoints² (more where the reflection stretches) jittered sub-cells per table cell, uniform in
// solid angle, each reflected to ωi and added to its bin. Only sub-cells straddling a bin edge
// are approximated, and the jitter (fixed seed) turns that into noise below the counts' own
// (a regular sub-grid aliases with the bin edges into a bias of a few percent per bin).
// Bins have equal area (no tiny bins at the poles for the sub-cells to miss).

#include <vector>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/sampling/sphere_chi_square.h"

namespace acdf {

// options.equalAreaRows is forced on; options.subPoints are the sub-cells per table cell per axis.
SphereChiSquareReport brdfChiSquareTest(const BrdfSampler& sampler, const Vec3d& wo, SphereChiSquareOptions options);

// The expected probability of each bin (as sphereBinOf() numbers them) under sampler's pdf(ωo, ·).
// Knows CosineBrdfSampler and TabulatedBrdfSampler; throws std::invalid_argument otherwise.
std::vector<double> brdfBinProbabilities(const BrdfSampler& sampler, const Vec3d& wo,
                                         const SphereChiSquareOptions& options);

}  // namespace acdf

#pragma once
// The chi-square goodness-of-fit test of a BRDF sampler at one outgoing direction: do its sampled
// ωi follow its own pdf(ωo, ·) over the sphere? Used by the tests and by `acdf chi2 --brdf`.
//
// Expected bin probabilities are integrated where the density is simple rather than by
// quadrature over ωi, which misses sharp specular peaks (and the reflection's stretching near
// ωo·ωh = 0) by up to a percent: the cosine part in closed form, and a half-vector sampler's
// density over the half vector on the cells the sampler names (BrdfSampler::halfVectorDensity),
// with subPoints² (more where the reflection stretches) jittered sub-cells per cell, each
// reflected to ωi and added to its bin. A tabulated sampler's cells are its own table cells, on
// which its density is constant per steradian, so only sub-cells straddling a bin edge are
// approximated; a smooth density (GGX, the RGL warps) is weighted by its value at each sub-cell.
// The jitter (fixed seed) turns the approximation into noise below the counts' own (a regular
// sub-grid aliases with the bin edges into a bias of a few percent per bin). Bins have equal
// area (no tiny bins at the poles for the sub-cells to miss).

#include <vector>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/sampling/sphere_chi_square.h"

namespace acdf {

// options.equalAreaRows is forced on; options.subPoints are the sub-cells per table cell per axis.
SphereChiSquareReport brdfChiSquareTest(const BrdfSampler& sampler, const Vec3d& wo, SphereChiSquareOptions options);

// The expected probability of each bin (as sphereBinOf() numbers them) under sampler's pdf(ωo, ·).
// Throws std::invalid_argument for a sampler that is not all cosine-weighted and describes no
// half-vector density.
std::vector<double> brdfBinProbabilities(const BrdfSampler& sampler, const Vec3d& wo,
                                         const SphereChiSquareOptions& options);

}  // namespace acdf

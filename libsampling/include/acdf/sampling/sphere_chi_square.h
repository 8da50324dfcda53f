#pragma once
// A chi-square goodness-of-fit test for samplers of directions (BRDFs, environment lights): does
// the histogram of sampled directions match the sampler's own pdf (per steradian)?
//
// Bins: thetaBins × phiBins over the whole sphere in the z-up frame of sphere.h (θ in [0, π], φ
// in [0, 2π)); rows equal in θ, or in cos θ with equalAreaRows. A bin's expected count is N × ∫ pdf over the bin, by a
// subPoints × subPoints midpoint rule in (θ, φ) with exact solid-angle weights (cos θa − cos θb)·Δφ per sub-cell. The
// rule is exact when the pdf is constant on those sub-cells (an environment map whose pixels
// align with them); otherwise its error shrinks with subPoints, which should then be large
// enough that the error stays well below the counts' noise (≈ 1/√expected).
//
// Every sample is also checked: finite unit direction (|‖ω‖ − 1| ≤ 1e-6), finite pdf > 0, and
// |pdf(ω) − returned pdf| ≤ pdfTolerance · returned pdf. So are the four corner variates
// (0 and kOneMinusEpsilon in each coordinate), which must give valid samples too.
//
// Deterministic for a fixed seed and any thread count: samples are drawn in fixed chunks, each
// with its own Pcg32 stream.

#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "acdf/sampling/chi_square.h"
#include "acdf/sampling/sphere.h"

namespace acdf {

struct DirectionSample {
  Vec3d direction;  // unit vector
  double pdf = 0;   // per steradian
};

struct SphereChiSquareOptions {
  uint64_t samples = 1'000'000;
  uint64_t seed = 0x2545F4914F6CDD1DULL;
  uint32_t thetaBins = 64;
  uint32_t phiBins = 128;
  uint32_t subPoints = 8;  // per bin per axis
  // Rows equal in θ (pixel-aligned for lat-long maps), or equal in cos θ: every bin then has the
  // same solid angle, none tiny at the poles (for pdfs not aligned with any (θ, φ) grid).
  bool equalAreaRows = false;
  double alpha = 0.01;  // level of this one test (apply sidakAlpha() for a family first)
  double pdfTolerance = 1e-4;
};

struct SphereChiSquareReport {
  ChiSquareResult chi2;
  double alpha = 0;
  uint64_t samples = 0;
  uint64_t invalidSamples = 0;  // direction not finite and unit, or pdf not finite and > 0
  uint64_t pdfMismatch = 0;     // |pdf(ω) − returned| > tolerance · returned
  double worstPdfMismatch = 0;  // largest relative mismatch seen
  double pdfIntegral = 0;       // ∫ pdf over the sphere by the midpoint rule
  std::string firstProblem;     // the first invalid or mismatched sample, described

  bool chiSquarePassed() const { return chi2.pvalue >= alpha; }
  bool samplesValid() const { return invalidSamples == 0 && pdfMismatch == 0; }
  bool passed() const { return chiSquarePassed() && samplesValid(); }
  std::string summary() const;
};

using DirectionSampler = std::function<DirectionSample(float u0, float u1)>;
using DirectionPdf = std::function<double(const Vec3d& direction)>;

// Both functions are called from several threads at once. Throws std::invalid_argument for zero
// samples, bins or subPoints.
SphereChiSquareReport sphereChiSquareTest(const DirectionSampler& sample, const DirectionPdf& pdf,
                                          const SphereChiSquareOptions& options = {});

// The same test with each bin's probability given by the caller (thetaBins × phiBins, row-major
// in θ; see sphereBinOf), for samplers whose pdf the (θ, φ) midpoint rule cannot integrate
// accurately but whose own parameter space can (a half-vector table: exactly constant on its
// cells there). pdf() is still used for the per-sample checks; pdfIntegral is Σ probabilities.
SphereChiSquareReport sphereChiSquareTest(const DirectionSampler& sample, const DirectionPdf& pdf,
                                          std::span<const double> binProbabilities,
                                          const SphereChiSquareOptions& options = {});

// The histogram bin of a direction under the options' binning: row × phiBins + φ column.
std::size_t sphereBinOf(const Vec3d& direction, const SphereChiSquareOptions& options);

}  // namespace acdf

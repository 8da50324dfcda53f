#include "acdf/sampling/sphere_chi_square.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "acdf/sampling/rng.h"
#include "acdf/sampling/sample.h"

namespace acdf {

namespace {

constexpr uint64_t kChunkSamples = 1u << 16;

// The per-sample checks; returns false if the sample cannot be binned.
struct SampleChecker {
  const DirectionPdf& pdf;
  double tolerance;

  struct Counts {
    uint64_t invalid = 0, mismatch = 0;
    double worstMismatch = 0;
    std::string firstProblem;

    void problem(const std::string& what) {
      if (firstProblem.empty()) firstProblem = what;
    }
  };

  bool check(float u0, float u1, const DirectionSample& s, Counts& counts) const {
    const Vec3d& w = s.direction;
    auto where = [&] {
      std::ostringstream out;
      out << "u = (" << u0 << ", " << u1 << ") -> (" << w.x << ", " << w.y << ", " << w.z << ") pdf " << s.pdf;
      return out.str();
    };
    const double len = length(w);
    if (!std::isfinite(len) || std::fabs(len - 1.0) > 1e-6 || !std::isfinite(s.pdf) || !(s.pdf > 0.0)) {
      ++counts.invalid;
      counts.problem("invalid sample at " + where());
      return std::isfinite(len) && len > 0.0;
    }
    const double recomputed = pdf(w);
    const double mismatch = std::fabs(recomputed - s.pdf) / s.pdf;
    counts.worstMismatch = std::max(counts.worstMismatch, mismatch);
    if (!(mismatch <= tolerance)) {
      ++counts.mismatch;
      std::ostringstream m;
      m << "pdf(ω) = " << recomputed << " differs from the returned pdf at " << where();
      counts.problem(m.str());
    }
    return true;
  }
};

}  // namespace

std::string SphereChiSquareReport::summary() const {
  std::ostringstream out;
  out << "chi2 " << chi2.statistic << " dof " << chi2.dof << " p " << chi2.pvalue << " (alpha " << alpha
      << "), samples " << samples << ", invalid " << invalidSamples << ", pdf mismatches " << pdfMismatch
      << " (worst " << worstPdfMismatch << "), ∫pdf " << pdfIntegral;
  if (!firstProblem.empty()) out << "; first problem: " << firstProblem;
  return out.str();
}

std::size_t sphereBinOf(const Vec3d& w, const SphereChiSquareOptions& o) {
  const auto cell = [](double fraction, uint32_t n) {
    return std::min(static_cast<uint32_t>(std::max(0.0, fraction * n)), n - 1);
  };
  // Row fraction from the north pole: θ/π, or (1 − cos θ)/2 for equal-area rows.
  const double row = o.equalAreaRows ? 0.5 * (1.0 - w.z / length(w)) : polarAngle(w) / std::numbers::pi;
  return std::size_t{cell(row, o.thetaBins)} * o.phiBins + cell(azimuth(w) / (2.0 * std::numbers::pi), o.phiBins);
}

SphereChiSquareReport sphereChiSquareTest(const DirectionSampler& sample, const DirectionPdf& pdf,
                                          const SphereChiSquareOptions& options) {
  if (options.thetaBins == 0 || options.phiBins == 0 || options.subPoints == 0)
    throw std::invalid_argument("sphere chi-square: bins and subPoints must be > 0");
  const std::size_t bins = std::size_t{options.thetaBins} * options.phiBins;

  // Expected probabilities: per θ row in parallel, each row's sums in double and in a fixed order.
  std::vector<double> probability(bins, 0.0);
  const uint32_t sub = options.subPoints;
  const double dRow = 1.0 / (static_cast<double>(options.thetaBins) * sub);
  const double dPhi = 2.0 * std::numbers::pi / (static_cast<double>(options.phiBins) * sub);
  tbb::parallel_for(uint32_t{0}, options.thetaBins, [&](uint32_t row) {
    for (uint32_t i = 0; i < sub; ++i) {
      // Sub-row edges at fractions fa < fb of the rows' variable (θ/π or (1 − cos θ)/2).
      const double fa = (static_cast<double>(row) * sub + i) * dRow, fb = fa + dRow;
      const double cosA = options.equalAreaRows ? 1.0 - 2.0 * fa : std::cos(fa * std::numbers::pi);
      const double cosB = options.equalAreaRows ? 1.0 - 2.0 * fb : std::cos(fb * std::numbers::pi);
      const double theta = options.equalAreaRows ? std::acos(0.5 * (cosA + cosB)) : 0.5 * (fa + fb) * std::numbers::pi;
      const double weight = (cosA - cosB) * dPhi;  // solid angle of a sub-cell
      for (uint32_t col = 0; col < options.phiBins; ++col) {
        double sum = 0.0;
        for (uint32_t j = 0; j < sub; ++j)
          sum += pdf(sphericalDirection(theta, (static_cast<double>(col) * sub + j + 0.5) * dPhi));
        probability[std::size_t{row} * options.phiBins + col] += sum * weight;
      }
    }
  });
  return sphereChiSquareTest(sample, pdf, probability, options);
}

SphereChiSquareReport sphereChiSquareTest(const DirectionSampler& sample, const DirectionPdf& pdf,
                                          std::span<const double> probability, const SphereChiSquareOptions& options) {
  if (options.samples == 0 || options.thetaBins == 0 || options.phiBins == 0)
    throw std::invalid_argument("sphere chi-square: samples and bins must be > 0");
  const std::size_t bins = std::size_t{options.thetaBins} * options.phiBins;
  if (probability.size() != bins)
    throw std::invalid_argument("sphere chi-square: " + std::to_string(probability.size()) + " bin probabilities for " +
                                std::to_string(bins) + " bins");
  const SampleChecker checker{pdf, options.pdfTolerance};

  // Samples: fixed chunks with their own streams, so the histogram is thread-count independent.
  const uint64_t chunks = (options.samples + kChunkSamples - 1) / kChunkSamples;
  std::vector<std::vector<uint32_t>> chunkCounts(chunks);
  std::vector<SampleChecker::Counts> chunkChecks(chunks);
  tbb::parallel_for(uint64_t{0}, chunks, [&](uint64_t c) {
    Pcg32 rng(options.seed, c);
    auto& counts = chunkCounts[c];
    counts.assign(bins, 0);
    const uint64_t n = std::min(kChunkSamples, options.samples - c * kChunkSamples);
    for (uint64_t k = 0; k < n; ++k) {
      const float u0 = rng.nextFloat(), u1 = rng.nextFloat();
      const DirectionSample s = sample(u0, u1);
      if (checker.check(u0, u1, s, chunkChecks[c])) ++counts[sphereBinOf(s.direction, options)];
    }
  });

  SphereChiSquareReport report;
  report.alpha = options.alpha;
  report.samples = options.samples;
  std::vector<double> observed(bins, 0.0), expected(bins);
  for (uint64_t c = 0; c < chunks; ++c) {
    for (std::size_t b = 0; b < bins; ++b) observed[b] += chunkCounts[c][b];
    const auto& check = chunkChecks[c];
    report.invalidSamples += check.invalid;
    report.pdfMismatch += check.mismatch;
    report.worstPdfMismatch = std::max(report.worstPdfMismatch, check.worstMismatch);
    if (report.firstProblem.empty()) report.firstProblem = check.firstProblem;
  }
  // The extreme variates must give valid samples as well (not part of the histogram).
  SampleChecker::Counts corners;
  for (float u0 : {0.0f, kOneMinusEpsilon})
    for (float u1 : {0.0f, kOneMinusEpsilon}) checker.check(u0, u1, sample(u0, u1), corners);
  report.invalidSamples += corners.invalid;
  report.pdfMismatch += corners.mismatch;
  report.worstPdfMismatch = std::max(report.worstPdfMismatch, corners.worstMismatch);
  if (report.firstProblem.empty()) report.firstProblem = corners.firstProblem;

  for (std::size_t b = 0; b < bins; ++b) {
    report.pdfIntegral += probability[b];
    expected[b] = probability[b] * static_cast<double>(options.samples);
  }
  report.chi2 = chiSquareTest(observed, expected);
  return report;
}

}  // namespace acdf

// Fuzzes the sampling engine: arbitrary bytes become a distribution's shape, domain, options and
// tabulated values, then variates. Invariants (the numerical contract of libsampling):
//   - the constructor either succeeds or throws std::invalid_argument (anything else escapes and
//     libFuzzer records it);
//   - every sample lies inside the domain, with a finite pdf > 0 that equals pdf(x) exactly;
//   - invert(x) is a variate in [0, 1].
// Values come from raw float bits (NaN, Inf, negatives and denormals included) or from a palette
// of extreme magnitudes, so both validation and the adversarial-but-valid paths are reached.

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_grid.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "fuzz_input.h"

namespace {

using namespace acdf;
using fuzz::Bytes;
using fuzz::require;

constexpr float kPalette[16] = {0.0f,
                                0.0f,
                                1.0f,
                                1.0f,
                                0.5f,
                                1e-30f,
                                1e30f,
                                std::numeric_limits<float>::denorm_min(),
                                std::numeric_limits<float>::min(),
                                std::numeric_limits<float>::max(),
                                1e-38f,
                                3.0f,
                                1e-10f,
                                1e10f,
                                0.25f,
                                7.0f};
constexpr float kVariatePalette[8] = {
    0.0f, kOneMinusEpsilon, 0.5f, 0x1p-24f, 1.0f - 0x1p-23f, std::numeric_limits<float>::denorm_min(), 1.0f, -0.0f};

float value(Bytes& in, bool raw) {
  if (raw) return in.take<float>();
  const uint8_t b = in.byte();
  return kPalette[b & 15] * (b & 16 ? 2.0f : 1.0f);
}

// A variate: raw bits (NaN, negatives and > 1 are clamped by the samplers), a palette entry near
// the ends of [0, 1), or a 16-bit lattice point.
float variate(Bytes& in) {
  const uint8_t mode = in.byte() % 3;
  if (mode == 0) return in.take<float>();
  if (mode == 1) return kVariatePalette[in.byte() & 7];
  return static_cast<float>(in.take<uint16_t>()) * 0x1p-16f;
}

GridAxis axis(Bytes& in, uint32_t maxCells) {
  const uint32_t cells = 1 + in.take<uint16_t>() % maxCells;
  if (in.byte() % 4 != 0) return GridAxis(cells);
  const float lo = in.take<float>(), hi = in.take<float>();
  return GridAxis(cells, lo, hi);  // may throw std::invalid_argument: a documented outcome
}

SimplifyOptions simplifyOptions(Bytes& in) {
  SimplifyOptions o;
  const uint8_t b = in.byte();
  o.method = b & 1 ? Simplifier::GreedyRefinement : Simplifier::DouglasPeucker;
  o.metric = static_cast<ErrorMetric>((b >> 1) % 3);
  constexpr double kEpsilon[8] = {0.0, 1e-6, 1e-4, 2e-3, 0.05, 0.5, 10.0, -1.0};
  o.epsilon = kEpsilon[(b >> 3) & 7];
  const uint8_t c = in.byte();
  o.maxPoints = c & 1 ? c >> 1 : 0;
  constexpr double kWeightBound[4] = {0.0, 1.0, 4.0, 0.5};
  o.weightBound = kWeightBound[in.byte() & 3];
  return o;
}

std::string where(float x, float pdf, float expected) {
  return "x=" + std::to_string(x) + " pdf=" + std::to_string(pdf) + " pdf(x)=" + std::to_string(expected);
}

void checkVariate(float u) { require(u >= 0.0f && u <= 1.0f, "invert() outside [0, 1]", std::to_string(u)); }

void checkSample1D(const GridAxis& axis, Sample1D s, float pdfAtX) {
  require(axis.contains(s.x), "1D sample outside the domain", where(s.x, s.pdf, pdfAtX));
  require(std::isfinite(s.pdf) && s.pdf > 0.0f, "1D pdf not finite and positive", where(s.x, s.pdf, pdfAtX));
  require(s.pdf == pdfAtX, "1D pdf(x) differs from the sample's pdf", where(s.x, s.pdf, pdfAtX));
}

template <class Distribution>
void run1D(const Distribution& d, Bytes& in) {
  while (!in.empty()) {
    const Sample1D s = d.sample(variate(in));
    checkSample1D(d.axis(), s, d.pdf(s.x));
    if constexpr (requires { d.invert(s.x); }) checkVariate(d.invert(s.x));
  }
}

void checkSampleND(std::span<const GridAxis> axes, const SampleND& s, float pdfAtX) {
  require(s.dims == axes.size(), "ND sample has the wrong dimension");
  for (std::size_t d = 0; d < axes.size(); ++d)
    require(axes[d].contains(s.x[d]), "ND sample outside the domain",
            "axis " + std::to_string(d) + " " + where(s.x[d], s.pdf, pdfAtX));
  require(std::isfinite(s.pdf) && s.pdf > 0.0f, "ND pdf not finite and positive", where(s.x[0], s.pdf, pdfAtX));
  require(s.pdf == pdfAtX, "ND pdf(x) differs from the sample's pdf", where(s.x[0], s.pdf, pdfAtX));
}

// Sets `built` once a distribution exists: from then on nothing may throw.
void fuzzOne(Bytes& in, bool& built) {
  const uint8_t kind = in.byte() % 5;
  const bool raw = in.byte() & 1;
  if (kind < 3) {
    const GridAxis a = axis(in, 300);
    const SimplifyOptions options = simplifyOptions(in);
    std::vector<float> f(a.cells());
    for (float& v : f) v = value(in, raw);
    auto run = [&](const auto& distribution) {
      built = true;
      run1D(distribution, in);
    };
    if (kind == 0) run(PiecewiseConstant1D(f, a.lo(), a.hi()));
    if (kind == 1) run(AdaptiveCdf1D(f, a.lo(), a.hi(), options));
    if (kind == 2) run(AliasTable1D(f, a.lo(), a.hi()));
    return;
  }
  const std::size_t dims = 1 + in.byte() % 3;
  std::vector<GridAxis> axes;
  std::size_t cells = 1;
  for (std::size_t d = 0; d < dims; ++d) {
    axes.push_back(axis(in, 24));
    cells *= axes.back().cells();
  }
  // Occasionally one value too few or too many: the shape check must catch it.
  const uint8_t shapeByte = in.byte();
  const std::size_t count = shapeByte == 255 ? cells + 1 : shapeByte == 254 ? cells - 1 : cells;
  std::vector<float> values(count);
  for (float& v : values) v = value(in, raw);

  if (kind == 3) {
    const AliasGrid grid(values, axes);
    built = true;
    std::vector<float> u(dims);
    while (!in.empty()) {
      for (float& v : u) v = variate(in);
      const SampleND s = grid.sample(u);
      checkSampleND(axes, s, grid.pdf(s.point()));
    }
    return;
  }

  CascadeOptions options;
  const uint8_t b = in.byte();
  options.conditioningDims = b % dims;
  if (b & 4) {
    for (std::size_t d = options.conditioningDims; d < dims; ++d)
      options.methods.push_back(in.byte() & 1 ? DimensionMethod::Adaptive : DimensionMethod::Uniform);
  }
  options.conditional = b & 8 ? ConditionalRule::AverageOfNormalized : ConditionalRule::ExactMass;
  options.tolerance = b & 16 ? ConditionalTolerance::MassScaled : ConditionalTolerance::Constant;
  constexpr double kGrouping[4] = {0.0, 0.0, 0.01, 1.0};
  options.sliceGroupingTolerance = kGrouping[(b >> 5) & 3];
  options.simplify = simplifyOptions(in);
  const Cascade cascade(values, axes, options);
  built = true;
  const std::size_t conditioning = cascade.conditioningDims(), sampled = cascade.sampledDims();
  const std::span<const GridAxis> sampledAxes(cascade.axes().data() + conditioning, sampled);
  std::vector<float> condition(conditioning), u(sampled), back(sampled);
  while (!in.empty()) {
    for (float& c : condition) c = in.take<float>();  // any float: looked up by nearest cell
    for (float& v : u) v = variate(in);
    const SampleND s = cascade.sample(condition, u);
    checkSampleND(sampledAxes, s, cascade.pdf(condition, s.point()));
    cascade.invert(condition, s.point(), back);
    for (float v : back) checkVariate(v);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  bool built = false;
  try {
    fuzzOne(in, built);
  } catch (const std::invalid_argument& e) {
    // The documented outcome of a bad shape, domain, value or option, at construction only.
    require(!built, "sampling a valid distribution threw", e.what());
  }
  return 0;
}

// Binary serialization of a Cascade (see cascade.h). Layout, all little-endian:
//   u32 magic "ACSC", u32 version (Cascade::kSerialVersion)
//   u8 dims, u8 conditioning dims; per axis: u32 cells, f32 lo, f32 hi
//   options: u8 method count (0 or the sampled dims) and one u8 each; simplify: u8 simplifier,
//            u8 metric, f64 ε, u32 point budget, f64 ρ; u8 conditional rule; u8 tolerance rule;
//            f64 slice grouping tolerance
//   slice integrals (u64 count, f64 each), slice roots (u64 count, u32 each)
//   per sampled level: u8 method, interior CDF values (u64 count, f32 each); adaptive levels add
//            u8 vertex index width, u64 count and the indices (width bytes each), and starts (u64
//            count, u32 each)
// That is the in-memory layout of cascade.h (the end points 0 and 1 of each CDF are implicit).
// Arrays carry their counts so a reader can check them against the shape before using them.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "acdf/sampling/byte_io.h"
#include "acdf/sampling/cascade.h"

namespace acdf {

namespace {

constexpr uint32_t kMagic = 0x43534341;  // "ACSC" read as little-endian bytes

std::string levelName(std::size_t level) { return "level " + std::to_string(level); }

// The interior values of one 1D CDF as every sampler requires them: with the implicit end points
// 0 and 1, a non-decreasing sequence (which also rules out NaN and Inf), so every u in [0, 1)
// falls in an interval of positive mass.
void checkCdf(const ByteReader& in, const float* interior, std::size_t count, const std::string& where) {
  float previous = 0.0f;
  for (std::size_t j = 0; j < count; ++j) {
    if (!(interior[j] >= previous)) {
      in.fail(where + ": CDF value " + std::to_string(interior[j]) + " at point " + std::to_string(j + 1) +
              " is not >= the previous " + std::to_string(previous));
    }
    previous = interior[j];
  }
  if (!(previous <= 1.0f)) in.fail(where + ": CDF value " + std::to_string(previous) + " exceeds 1");
}

template <class Enum>
Enum getEnum(ByteReader& in, Enum last, const char* name) {
  const uint8_t v = in.get<uint8_t>();
  if (v > static_cast<uint8_t>(last)) in.fail(std::string("unknown ") + name + " " + std::to_string(v));
  return static_cast<Enum>(v);
}

void writeOptions(ByteWriter& out, const CascadeOptions& o) {
  out.put<uint8_t>(static_cast<uint8_t>(o.methods.size()));
  for (DimensionMethod m : o.methods) out.put(static_cast<uint8_t>(m));
  out.put(static_cast<uint8_t>(o.simplify.method));
  out.put(static_cast<uint8_t>(o.simplify.metric));
  out.put(o.simplify.epsilon);
  out.put(o.simplify.maxPoints);
  out.put(o.simplify.weightBound);
  out.put(static_cast<uint8_t>(o.conditional));
  out.put(static_cast<uint8_t>(o.tolerance));
  out.put(o.sliceGroupingTolerance);
}

CascadeOptions readOptions(ByteReader& in, uint32_t conditioningDims, std::size_t sampledDims) {
  CascadeOptions o;
  o.conditioningDims = conditioningDims;
  const uint8_t methods = in.get<uint8_t>();
  if (methods != 0 && methods != sampledDims) {  // before reading that many
    in.fail(std::to_string(methods) + " dimension methods for " + std::to_string(sampledDims) + " sampled axes");
  }
  for (uint8_t d = 0; d < methods; ++d) o.methods.push_back(getEnum(in, DimensionMethod::Adaptive, "dimension method"));
  o.simplify.method = getEnum(in, Simplifier::GreedyRefinement, "simplifier");
  o.simplify.metric = getEnum(in, ErrorMetric::ChiSquare, "error metric");
  o.simplify.epsilon = in.get<double>();
  o.simplify.maxPoints = in.get<uint32_t>();
  o.simplify.weightBound = in.get<double>();
  o.conditional = getEnum(in, ConditionalRule::AverageOfNormalized, "conditional rule");
  o.tolerance = getEnum(in, ConditionalTolerance::MassScaled, "tolerance rule");
  o.sliceGroupingTolerance = in.get<double>();
  try {
    validate(o, conditioningDims + sampledDims);
  } catch (const OptionError& e) {
    in.fail(e.option() + " " + e.problem());  // `in` names the cascade already
  }
  return o;
}

// Reads an adaptive level's interior vertex indices (at most `largestVertex`) in the width a build
// uses for them.
VertexIndices readVertices(ByteReader& in, uint32_t largestVertex, const std::string& where) {
  VertexIndices v(largestVertex);
  const uint8_t width = in.get<uint8_t>();
  if (width != v.width()) {
    in.fail(where + ": " + std::to_string(width) + "-byte vertex indices up to " + std::to_string(largestVertex) +
            " (a build uses " + std::to_string(v.width()) + ")");
  }
  const uint64_t count = in.get<uint64_t>();
  if (count > in.remaining() / width) {
    in.fail("truncated (" + where + ": " + std::to_string(count) + " vertex indices of " + std::to_string(width) +
            " bytes, " + std::to_string(in.remaining()) + " bytes left)");
  }
  v.reserve(static_cast<std::size_t>(count));
  for (uint64_t i = 0; i < count; ++i) {
    const uint32_t vertex = width == 1 ? in.get<uint8_t>() : width == 2 ? in.get<uint16_t>() : in.get<uint32_t>();
    v.push_back(vertex);
  }
  return v;
}

}  // namespace

void Cascade::write(ByteWriter& out) const {
  out.put(kMagic);
  out.put(kSerialVersion);
  out.put(static_cast<uint8_t>(axes_.size()));
  out.put(static_cast<uint8_t>(conditioningDims_));
  for (const GridAxis& a : axes_) {
    out.put(a.cells());
    out.put(a.lo());
    out.put(a.hi());
  }
  writeOptions(out, options_);
  out.putArray<double>(sliceIntegral_);
  out.putArray<uint32_t>(sliceRoot_);
  for (const Level& l : levels_) {
    out.put(static_cast<uint8_t>(l.method));
    out.putArray<float>(l.cdf);
    if (l.method == DimensionMethod::Uniform) continue;
    out.put(static_cast<uint8_t>(l.vertices.width()));
    out.put<uint64_t>(l.vertices.size());
    for (std::size_t i = 0; i < l.vertices.size(); ++i) {
      const uint32_t v = l.vertices[i];
      if (l.vertices.width() == 1)
        out.put(static_cast<uint8_t>(v));
      else if (l.vertices.width() == 2)
        out.put(static_cast<uint16_t>(v));
      else
        out.put(v);
    }
    out.putArray<uint32_t>(l.starts);
  }
}

std::vector<std::byte> Cascade::serialize() const {
  ByteWriter out;
  write(out);
  return out.take();
}

Cascade Cascade::deserialize(std::span<const std::byte> bytes) {
  ByteReader in(bytes, "cascade");
  Cascade c = read(in);
  in.expectEnd();
  return c;
}

Cascade Cascade::read(ByteReader& in) {
  if (in.get<uint32_t>() != kMagic) in.fail("not a serialized cascade (wrong magic number)");
  if (const uint32_t version = in.get<uint32_t>(); version != kSerialVersion) {
    in.fail("format version " + std::to_string(version) + ", this build reads " + std::to_string(kSerialVersion));
  }
  Cascade c;
  const uint8_t dims = in.get<uint8_t>();
  const uint8_t conditioning = in.get<uint8_t>();
  if (dims < 1 || dims > kMaxDims) in.fail(std::to_string(dims) + " axes (1 to " + std::to_string(kMaxDims) + ")");
  if (conditioning >= dims) {
    in.fail(std::to_string(conditioning) + " conditioning axes leave none to sample out of " + std::to_string(dims));
  }
  for (uint8_t d = 0; d < dims; ++d) {
    const uint32_t cells = in.get<uint32_t>();
    const float lo = in.get<float>(), hi = in.get<float>();
    try {
      c.axes_.emplace_back(cells, lo, hi);
    } catch (const std::invalid_argument& e) {
      in.fail("axis " + std::to_string(d) + ": " + e.what());
    }
  }
  c.conditioningDims_ = conditioning;
  c.options_ = readOptions(in, conditioning, c.sampledDims());

  // Slices: the conditioning grid's cells. Each needs an 8-byte integral, which bounds the count
  // by the bytes left before the product could overflow.
  std::size_t slices = 1;
  for (std::size_t d = 0; d < conditioning; ++d) {
    slices *= c.axes_[d].cells();
    if (slices > in.remaining() / sizeof(double)) in.fail("truncated (the conditioning grid needs more slices)");
  }
  c.sliceIntegral_ = in.getArray<double>("slice integrals");
  if (c.sliceIntegral_.size() != slices) {
    in.fail(std::to_string(c.sliceIntegral_.size()) + " slice integrals for " + std::to_string(slices) + " slices");
  }
  for (std::size_t s = 0; s < slices; ++s) {
    if (!(c.sliceIntegral_[s] >= 0.0) || !std::isfinite(c.sliceIntegral_[s])) {
      in.fail("slice " + std::to_string(s) + " has integral " + std::to_string(c.sliceIntegral_[s]));
    }
  }
  c.sliceRoot_ = in.getArray<uint32_t>("slice roots");
  std::size_t nodes = slices;  // 1D CDFs of the current level; level 0 has one per distribution
  if (!c.sliceRoot_.empty()) {
    if (c.sliceRoot_.size() != slices) {
      in.fail(std::to_string(c.sliceRoot_.size()) + " slice roots for " + std::to_string(slices) + " slices");
    }
    // Roots are numbered in slice order: each slice reuses an earlier root or takes the next.
    nodes = 0;
    for (uint32_t r : c.sliceRoot_) {
      if (r > nodes) in.fail("slice roots are not numbered in slice order");
      nodes = std::max<std::size_t>(nodes, std::size_t{r} + 1);
    }
  }

  for (std::size_t level = 0; level < c.sampledDims(); ++level) {
    const std::string where = levelName(level);
    const uint32_t cells = c.axes_[conditioning + level].cells();
    const DimensionMethod expected = c.options_.methods.empty() ? DimensionMethod::Adaptive : c.options_.methods[level];
    Level l;
    l.method = getEnum(in, DimensionMethod::Adaptive, "dimension method");
    if (l.method != expected) in.fail(where + ": method differs from the options'");
    l.cdf = in.getArray<float>("CDF values");
    if (l.cdf.size() > UINT32_MAX) in.fail(where + ": more than 2^32 CDF values");
    if (l.method == DimensionMethod::Uniform) {
      // Every 1D CDF keeps all cells − 1 inner grid vertices and has one child per cell.
      // (Divided rather than multiplied: a corrupt count must not overflow.)
      const std::size_t inner = std::size_t{cells} - 1;
      if (inner == 0 ? !l.cdf.empty() : l.cdf.size() % inner != 0 || l.cdf.size() / inner != nodes) {
        in.fail(where + ": " + std::to_string(l.cdf.size()) + " CDF values for " + std::to_string(nodes) +
                " uniform CDFs of " + std::to_string(cells) + " cells");
      }
      for (std::size_t k = 0; k < nodes; ++k) {
        checkCdf(in, l.cdf.data() + k * (cells - 1), cells - 1, where + " CDF " + std::to_string(k));
      }
      nodes *= cells;
    } else {
      l.vertices = readVertices(in, cells - 1, where);
      if (l.vertices.size() != l.cdf.size()) {
        in.fail(where + ": " + std::to_string(l.vertices.size()) + " vertex indices for " +
                std::to_string(l.cdf.size()) + " CDF values");
      }
      l.starts = in.getArray<uint32_t>("CDF starts");
      if (l.starts.size() != nodes + 1 || l.starts.front() != 0 || l.starts.back() != l.cdf.size()) {
        in.fail(where + ": CDF starts do not cover the " + std::to_string(l.cdf.size()) + " values of " +
                std::to_string(nodes) + " CDFs");
      }
      for (std::size_t k = 0; k < nodes; ++k) {
        const std::string cdfName = where + " CDF " + std::to_string(k);
        const uint32_t first = l.starts[k], end = l.starts[k + 1];
        if (end < first) in.fail(cdfName + ": start offsets decrease");
        // Interior vertices lie strictly between vertex 0 and the last one, strictly increasing.
        uint32_t previous = 0;
        for (uint32_t j = first; j < end; ++j) {
          if (l.vertices[j] <= previous || l.vertices[j] >= cells) {
            in.fail(cdfName + ": vertex index " + std::to_string(l.vertices[j]) + " not strictly between " +
                    std::to_string(previous) + " and " + std::to_string(cells));
          }
          previous = l.vertices[j];
        }
        checkCdf(in, l.cdf.data() + first, end - first, cdfName);
      }
      // Each CDF has its interior points + 1 intervals, each with one child CDF in the next level.
      nodes = l.cdf.size() + nodes;
    }
    c.levels_.push_back(std::move(l));
  }
  return c;
}

}  // namespace acdf

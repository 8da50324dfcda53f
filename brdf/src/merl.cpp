#include "acdf/brdf/merl.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <system_error>

#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/regular_file.h"
#include "acdf/sampling/threshold_cells.h"
#include "acdf/sampling/write_atomically.h"

namespace acdf {

// The file holds little-endian int32 and float64; both are copied as they are.
static_assert(std::endian::native == std::endian::little, "the MERL reader copies little-endian data as is");
// The conversion pass narrows every double before checking it, relying on IEEE 754 conversion.
static_assert(std::numeric_limits<float>::is_iec559 && std::numeric_limits<double>::is_iec559);

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kHeaderBytes = 3 * sizeof(int32_t);
constexpr std::size_t kChannelBytes = MerlBrdf::kCells * sizeof(double);
constexpr std::size_t kFileBytes = kHeaderBytes + 3 * kChannelBytes;
constexpr const char* kChannelName[3] = {"red", "green", "blue"};
constexpr double kHalfPi = std::numbers::pi / 2;

// "NaN in the green channel at index 12345 (θh cell 0, θd cell 68, φd cell 105)".
std::string badValueProblem(int channel, std::size_t index, double value) {
  std::string what;
  if (std::isnan(value))
    what = "NaN";
  else if (std::isinf(value))
    what = value > 0 ? "+Inf" : "-Inf";
  else {
    char text[40];
    std::snprintf(text, sizeof text, "%.9g", value);
    what = std::string("value ") + text + " (beyond float range)";
  }
  const std::size_t th = index / (std::size_t{MerlBrdf::kThetaDiffCells} * MerlBrdf::kPhiDiffCells);
  const std::size_t td = index / MerlBrdf::kPhiDiffCells % MerlBrdf::kThetaDiffCells;
  const std::size_t pd = index % MerlBrdf::kPhiDiffCells;
  return what + " in the " + kChannelName[channel] + " channel at index " + std::to_string(index) + " (theta_h cell " +
         std::to_string(th) + ", theta_d cell " + std::to_string(td) + ", phi_d cell " + std::to_string(pd) + ")";
}

std::string errnoText() { return std::strerror(errno); }

// Continuous grid coordinates (cell k spans [k, k+1)) of the three table axes.
double thetaHalfCoordinate(double thetaHalf) {
  return thetaHalf > 0 ? std::sqrt(thetaHalf / kHalfPi) * MerlBrdf::kThetaHalfCells : 0.0;
}
double thetaDiffCoordinate(double thetaDiff) { return thetaDiff / kHalfPi * MerlBrdf::kThetaDiffCells; }
// φd folded into [0, π) by reciprocity first (any finite angle; NaN gives NaN).
double foldPhiDiff(double phiDiff) {
  double phi = std::fmod(phiDiff, std::numbers::pi);  // exact, in (−π, π)
  if (phi < 0) phi += std::numbers::pi;
  if (phi >= std::numbers::pi) phi -= std::numbers::pi;  // −tiny + π can round up to π
  return phi;
}
double phiDiffCoordinate(double phiDiff) { return foldPhiDiff(phiDiff) / std::numbers::pi * MerlBrdf::kPhiDiffCells; }

// The two cells whose centres bracket grid coordinate g, and the weight of the second.
struct Bracket {
  int i0, i1;
  double t;
};
// θ axes: constant beyond the first and last centres (nothing to interpolate towards).
Bracket clampedBracket(double g, int cells) {
  const double p = g - 0.5;
  if (!(p > 0)) return {0, 0, 0.0};
  if (p >= cells - 1) return {cells - 1, cells - 1, 0.0};
  const int i0 = static_cast<int>(p);
  return {i0, i0 + 1, p - i0};
}
// φd: periodic, the last cell's neighbour is the first (φd = π is φd = 0 by reciprocity).
Bracket wrappedBracket(double g, int cells) {
  const double p = g - 0.5;
  const double floorP = std::floor(p);
  int i0 = static_cast<int>(floorP);  // in [−1, cells − 1] for g in [0, cells]
  const double t = p - floorP;
  i0 = (i0 % cells + cells) % cells;
  return {i0, (i0 + 1) % cells, t};
}

// Clamps a non-negative grid coordinate (or NaN) to a cell index without overflowing the cast.
int clampIndex(double g, int cells) {
  if (!(g > 0)) return 0;
  if (g >= cells - 1) return cells - 1;
  return static_cast<int>(g);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Construction and validation

namespace {

// The one pass over a channel's data, shared by the constructor and load(): converts kCells
// doubles (read from `bytes`, little-endian, possibly unaligned) into every third float of `out`
// (the channel's place in the interleaved table), adding the negatives
// to `negativeEntries`. Returns the index of the first NaN / Inf / beyond-float value, or kCells
// if there is none. Written so that GCC vectorises it (the checks are on the float, the counters
// int): it then costs a fraction of the read. A bad channel is rescanned for the first bad index.
// memcpy because the file's doubles start at offset 12, not 8-byte aligned; it compiles to a
// plain unaligned load.
std::size_t convertChannel(const unsigned char* bytes, float* out, std::size_t& negativeEntries) {
  constexpr float kFloatMax = std::numeric_limits<float>::max();
  const auto narrowed = [bytes](std::size_t i) {
    double v;
    std::memcpy(&v, bytes + i * sizeof(double), sizeof(double));
    return static_cast<float>(v);  // IEEE (is_iec559): beyond float range rounds to ±Inf
  };
  int negatives = 0, bad = 0;  // kCells < 2^31
  for (std::size_t i = 0; i < MerlBrdf::kCells; ++i) {
    const float f = narrowed(i);
    bad |= !(std::fabs(f) <= kFloatMax);  // NaN, Inf, or a double beyond float range
    negatives += f < 0.0f;
    out[3 * i] = f > 0.0f ? f : 0.0f;  // negatives (and −0) become +0
  }
  if (bad) {
    for (std::size_t i = 0; i < MerlBrdf::kCells; ++i)
      if (!(std::fabs(narrowed(i)) <= kFloatMax)) return i;
  }
  negativeEntries += static_cast<std::size_t>(negatives);
  return MerlBrdf::kCells;
}

// Uninitialised: every entry is overwritten, and zero-filling 17.5 MB first would cost a third of
// the read.
std::shared_ptr<float[]> allocateValues() { return std::make_shared_for_overwrite<float[]>(3 * MerlBrdf::kCells); }

}  // namespace

MerlBrdf::MerlBrdf(std::span<const double> red, std::span<const double> green, std::span<const double> blue,
                   Interpolation interpolation)
    : interpolation_(interpolation) {
  const std::span<const double> channels[3] = {red, green, blue};
  for (int c = 0; c < 3; ++c) {
    if (channels[c].size() != kCells) {
      throw std::invalid_argument("MERL BRDF: the " + std::string(kChannelName[c]) + " channel has " +
                                  std::to_string(channels[c].size()) + " values, expected " + std::to_string(kCells) +
                                  " (90 x 90 x 180)");
    }
  }
  const std::shared_ptr<float[]> values = allocateValues();
  for (int c = 0; c < 3; ++c) {
    const std::size_t bad =
        convertChannel(reinterpret_cast<const unsigned char*>(channels[c].data()), values.get() + c, negativeEntries_);
    if (bad != kCells) throw std::invalid_argument("MERL BRDF: " + badValueProblem(c, bad, channels[c][bad]));
  }
  values_ = values;
}

MerlBrdf MerlBrdf::withInterpolation(Interpolation interpolation) const {
  return MerlBrdf(values_, negativeEntries_, interpolation);
}

MerlBrdf MerlBrdf::load(const fs::path& path, Interpolation interpolation) {
  const std::string name = path.string();
  if (const auto problem = regularFileProblem(path)) throw FileError(name, *problem);

  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(name, "cannot open file (" + errnoText() + ")");
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  in.seekg(0, std::ios::beg);
  if (end < 0 || !in) throw FileError(name, "cannot determine the file size");
  const auto size = static_cast<std::size_t>(end);

  if (size < kHeaderBytes) {
    throw FileError(name, "truncated header: the file has " + std::to_string(size) +
                              " bytes, a MERL header is 12 (three int32 dimensions)");
  }
  const auto checkDimensions = [&](const unsigned char* header) {
    int32_t dims[3];
    std::memcpy(dims, header, kHeaderBytes);
    // In double: three int32 can multiply to 2^93, beyond int64 (found by fuzz/merl_fuzz.cpp).
    // Exact wherever it matters: any product near kCells is far below 2^53.
    const double product = static_cast<double>(dims[0]) * dims[1] * dims[2];
    if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0 || product != static_cast<double>(kCells)) {
      throw FileError(name, "wrong dimensions " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                                std::to_string(dims[2]) +
                                " in the header; a MERL table has 90 x 90 x 180 = 1458000 entries");
    }
  };
  // A file of the wrong size is an error whatever it holds: read only its header, to say which
  // error, rather than all of a possibly huge file.
  if (size != kFileBytes) {
    unsigned char header[kHeaderBytes];
    if (!in.read(reinterpret_cast<char*>(header), kHeaderBytes)) throw FileError(name, "read error");
    checkDimensions(header);
    if (size < kFileBytes) {
      throw FileError(name, "truncated data: " + std::to_string(size - kHeaderBytes) +
                                " bytes after the header, expected " + std::to_string(3 * kChannelBytes) +
                                " (3 channels of 1458000 float64)");
    }
    throw FileError(name, std::to_string(size - kFileBytes) + " extra trailing bytes after the data (file is " +
                              std::to_string(size) + " bytes, expected " + std::to_string(kFileBytes) + ")");
  }

  // The whole file in one read; for_overwrite because zero-filling 35 MB first would cost about
  // as much as reading them.
  const auto bytes = std::make_unique_for_overwrite<unsigned char[]>(size);
  in.read(reinterpret_cast<char*>(bytes.get()), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size || in.peek() != std::ifstream::traits_type::eof()) {
    throw FileError(name, "read error (file changed while reading?)");
  }
  checkDimensions(bytes.get());

  const std::shared_ptr<float[]> values = allocateValues();
  std::size_t negativeEntries = 0;
  for (int c = 0; c < 3; ++c) {
    const unsigned char* channelBytes = bytes.get() + kHeaderBytes + c * kChannelBytes;
    const std::size_t bad = convertChannel(channelBytes, values.get() + c, negativeEntries);
    if (bad != kCells) {
      double v;
      std::memcpy(&v, channelBytes + bad * sizeof(double), sizeof(double));
      throw FileError(name, badValueProblem(c, bad, v));
    }
  }
  return MerlBrdf(values, negativeEntries, interpolation);
}

// ---------------------------------------------------------------------------------------------
// Saving

void MerlBrdf::save(const fs::path& path) const {
  const std::string name = path.string();
  const auto bytes = std::make_unique_for_overwrite<unsigned char[]>(kFileBytes);
  const int32_t dims[3] = {kThetaHalfCells, kThetaDiffCells, kPhiDiffCells};
  std::memcpy(bytes.get(), dims, kHeaderBytes);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < kCells; ++i) {
      const double v = values_[3 * i + c];
      std::memcpy(bytes.get() + kHeaderBytes + (c * kCells + i) * sizeof(double), &v, sizeof(double));
    }
  writeFileAtomically(name, std::as_bytes(std::span(bytes.get(), kFileBytes)));
}

void MerlBrdf::saveRaw(const fs::path& path, std::span<const double> values) {
  if (values.size() != 3 * kCells) {
    throw std::invalid_argument("MERL BRDF: saveRaw got " + std::to_string(values.size()) + " values, expected " +
                                std::to_string(3 * kCells) + " (3 x 90 x 180 x 90)");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw std::invalid_argument("MERL BRDF: saveRaw: " +
                                  badValueProblem(static_cast<int>(i / kCells), i % kCells, values[i]));
    }
  }
  const std::string name = path.string();
  const auto bytes = std::make_unique_for_overwrite<unsigned char[]>(kFileBytes);
  const int32_t dims[3] = {kThetaHalfCells, kThetaDiffCells, kPhiDiffCells};
  std::memcpy(bytes.get(), dims, kHeaderBytes);
  std::memcpy(bytes.get() + kHeaderBytes, values.data(), 3 * kChannelBytes);
  writeFileAtomically(name, std::as_bytes(std::span(bytes.get(), kFileBytes)));
}

// ---------------------------------------------------------------------------------------------
// Indexing and evaluation

int MerlBrdf::thetaHalfIndex(double thetaHalf) {
  // MERL: ⌊√(θh/(π/2) · 90 · 90)⌋, written in its order of operations so cell boundaries agree.
  if (!(thetaHalf > 0)) return 0;
  const double thetaHalfDeg = thetaHalf / kHalfPi * kThetaHalfCells;
  return clampIndex(std::sqrt(thetaHalfDeg * kThetaHalfCells), kThetaHalfCells);
}

int MerlBrdf::thetaDiffIndex(double thetaDiff) {
  return clampIndex(thetaDiff / kHalfPi * kThetaDiffCells, kThetaDiffCells);
}

int MerlBrdf::phiDiffIndex(double phiDiff) {
  // MERL only adds π to negative angles, which sends φd = π to index 180 (clamped to 179);
  // folding into [0, π) sends it to 0 — the same configuration as φd = 0, which is the point.
  return clampIndex(phiDiffCoordinate(phiDiff), kPhiDiffCells);
}

double MerlBrdf::thetaHalfCentre(int k) {
  const double s = (k + 0.5) / kThetaHalfCells;
  return s * s * kHalfPi;
}
double MerlBrdf::thetaDiffCentre(int k) { return (k + 0.5) / kThetaDiffCells * kHalfPi; }
double MerlBrdf::phiDiffCentre(int k) { return (k + 0.5) / kPhiDiffCells * std::numbers::pi; }

namespace {

// How near a cell boundary a quantity must be for MerlBrdf::cellOf to defer to the angles: the
// quantities, the thresholds and atan2 are each within a few double ulps of exact, so 1e-9
// leaves a factor of 10^5 and sends well under 1e-6 of the pairs down the slow path.
constexpr double kCellMargin = 1e-9;

// φd's cells over the whole turn of d's azimuth, by the pseudo-angle of (dx, dy) in [0, 4): the
// index steps up at the same angles in [0, π) and in [π, 2π) (the fold by reciprocity), and
// returns to 0 at π (pseudo-angle 2) and at 2π (4). The counts 180 and 360 at those two are 0
// again; a threshold at 4 keeps the margin from it, where atan2's −0-ish angles fold to 0.
std::vector<double> phiDiffPseudoAngles() {
  const std::vector<double> angles = firstOfEachCell(MerlBrdf::kPhiDiffCells, std::nextafter(std::numbers::pi, 0.0),
                                                     [](double a) { return MerlBrdf::phiDiffIndex(a); });
  std::vector<double> thresholds;
  for (double a : angles) thresholds.push_back(pseudoAngle(std::sin(a), std::cos(a)));
  thresholds.push_back(2.0);
  for (double a : angles) thresholds.push_back(pseudoAngle(-std::sin(a), -std::cos(a)));
  thresholds.push_back(4.0);
  return thresholds;
}

class MerlCells {
 public:
  MerlCells()
      : thetaHalf_(halfAngleTangents(firstOfEachCell(MerlBrdf::kThetaHalfCells, kHalfPi,
                                                     [](double a) { return MerlBrdf::thetaHalfIndex(a); })),
                   1.0, kCellMargin),
        thetaDiff_(halfAngleTangents(firstOfEachCell(MerlBrdf::kThetaDiffCells, kHalfPi,
                                                     [](double a) { return MerlBrdf::thetaDiffIndex(a); })),
                   1.0, kCellMargin),
        phiDiff_(phiDiffPseudoAngles(), 4.5, kCellMargin) {}

  std::optional<std::size_t> cellOf(const HalfDiffVectors& v) const {
    const std::optional<uint32_t> h = thetaHalf_.cellOf(halfAngleTangent(v.rho, v.length, v.half.z));
    const Vec3d& d = v.diff;
    const double rhoDiff = std::sqrt(d.x * d.x + d.y * d.y);
    const std::optional<uint32_t> t =
        thetaDiff_.cellOf(halfAngleTangent(rhoDiff, std::sqrt(rhoDiff * rhoDiff + d.z * d.z), d.z));
    // d = 0 gives NaN, which has no cell.
    const std::optional<uint32_t> p = phiDiff_.cellOf(pseudoAngle(d.y, d.x));
    if (!(h && t && p)) return std::nullopt;
    const int phi = static_cast<int>(*p) % MerlBrdf::kPhiDiffCells;
    return MerlBrdf::flatIndex(static_cast<int>(*h), static_cast<int>(*t), phi);
  }

 private:
  ThresholdCells thetaHalf_, thetaDiff_, phiDiff_;
};

}  // namespace

std::size_t MerlBrdf::cellByAngles(const Vec3d& wo, const Vec3d& wi) {
  const HalfDiffAngles a = toHalfDiff(wo, wi, false);
  return flatIndex(thetaHalfIndex(a.thetaHalf), thetaDiffIndex(a.thetaDiff), phiDiffIndex(a.phiDiff));
}

std::size_t MerlBrdf::cellOf(const Vec3d& wo, const Vec3d& wi) {
  static const MerlCells cells;
  if (const std::optional<std::size_t> cell = cells.cellOf(halfDiffVectors(wo, wi))) return *cell;
  return cellByAngles(wo, wi);
}

Rgb MerlBrdf::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wi.z > 0 && wo.z > 0)) return {};
  if (interpolation_ == Interpolation::Nearest) return cell(cellOf(wo, wi));
  const HalfDiffAngles a = toHalfDiff(wo, wi, false);
  return evalHalfDiff(a.thetaHalf, a.thetaDiff, a.phiDiff);
}

std::vector<float> MerlBrdf::channel(int c) const {
  std::vector<float> values(kCells);
  for (std::size_t i = 0; i < kCells; ++i) values[i] = value(c, i);
  return values;
}

std::string MerlBrdf::addToKey(ContentHash& content) const {
  // Channel after channel, as the file (and the keys of tables cached before the interleaved
  // layout) has them; ContentHash streams, so chunks hash as the whole channel would.
  std::array<float, 4096> chunk;
  for (int c = 0; c < 3; ++c)
    for (std::size_t first = 0; first < kCells; first += chunk.size()) {
      const std::size_t n = std::min(chunk.size(), kCells - first);
      for (std::size_t i = 0; i < n; ++i) chunk[i] = values_[3 * (first + i) + c];
      content.values(std::span<const float>(chunk.data(), n));
    }
  return "interpolation=" + std::string(toString(interpolation_));
}

namespace {
constexpr EnumName<MerlBrdf::Interpolation> kInterpolationNames[] = {
    {MerlBrdf::Interpolation::Nearest, "nearest"}, {MerlBrdf::Interpolation::Trilinear, "trilinear"}};
}  // namespace

std::string_view toString(MerlBrdf::Interpolation interpolation) { return nameOf(kInterpolationNames, interpolation); }

MerlBrdf::Interpolation parseInterpolation(std::string_view name) {
  return valueNamed(kInterpolationNames, name, "interpolation");
}

Rgb MerlBrdf::evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const {
  if (interpolation_ == Interpolation::Nearest) {
    return cell(flatIndex(thetaHalfIndex(thetaHalf), thetaDiffIndex(thetaDiff), phiDiffIndex(phiDiff)));
  }
  // Trilinear on the cell-centred grid. θh is interpolated in √θh, the variable its cells are
  // uniform in, so the interpolation is symmetric in every cell.
  const Bracket h = clampedBracket(thetaHalfCoordinate(thetaHalf), kThetaHalfCells);
  const Bracket d = clampedBracket(thetaDiffCoordinate(thetaDiff), kThetaDiffCells);
  const double phiCoord = phiDiffCoordinate(phiDiff);
  const Bracket p = wrappedBracket(phiCoord == phiCoord ? phiCoord : 0.0, kPhiDiffCells);  // NaN → 0
  double sum[3] = {0, 0, 0};
  for (int a = 0; a < 2; ++a) {
    const double wa = a ? h.t : 1.0 - h.t;
    for (int b = 0; b < 2; ++b) {
      const double wb = wa * (b ? d.t : 1.0 - d.t);
      for (int c = 0; c < 2; ++c) {
        const double w = wb * (c ? p.t : 1.0 - p.t);
        const std::size_t index = flatIndex(a ? h.i1 : h.i0, b ? d.i1 : d.i0, c ? p.i1 : p.i0);
        const float* v = values_.get() + 3 * index;
        sum[0] += w * v[0];
        sum[1] += w * v[1];
        sum[2] += w * v[2];
      }
    }
  }
  return {static_cast<float>(sum[0] * kChannelScale[0]), static_cast<float>(sum[1] * kChannelScale[1]),
          static_cast<float>(sum[2] * kChannelScale[2])};
}

}  // namespace acdf

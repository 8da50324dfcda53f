#pragma once
// A measured isotropic BRDF in the MERL format (Matusik, Pfister, Brand & McMillan, "A
// Data-Driven Reflectance Model", SIGGRAPH 2003), read and evaluated as MERL's reference code
// BRDFRead.cpp does.
//
// The table is indexed by Rusinkiewicz angles (see coordinates.h): 90 θh × 90 θd × 180 φd cells,
// φh dropped (isotropy) and φd stored on [0, π) only (reciprocity: φd and φd + π are the same
// configuration with ωi and ωo swapped). θh is sampled densely near the specular peak: its cell
// is ⌊√(θh / (π/2)) · 90⌋, so cell k spans θh in [(k/90)², ((k+1)/90)²] · π/2.
//
// File format (.binary): three little-endian int32 dimensions whose product is 90·90·180, then
// three blocks of 90·90·180 little-endian float64 — red, green, blue — each in the order
// index = θh_idx·90·180 + θd_idx·180 + φd_idx. Physical values are the stored ones times the
// channel scales 1/1500, 1.15/1500, 1.66/1500. Like BRDFRead.cpp, only the product of the
// dimensions is checked (each must be positive); the layout is always the one above. Real files hold −1 in cells with
// no measurement (below the horizon); those read as 0 and are counted.
//
// Storage: the raw (unscaled) values as float, interleaved: red, green, blue of cell 0, then of
// cell 1, ... so a lookup reads 12 contiguous bytes, one cache line (rarely two), where three
// channel planes 5.8 MB apart would cost three misses. Float's seven digits are far finer than
// the measurement noise, and it halves the memory (17.5 MB, which fits a server's L3) and the
// cache traffic of eval(). The layout is in memory only: files, channel() and the table-cache key
// (addToKey) see the channels one after the other, as the file stores them.
// load(save(b)) reproduces b exactly; save(load(file)) rewrites −1 as 0 and values as their
// nearest float. Copies share the values (immutable): withInterpolation() is one more model of
// the same data, not a second 17.5 MB.
//
// As a BrdfModel, a MerlBrdf is the table evaluated with one Interpolation, chosen at
// construction (nearest, MERL's own lookup, by default).

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/coordinates.h"
#include "acdf/sampling/file_error.h"
#include "acdf/sampling/rgb.h"

namespace acdf {

class MerlBrdf final : public BrdfModel {
 public:
  static constexpr int kThetaHalfCells = 90;
  static constexpr int kThetaDiffCells = 90;
  static constexpr int kPhiDiffCells = 180;
  static constexpr std::size_t kCells = std::size_t{kThetaHalfCells} * kThetaDiffCells * kPhiDiffCells;
  // Stored value × scale = BRDF value (1/sr), per channel, as in BRDFRead.cpp.
  static constexpr std::array<double, 3> kChannelScale = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

  enum class Interpolation {
    Nearest,    // the cell holding the angles, exactly as MERL's lookup_brdf_val
    Trilinear,  // linear in (√θh, θd, φd) between cell centres
  };

  // From raw table values (file units, before the channel scales), kCells per channel in file
  // order. Negative values become 0 and are counted (negativeEntries()). Throws
  // std::invalid_argument for a wrong size or a NaN / Inf / beyond-float value, naming the
  // channel and index.
  MerlBrdf(std::span<const double> red, std::span<const double> green, std::span<const double> blue,
           Interpolation interpolation = Interpolation::Nearest);

  // Reads a .binary file with a single read of the whole file. Throws FileError naming the
  // file and the problem: missing file, directory, truncated header, wrong dimensions, truncated
  // data, extra trailing bytes, NaN or Inf (with channel and index).
  static MerlBrdf load(const std::filesystem::path& path, Interpolation interpolation = Interpolation::Nearest);

  // The same table evaluated with another interpolation (sharing the values).
  MerlBrdf withInterpolation(Interpolation interpolation) const;
  Interpolation interpolation() const { return interpolation_; }

  // Writes the .binary format (dimensions 90, 90, 180). The data go to a temporary file in the
  // same directory which is then renamed over `path`, so a failure never leaves a partial file
  // under `path` (an existing file there stays as it was). Throws FileError.
  void save(const std::filesystem::path& path) const;

  // Writes raw table values (file units, 3 · kCells in file order: red, green, blue blocks) as a
  // .binary file exactly, in double, −1 "no data" marks included — for generated tables, which
  // a MerlBrdf (float, negatives cleared) cannot carry. Same temporary + rename as save().
  // Throws std::invalid_argument for a wrong size or a NaN / Inf value, FileError for the file.
  static void saveRaw(const std::filesystem::path& path, std::span<const double> values);

  // The BRDF value for unit directions ωo, ωi in the local frame (z = normal). 0 unless both are
  // strictly above the horizon (z > 0): the table has no data below it, and at z = 0 the
  // cosine factor makes the value irrelevant. Symmetric in ωo, ωi.
  Rgb eval(const Vec3d& wo, const Vec3d& wi) const override;

  // The same from half/difference angles (φh is irrelevant); θh, θd beyond π/2 clamp to the
  // last cell, φd is any angle (folded by reciprocity). No horizon test: the caller has angles.
  Rgb evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const override;

  bool isotropic() const override { return true; }
  // Every stored value, and "interpolation=nearest" or "interpolation=trilinear": unlike the other
  // models' texts no model word, so MERL tables keep the keys cached ones were stored under.
  std::string addToKey(ContentHash& content) const override;

  // MERL's cell indices (theta_half_index, theta_diff_index, phi_diff_index), and the flat
  // index into a channel. One deliberate difference: φd is folded into [0, π) (φd ≥ π → φd − π,
  // negative → + π), so φd = π lands in cell 0 like φd = 0, where MERL clamps it into cell 179.
  static int thetaHalfIndex(double thetaHalf);
  static int thetaDiffIndex(double thetaDiff);
  static int phiDiffIndex(double phiDiff);
  static std::size_t flatIndex(int thetaHalfIdx, int thetaDiffIdx, int phiDiffIdx) {
    return (static_cast<std::size_t>(thetaHalfIdx) * kThetaDiffCells + thetaDiffIdx) * kPhiDiffCells + phiDiffIdx;
  }
  // The flat index of the cell holding (ωo, ωi), both above the horizon: by definition
  // flatIndex of the three indices of toHalfDiff(ωo, ωi)'s angles (cellByAngles), found without
  // atan2 unless a quantity lies within rounding reach of a cell boundary (threshold_cells.h).
  static std::size_t cellOf(const Vec3d& wo, const Vec3d& wi);
  static std::size_t cellByAngles(const Vec3d& wo, const Vec3d& wi);
  // The angles at a cell's centre (the centre in √θh for θh).
  static double thetaHalfCentre(int thetaHalfIdx);
  static double thetaDiffCentre(int thetaDiffIdx);
  static double phiDiffCentre(int phiDiffIdx);

  // Raw stored value of channel c (0 = red, 1 = green, 2 = blue) in cell `index` (file order),
  // negatives as 0.
  float value(int c, std::size_t index) const { return values_[3 * index + c]; }
  // All kCells raw values of channel c in file order: a copy out of the interleaved table.
  std::vector<float> channel(int c) const;
  // Every stored value, interleaved (3 · kCells: red, green, blue of cell 0, then of cell 1, ...).
  std::span<const float> interleavedValues() const { return {values_.get(), 3 * kCells}; }
  // How many stored values were negative (and are now 0), over all three channels. Negative as
  // floats: a double in (−7e-46, 0) rounds to −0 and is just 0.
  std::size_t negativeEntries() const { return negativeEntries_; }

 private:
  MerlBrdf(std::shared_ptr<const float[]> values, std::size_t negativeEntries, Interpolation interpolation)
      : values_(std::move(values)), negativeEntries_(negativeEntries), interpolation_(interpolation) {}

  Rgb cell(std::size_t index) const {
    const float* v = values_.get() + 3 * index;
    return {static_cast<float>(v[0] * kChannelScale[0]), static_cast<float>(v[1] * kChannelScale[1]),
            static_cast<float>(v[2] * kChannelScale[2])};
  }

  std::shared_ptr<const float[]> values_;  // 3 · kCells, interleaved: the rgb of cell 0, of cell 1, ...
  std::size_t negativeEntries_ = 0;
  Interpolation interpolation_ = Interpolation::Nearest;
};

// The one spelling of each interpolation, used by the command line, the scene format, the JSON
// outputs and the table cache keys: "nearest", "trilinear". parse throws std::invalid_argument
// for any other name.
std::string_view toString(MerlBrdf::Interpolation interpolation);
MerlBrdf::Interpolation parseInterpolation(std::string_view name);

}  // namespace acdf

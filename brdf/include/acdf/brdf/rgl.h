#pragma once
// A measured isotropic BRDF of the RGL material database (Dupuy & Jakob 2018, "An Adaptive
// Parameterization for Efficient Material Acquisition and Rendering"), read from its `.bsdf`
// tensor file (tensor_file.h) and evaluated as the paper, pbrt-v4's MeasuredBxDF and Mitsuba 3's
// `measured` plugin define it.
//
// Directions. The tables are conditioned on the direction the measurement (and a path tracer's
// sampling) starts from: pbrt's ωo, the viewer, which the paper and Mitsuba call ωi. Everything
// below writes ωo for it, in pbrt's order like every BrdfModel: eval(ωo, ωi) with ωi the light.
//
// Unit coordinates. Angles map to [0, 1] as u(θ) = √(θ / (π/2)) (so θ = u²·π/2, dense near the
// normal) and v(φ) = (φ + π) / 2π. A half vector ωm = normalize(ωo + ωi) has um = (u(θm), v(φm − φo))
// — relative to φo, the file being isotropic — and ωo has (u(θo), v(φo)).
//
// Fields (float32 unless said): theta_i [nθ] and phi_i [1] (the conditioning angles of ωo in
// radians; more than one phi_i is an anisotropic file, refused), ndf [rows, cols] the microfacet
// distribution D at um, sigma [rows, cols] the projected area σ(ωo) = ∫ ⟨ωo, ωm⟩ D(ωm) dωm at ωo's
// unit coordinates, vndf [1, nθ, rows, cols] the visible-NDF warp over um, luminance
// [1, nθ, R, C] the luminance warp, rgb [1, nθ, 3, R, C] (or spectra [1, nθ, nλ, R, C] with
// wavelengths [nλ] in nm) the reflectance ρ, and jacobian (uint8 [1]). The last four are given
// over the *sample* domain s ∈ [0, 1]²: the point the visible-NDF warp maps to um. Grids are
// vertex grids, interpolated bilinearly (and linearly between theta_i slices, clamped at the ends);
// rows run over the φ coordinate, columns over the θ coordinate (pbrt's point (x, y) is our
// (column, row)).
//
// Evaluation, with s = vndf⁻¹(um | θo) (Bilinear2D::invert):
//   jacobian = 1:  f(ωo, ωi) = ρ(s | θo) · D(um) / (4 σ(ωo) cos θi)
//   jacobian = 0:  f(ωo, ωi) = ρ(s | θo) / cos θi                  (ρ holds f·cosθi itself)
// ρ is clamped at 0 (interpolated spectra can dip below). f is 0 unless both directions are
// strictly above the horizon.
//
// Spectral files: each vertex's spectrum (linear between the file's wavelengths, constant beyond
// its ends) is integrated against the CIE 1931 2° colour matching functions and the CIE D65
// illuminant at 5 nm, 380–780 nm, normalised so that ρ ≡ 1 has Y = 1, and XYZ taken to linear
// sRGB (Rec. 709 primaries, D65 white, IEC 61966-2-1's matrix): the reflectance under daylight,
// in the colour space of every other Rgb here. Tables: CIE 015:2018 (as tabulated by CVRL).
//
// Validation at load: every field above present with its dtype and consistent extents (2 or more
// vertices per grid axis), theta_i strictly increasing in [0, π/2], values finite, ndf, vndf and
// luminance >= 0, sigma > 0 (it divides), no all-zero vndf or luminance slice (it could not be
// sampled). Problems throw FileError naming the file and the field.

#include <array>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/tensor_file.h"
#include "acdf/sampling/bilinear_2d.h"

namespace acdf {

// A vertex grid over [0, 1]² (rows × columns, row-major), bilinearly interpolated, not
// normalised: the format's ndf, sigma and reflectance tables.
struct VertexGrid {
  uint32_t rows = 0, columns = 0;
  std::vector<float> values;
  // x[0] along rows, x[1] along columns, both clamped into [0, 1].
  double eval(double x0, double x1, std::size_t offset = 0) const;
};

class RglBrdf final : public BrdfModel {
 public:
  // From the fields of a tensor file read from `file` (named in errors). Throws FileError.
  RglBrdf(const TensorFile& tensors, const std::string& file);
  static RglBrdf load(const std::filesystem::path& path);
  // True when the file starts with the tensor file magic (how the tools recognise `.bsdf` files).
  static bool isRglFile(const std::filesystem::path& path);

  Rgb eval(const Vec3d& wo, const Vec3d& wi) const override;
  bool isotropic() const override { return true; }
  // Every table value and "rgl jacobian=…".
  std::string addToKey(ContentHash& content) const override;
  // Its warps (RglBrdfSampler).
  std::shared_ptr<const BrdfSampler> nativeSampler(const std::shared_ptr<const BrdfModel>& self) const override;

  // Unit coordinates (see above), in Bilinear2D's order: {row = v(φ), column = u(θ)}.
  static std::array<float, 2> unitCoordinates(double theta, double phi);
  static double elevation(const Vec3d& d);  // θ of a unit vector, accurate near the normal
  // The warps' conditioning parameters for ωo: {φo, θo}.
  static std::array<float, 2> parameters(const Vec3d& wo);
  // The half vector at unit coordinates um (relative to φo).
  static Vec3d halfVector(std::span<const float> um, double phiOut);

  const Bilinear2D& luminanceWarp() const { return luminance_; }
  const Bilinear2D& vndfWarp() const { return vndf_; }
  // The format's sampling tables (the luminance and visible-NDF warps) as Bilinear2D stores them.
  std::size_t warpBytes() const { return luminance_.bytes() + vndf_.bytes(); }
  const std::string& description() const { return description_; }
  bool spectral() const { return spectral_; }
  bool jacobian() const { return jacobian_; }
  const std::vector<float>& thetaIn() const { return thetaIn_; }

 private:
  std::vector<float> thetaIn_;
  bool spectral_;  // spectra + wavelengths instead of rgb
  VertexGrid ndf_, sigma_;
  Bilinear2D vndf_, luminance_;
  VertexGrid reflectance_;  // nθ × 3 stacked grids of R × C vertices: the rgb (or converted spectra)
  bool jacobian_;
  std::string description_;
  CacheKey warpDigest_;  // of the vndf and luminance fields, for addToKey()
};

}  // namespace acdf

#pragma once
// Reflectance spectra to linear sRGB, for spectral RGL files (rgl.h).
//
// Convention: the reflectance ρ(λ) under the CIE standard illuminant D65, observed with the CIE
// 1931 2° colour matching functions, both tabulated at 5 nm from 380 to 780 nm (CIE 015:2018,
// as distributed by CVRL, cvrl.org) and summed with 5 nm weights:
//   X = Σ ρ(λ) x̄(λ) D65(λ) / Σ ȳ(λ) D65(λ)   (Y, Z alike),
// so ρ ≡ 1 gives Y = 1 and the D65 white point; then XYZ → linear sRGB (Rec. 709 primaries, D65
// white) with IEC 61966-2-1's matrix. ρ ≡ 1 therefore maps to (1, 1, 1) up to the tables'
// rounding (about 1e-3).

#include <array>
#include <span>

namespace acdf {

// ρ given at strictly increasing wavelengths (nm), linear between them and constant beyond the
// first and the last. Channels may be negative for saturated spectra (outside the sRGB gamut).
std::array<double, 3> reflectanceToLinearSrgb(std::span<const float> wavelengths, std::span<const double> reflectance);

}  // namespace acdf

#pragma once
// An RGL `.bsdf` file (rgl.h) of an analytic GGX model (analytic.h), built the way the paper
// parameterises a measurement (Dupuy & Jakob 2018, §4), so that tests and users have `.bsdf`
// files with a known closed form (the RGL database's may not be redistributed here):
//
//   ndf [2, N]        D(θm) = α² / (π (cos²θm (α² − 1) + 1)²) at θm = u²·π/2, u = c / (N − 1)
//   sigma [2, N]      σ(θ) = ∫ ⟨ω, ωm⟩ D dωm = (cosθ + √(cos²θ + α² sin²θ)) / 2 (Smith GGX)
//   theta_i [nθ]      θo = k / (nθ − 1) · π/2, phi_i = [0]
//   vndf [1, nθ, V, V]  the visible NDF ⟨ωo, ωm⟩₊ D(ωm) / σ(ωo) as a density over um, i.e. times
//                     dωm/dum = 2π² u sinθm, at um = (r, c) / (V − 1)
//   rgb [1, nθ, 3, R, R]  ρ at the sample-domain vertices s = (r, c) / (R − 1): um = the vndf
//                     warp's sample(s) (Bilinear2D, the one the reader builds), ωi = reflect(ωo, ωm),
//                     ρ = f(ωo, ωi) · 4 σ(ωo) cosθi / D(ωm) (for the conductor F(ωi·ωm) G1(ωi)),
//                     0 where ωi is below the horizon
//   luminance [1, nθ, R, R]  the luminance of ρ (Rec. 709 weights)
//   jacobian [1] = 1, description, version [1, 0]
//
// With `spectral`, spectra [1, nθ, nλ, R, R] at wavelengths 360, 370, …, 830 nm replace rgb:
// each vertex a flat (grey) spectrum equal to ρ's luminance, so a reader converting it (spectrum.h)
// must give ρ's luminance in every channel.

#include <cstdint>
#include <string>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/tensor_file.h"

namespace acdf {

struct RglSynthesisOptions {
  uint32_t thetaIn = 8;       // conditioning angles, >= 1
  uint32_t ndf = 128;         // vertices of ndf and sigma along θ, >= 2
  uint32_t vndf = 128;        // vertices of the vndf warp per axis, >= 2
  uint32_t reflectance = 32;  // vertices of the luminance and rgb tables per axis, >= 2
  bool spectral = false;
};

// Throws std::invalid_argument for counts out of range or a warp slice with no mass.
TensorFile synthesizeRgl(const AnalyticBrdf& model, const RglSynthesisOptions& options, const std::string& description);

}  // namespace acdf

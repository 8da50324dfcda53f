#include "acdf/brdf/rgl_synthesis.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/rgl.h"
#include "acdf/sampling/bilinear_2d.h"

namespace acdf {

namespace {

constexpr double kPi = std::numbers::pi;

double ggxSigma(double alpha, double cosTheta) {
  const double sin2 = std::max(0.0, 1.0 - cosTheta * cosTheta);
  return 0.5 * (cosTheta + std::sqrt(cosTheta * cosTheta + alpha * alpha * sin2));
}

double uToTheta(double u) { return u * u * (kPi / 2); }

}  // namespace

TensorFile synthesizeRgl(const AnalyticBrdf& model, const RglSynthesisOptions& o, const std::string& description) {
  if (o.thetaIn < 1 || o.ndf < 2 || o.vndf < 2 || o.reflectance < 2 || o.thetaIn > 1024 || o.ndf > 65536 ||
      o.vndf > 4096 || o.reflectance > 4096)
    throw std::invalid_argument(
        "RGL synthesis: theta_i in [1, 1024], ndf in [2, 65536], vndf and reflectance in [2, 4096]");
  const double alpha = model.alpha();
  TensorFile file;
  const unsigned char version[8] = {1, 0, 0, 0, 0, 0, 0, 0};
  file.add("version", {TensorField::Type::UInt32, {2}, {version, version + 8}});
  file.add("description",
           TensorField::bytes({description.size()},
                              {reinterpret_cast<const unsigned char*>(description.data()), description.size()}));
  const float phiIn[1] = {0.0f};
  file.add("phi_i", TensorField::floats({1}, phiIn));
  std::vector<float> thetaIn(o.thetaIn);
  for (uint32_t k = 0; k < o.thetaIn; ++k)
    thetaIn[k] = o.thetaIn == 1 ? 0.0f : static_cast<float>(k * (kPi / 2) / (o.thetaIn - 1));
  file.add("theta_i", TensorField::floats({o.thetaIn}, thetaIn));

  std::vector<float> ndf(2 * o.ndf), sigma(2 * o.ndf);
  for (uint32_t c = 0; c < o.ndf; ++c) {
    const double cosTheta = std::cos(uToTheta(static_cast<double>(c) / (o.ndf - 1)));
    ndf[c] = ndf[o.ndf + c] = static_cast<float>(ggxDistribution(alpha, cosTheta));
    sigma[c] = sigma[o.ndf + c] = static_cast<float>(ggxSigma(alpha, cosTheta));
  }
  file.add("sigma", TensorField::floats({2, o.ndf}, sigma));
  file.add("ndf", TensorField::floats({2, o.ndf}, ndf));

  const std::size_t vSlice = std::size_t{o.vndf} * o.vndf, rSlice = std::size_t{o.reflectance} * o.reflectance;
  std::vector<float> vndf(o.thetaIn * vSlice), luminance(o.thetaIn * rSlice), rgb(o.thetaIn * 3 * rSlice);
  for (uint32_t k = 0; k < o.thetaIn; ++k) {
    const Vec3d wo = sphericalDirection(thetaIn[k], 0.0);
    const double sigmaOut = ggxSigma(alpha, wo.z);
    float* slice = vndf.data() + k * vSlice;
    for (uint32_t r = 0; r < o.vndf; ++r)
      for (uint32_t c = 0; c < o.vndf; ++c) {
        const float um[2] = {static_cast<float>(r) / (o.vndf - 1), static_cast<float>(c) / (o.vndf - 1)};
        const Vec3d wm = RglBrdf::halfVector(um, 0.0);
        const double theta = uToTheta(um[1]);
        const double visible = std::max(0.0, dot(wo, wm)) * ggxDistribution(alpha, wm.z) / sigmaOut;
        slice[std::size_t{r} * o.vndf + c] = static_cast<float>(visible * 2 * kPi * kPi * um[1] * std::sin(theta));
      }
    // The warp the reader will build from this slice, to place the reflectance vertices.
    const Bilinear2D warp(std::span<const float>(slice, vSlice), o.vndf, o.vndf);
    for (uint32_t r = 0; r < o.reflectance; ++r)
      for (uint32_t c = 0; c < o.reflectance; ++c) {
        const float s[2] = {static_cast<float>(r) / (o.reflectance - 1), static_cast<float>(c) / (o.reflectance - 1)};
        const SampleND um = warp.sample(s);
        const Vec3d wm = RglBrdf::halfVector(um.point(), 0.0);
        const Vec3d wi = normalize(reflect(wo, wm));
        std::array<double, 3> rho = {0, 0, 0};
        if (wi.z > 0) {
          // ρ's limit at grazing ωo (where f itself is 0 by the horizon rule) from just above it.
          const HalfDiffAngles a = toHalfDiff(wo.z > 1e-4 ? wo : sphericalDirection(kPi / 2 - 1e-4, 0.0), wi);
          const std::array<double, 3> f = model.closedForm(a.thetaHalf, a.thetaDiff, a.phiDiff);
          const double scale = 4.0 * sigmaOut * wi.z / ggxDistribution(alpha, wm.z);
          for (int ch = 0; ch < 3; ++ch) rho[ch] = f[ch] * scale;
        }
        const std::size_t i = std::size_t{r} * o.reflectance + c;
        for (int ch = 0; ch < 3; ++ch) rgb[(k * 3 + ch) * rSlice + i] = static_cast<float>(rho[ch]);
        luminance[k * rSlice + i] = static_cast<float>(0.2126 * rho[0] + 0.7152 * rho[1] + 0.0722 * rho[2]);
      }
  }
  file.add("vndf", TensorField::floats({1, o.thetaIn, o.vndf, o.vndf}, vndf));
  file.add("luminance", TensorField::floats({1, o.thetaIn, o.reflectance, o.reflectance}, luminance));
  if (o.spectral) {
    std::vector<float> wavelengths;
    for (int l = 360; l <= 830; l += 10) wavelengths.push_back(static_cast<float>(l));
    std::vector<float> spectra(o.thetaIn * wavelengths.size() * rSlice);
    for (uint32_t k = 0; k < o.thetaIn; ++k)
      for (std::size_t l = 0; l < wavelengths.size(); ++l)
        for (std::size_t i = 0; i < rSlice; ++i)
          spectra[(k * wavelengths.size() + l) * rSlice + i] = luminance[k * rSlice + i];
    file.add("wavelengths", TensorField::floats({wavelengths.size()}, wavelengths));
    file.add("spectra", TensorField::floats({1, o.thetaIn, wavelengths.size(), o.reflectance, o.reflectance}, spectra));
  } else {
    file.add("rgb", TensorField::floats({1, o.thetaIn, 3, o.reflectance, o.reflectance}, rgb));
  }
  const unsigned char jacobian[1] = {1};
  file.add("jacobian", TensorField::bytes({1}, jacobian));
  return file;
}

}  // namespace acdf

#include "acdf/brdf/rgl.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include "acdf/brdf/rgl_sampler.h"
#include "acdf/brdf/spectrum.h"
#include "acdf/sampling/file_error.h"

namespace acdf {

namespace {

constexpr double kPi = std::numbers::pi;

// Field access with the file's error messages.
class Fields {
 public:
  Fields(const TensorFile& tensors, const std::string& file) : tensors_(tensors), file_(file) {}

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw FileError(file_, "field '" + field + "': " + problem);
  }
  const TensorField& get(const std::string& name, TensorField::Type type, std::size_t dims) const {
    const TensorField* f = tensors_.find(name);
    if (!f) throw FileError(file_, "field '" + name + "' is missing (not an RGL BRDF file?)");
    if (f->type != type)
      fail(name,
           std::string("dtype is ") + TensorField::typeName(f->type) + ", expected " + TensorField::typeName(type));
    if (f->shape.size() != dims) {
      fail(name, std::to_string(f->shape.size()) + " dimensions, expected " + std::to_string(dims));
    }
    return *f;
  }
  bool has(const std::string& name) const { return tensors_.find(name) != nullptr; }
  // Finite float32 values of a field, its extents checked against `shape` (0 = any, >= 2).
  std::vector<float> floats(const std::string& name, const std::vector<uint64_t>& shape) const {
    const TensorField& f = get(name, TensorField::Type::Float32, shape.size());
    for (std::size_t d = 0; d < shape.size(); ++d) {
      if (shape[d] == 0 ? f.shape[d] < 2 : f.shape[d] != shape[d]) {
        fail(name, "extent " + std::to_string(f.shape[d]) + " in dimension " + std::to_string(d) + ", expected " +
                       (shape[d] == 0 ? std::string("at least 2") : std::to_string(shape[d])));
      }
    }
    std::vector<float> v(f.elements());
    std::memcpy(v.data(), f.data.data(), v.size() * sizeof(float));
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i]))
        fail(name, (std::isnan(v[i]) ? "NaN" : "Inf") + std::string(" at index ") + std::to_string(i));
    return v;
  }
  void nonNegative(const std::string& name, std::span<const float> v) const {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (v[i] < 0) fail(name, "negative value " + std::to_string(v[i]) + " at index " + std::to_string(i));
  }
  // The extents of a field already checked by floats().
  const std::vector<uint64_t>& shape(const std::string& name) const { return tensors_.find(name)->shape; }

 private:
  const TensorFile& tensors_;
  const std::string& file_;
};

std::vector<float> thetaInValues(const Fields& f) {
  const TensorField& field = f.get("theta_i", TensorField::Type::Float32, 1);
  if (field.shape[0] == 0) f.fail("theta_i", "no values");
  std::vector<float> v = f.floats("theta_i", {field.shape[0]});
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!(v[i] >= 0 && v[i] <= static_cast<float>(kPi / 2) + 1e-6f))
      f.fail("theta_i", "value " + std::to_string(v[i]) + " outside [0, pi/2]");
    if (i > 0 && !(v[i - 1] < v[i])) f.fail("theta_i", "values not strictly increasing at index " + std::to_string(i));
  }
  const TensorField& phi = f.get("phi_i", TensorField::Type::Float32, 1);
  if (phi.shape[0] != 1) {
    f.fail("phi_i", std::to_string(phi.shape[0]) +
                        " values: an anisotropic material; only isotropic RGL files (one phi_i) are supported");
  }
  f.floats("phi_i", {1});
  return v;
}

VertexGrid grid(const Fields& f, const std::string& name, bool positive) {
  std::vector<float> v = f.floats(name, {0, 0});
  f.nonNegative(name, v);
  if (positive) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!(v[i] > 0)) f.fail(name, "zero at index " + std::to_string(i) + " (sigma divides the BRDF)");
  }
  const auto& s = f.shape(name);
  return {static_cast<uint32_t>(s[0]), static_cast<uint32_t>(s[1]), std::move(v)};
}

// A conditioned warp [1, nθ, rows, cols]: non-negative, every slice with mass.
Bilinear2D warp(const Fields& f, const std::string& name, const std::vector<float>& thetaIn) {
  const std::vector<float> v = f.floats(name, {1, thetaIn.size(), 0, 0});
  f.nonNegative(name, v);
  const auto& s = f.shape(name);
  const std::size_t slice = s[2] * s[3];
  if (s[2] > (1u << 16) || s[3] > (1u << 16)) f.fail(name, "more than 65536 vertices per axis");
  for (std::size_t k = 0; k < thetaIn.size(); ++k) {
    if (std::all_of(v.begin() + k * slice, v.begin() + (k + 1) * slice, [](float x) { return x == 0; }))
      f.fail(name, "slice " + std::to_string(k) + " (theta_i " + std::to_string(thetaIn[k]) + ") is zero everywhere");
  }
  try {
    return Bilinear2D(v, static_cast<uint32_t>(s[2]), static_cast<uint32_t>(s[3]), {{0.0f}, thetaIn});
  } catch (const std::invalid_argument& e) {
    f.fail(name, e.what());
  }
}

// rgb [1, nθ, 3, R, C], or spectra [1, nθ, nλ, R, C] converted to it; R × C as luminance's.
VertexGrid reflectance(const Fields& f, std::size_t thetaCount, const Bilinear2D& luminance, bool spectral) {
  const uint64_t rows = luminance.rows(), columns = luminance.columns();
  if (!spectral)
    return {static_cast<uint32_t>(rows), static_cast<uint32_t>(columns),
            f.floats("rgb", {1, thetaCount, 3, rows, columns})};
  if (!f.has("spectra")) f.get("rgb", TensorField::Type::Float32, 5);  // names the missing field
  const TensorField& w = f.get("wavelengths", TensorField::Type::Float32, 1);
  if (w.shape[0] == 0) f.fail("wavelengths", "no values");
  const std::vector<float> lambda = f.floats("wavelengths", {w.shape[0]});
  for (std::size_t i = 1; i < lambda.size(); ++i)
    if (!(lambda[i - 1] < lambda[i])) f.fail("wavelengths", "not strictly increasing at index " + std::to_string(i));
  const std::vector<float> spectra = f.floats("spectra", {1, thetaCount, lambda.size(), rows, columns});
  const std::size_t vertices = rows * columns;
  std::vector<float> rgb(thetaCount * 3 * vertices);
  std::vector<double> spectrum(lambda.size());
  for (std::size_t k = 0; k < thetaCount; ++k)
    for (std::size_t i = 0; i < vertices; ++i) {
      for (std::size_t l = 0; l < lambda.size(); ++l) spectrum[l] = spectra[(k * lambda.size() + l) * vertices + i];
      const std::array<double, 3> c = reflectanceToLinearSrgb(lambda, spectrum);
      for (int ch = 0; ch < 3; ++ch) rgb[(k * 3 + ch) * vertices + i] = static_cast<float>(c[ch]);
    }
  return {static_cast<uint32_t>(rows), static_cast<uint32_t>(columns), std::move(rgb)};
}

bool jacobianFlag(const Fields& f) {
  const TensorField& j = f.get("jacobian", TensorField::Type::UInt8, 1);
  if (j.shape[0] != 1) f.fail("jacobian", std::to_string(j.shape[0]) + " values, expected 1");
  return j.data[0] != 0;
}

std::string descriptionText(const TensorFile& tensors) {
  const TensorField* d = tensors.find("description");
  if (!d || d->type != TensorField::Type::UInt8) return {};
  return {d->data.begin(), d->data.end()};
}

// The interval of `values` (strictly increasing) holding p and the weight of its upper end, as
// Bilinear2D blends its parameters: clamped at the ends, NaN takes the first value.
std::pair<std::size_t, double> bracket(const std::vector<float>& values, double p) {
  if (values.size() == 1 || !(p > values.front())) return {0, 0.0};
  if (p >= values.back()) return {values.size() - 2, 1.0};
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(values.begin(), values.end(), p) - values.begin()) - 1;
  return {i, (p - values[i]) / (static_cast<double>(values[i + 1]) - values[i])};
}

}  // namespace

double VertexGrid::eval(double x0, double x1, std::size_t offset) const {
  const auto position = [](double x, uint32_t n, uint32_t& i) {
    const double g = std::clamp(x == x ? x : 0.0, 0.0, 1.0) * (n - 1);
    i = std::min(static_cast<uint32_t>(g), n - 2);
    return g - i;
  };
  uint32_t r, c;
  const double t0 = position(x0, rows, r), t1 = position(x1, columns, c);
  const float* v = values.data() + offset + std::size_t{r} * columns + c;
  return (1 - t0) * ((1 - t1) * v[0] + t1 * v[1]) + t0 * ((1 - t1) * v[columns] + t1 * v[columns + 1]);
}

RglBrdf::RglBrdf(const TensorFile& tensors, const std::string& file)
    : thetaIn_(thetaInValues(Fields(tensors, file))),
      spectral_(!tensors.find("rgb") && tensors.find("spectra")),
      ndf_(grid(Fields(tensors, file), "ndf", false)),
      sigma_(grid(Fields(tensors, file), "sigma", true)),
      vndf_(warp(Fields(tensors, file), "vndf", thetaIn_)),
      luminance_(warp(Fields(tensors, file), "luminance", thetaIn_)),
      reflectance_(reflectance(Fields(tensors, file), thetaIn_.size(), luminance_, spectral_)),
      jacobian_(jacobianFlag(Fields(tensors, file))),
      description_(descriptionText(tensors)) {
  ContentHash warps;
  for (const char* name : {"vndf", "luminance"}) {
    const TensorField& f = *tensors.find(name);
    for (uint64_t e : f.shape) warps.number(e);
    warps.values(std::span<const unsigned char>(f.data));
  }
  warpDigest_ = warps.digest();
}

RglBrdf RglBrdf::load(const std::filesystem::path& path) { return RglBrdf(TensorFile::load(path), path.string()); }

bool RglBrdf::isRglFile(const std::filesystem::path& path) {
  unsigned char head[TensorFile::kMagicBytes] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head), sizeof head);
  return in.gcount() == sizeof head && TensorFile::hasMagic(head);
}

double RglBrdf::elevation(const Vec3d& d) {
  // 2 asin(|d − z| / 2): no acos cancellation near the normal.
  const double dist = std::sqrt(d.x * d.x + d.y * d.y + (d.z - 1) * (d.z - 1));
  return 2.0 * std::asin(std::min(0.5 * dist, 1.0));
}

std::array<float, 2> RglBrdf::unitCoordinates(double theta, double phi) {
  double v = (phi + kPi) / (2 * kPi);
  v -= std::floor(v);
  return {static_cast<float>(v), static_cast<float>(std::sqrt(std::max(theta, 0.0) * (2 / kPi)))};
}

std::array<float, 2> RglBrdf::parameters(const Vec3d& wo) {
  return {static_cast<float>(std::atan2(wo.y, wo.x)), static_cast<float>(elevation(wo))};
}

Vec3d RglBrdf::halfVector(std::span<const float> um, double phiOut) {
  const double u = um[1], theta = u * u * (kPi / 2), phi = (2.0 * um[0] - 1.0) * kPi + phiOut;
  return sphericalDirection(theta, phi);
}

Rgb RglBrdf::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wo.z > 0 && wi.z > 0)) return {};
  const Vec3d sum = wo + wi;
  const Vec3d wm = sum * (1.0 / length(sum));
  const std::array<float, 2> params = parameters(wo);
  const std::array<float, 2> um = unitCoordinates(elevation(wm), std::atan2(wm.y, wm.x) - params[0]);
  const std::array<float, 2> s = vndf_.invert(params, um);
  double scale = 1.0 / wi.z;
  if (jacobian_) {
    const std::array<float, 2> uo = unitCoordinates(params[1], params[0]);
    scale *= ndf_.eval(um[0], um[1]) / (4.0 * sigma_.eval(uo[0], uo[1]));
  }
  const auto [k, t] = bracket(thetaIn_, params[1]);
  const std::size_t grid = std::size_t{reflectance_.rows} * reflectance_.columns;
  // In double, then held to float's range: a file's extreme (finite) values, or ωi a denormal above
  // the horizon, can exceed it; 0 · ∞ (no reflectance there) is 0.
  constexpr double kLargest = std::numeric_limits<float>::max();
  float rgb[3];
  for (int c = 0; c < 3; ++c) {
    double rho = (1 - t) * reflectance_.eval(s[0], s[1], (k * 3 + c) * grid);
    if (t > 0) rho += t * reflectance_.eval(s[0], s[1], ((k + 1) * 3 + c) * grid);
    const double value = std::max(rho, 0.0) * scale;
    rgb[c] = static_cast<float>(value < kLargest ? value : value >= kLargest ? kLargest : 0.0);
  }
  return {rgb[0], rgb[1], rgb[2]};
}

std::string RglBrdf::addToKey(ContentHash& content) const {
  content.values(std::span<const float>(thetaIn_));
  for (const VertexGrid* g : {&ndf_, &sigma_, &reflectance_}) {
    content.number(g->rows).number(g->columns);
    content.values(std::span<const float>(g->values));
  }
  // The warps' input values, hashed when they were read.
  content.number(warpDigest_.high).number(warpDigest_.low);
  return std::string("rgl jacobian=") + (jacobian_ ? "1" : "0");
}

std::shared_ptr<const BrdfSampler> RglBrdf::nativeSampler(const std::shared_ptr<const BrdfModel>& self) const {
  checkIsSelf(*this, self);
  return std::make_shared<const RglBrdfSampler>(std::static_pointer_cast<const RglBrdf>(self));
}

}  // namespace acdf

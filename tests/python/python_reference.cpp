// The C++ side of the Python module's bit-for-bit test (test_reference.py): computes samples,
// densities and inverses of fixed tables on fixed inputs with the libraries alone, and writes the
// inputs and the results as raw little-endian arrays (<name>.f32 / <name>.f64) into a directory,
// with the generated environment map (sky.exr) and MERL file (gold.binary) the Python side loads.
//
// Usage: python_reference OUTPUT_DIRECTORY
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/image_file.h"
#include "acdf/fixtures/fixtures.h"
#include "acdf/sampling/adaptive_cdf_1d.h"
#include "acdf/sampling/alias_table_1d.h"
#include "acdf/sampling/cascade.h"
#include "acdf/sampling/piecewise_constant_1d.h"
#include "acdf/sampling/rng.h"
#include "acdf/sampling/sphere.h"

namespace fs = std::filesystem;
using namespace acdf;

namespace {

fs::path out;

template <class T>
void write(const std::string& name, const std::vector<T>& values) {
  const char* ext = sizeof(T) == 4 ? ".f32" : ".f64";
  std::ofstream f(out / (name + ext), std::ios::binary);
  f.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(T)));
  if (!f) throw std::runtime_error("cannot write " + name);
}

std::vector<float> variates(std::size_t n, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<float> u(n);
  for (float& x : u) x = rng.nextFloat();
  u[0] = 0.0f;  // the edges of [0, 1)
  u[1] = kOneMinusEpsilon;
  return u;
}

void oneDimensional() {
  const uint32_t dims[] = {257};
  const std::vector<float> f = fixtures::peakedSun(dims);
  write("f1d", f);
  const std::vector<float> u = variates(4096, 11);
  write("u1d", u);
  const PiecewiseConstant1D pc(f, -1.0f, 3.0f);
  const AdaptiveCdf1D ad(f, -1.0f, 3.0f, {.epsilon = 1e-3});
  const AliasTable1D al(f, -1.0f, 3.0f);
  std::vector<float> x, pdf, inv;
  auto run = [&](const auto& t, const std::string& name, bool invertible) {
    x.clear(), pdf.clear(), inv.clear();
    for (float v : u) {
      const Sample1D s = t.sample(v);
      x.push_back(s.x);
      pdf.push_back(s.pdf);
      if constexpr (requires { t.invert(0.0f); }) inv.push_back(t.invert(s.x));
    }
    write(name + "_x", x);
    write(name + "_pdf", pdf);
    if (invertible) write(name + "_invert", inv);
  };
  run(pc, "pc", true);
  run(ad, "ad", true);
  run(al, "al", false);
}

void cascades() {
  // 2D adaptive on (θ, φ)-like domains; 3D with one conditioning axis, uniform then adaptive.
  const uint32_t dims2[] = {48, 40};
  const std::vector<float> v2 = fixtures::smooth(dims2);
  write("c2_values", v2);
  CascadeOptions o2;
  o2.simplify.epsilon = 1e-3;
  const Cascade c2(v2, {GridAxis(48, 0.0f, 3.14159265f), GridAxis(40, 0.0f, 6.28318531f)}, o2);
  const uint32_t dims3[] = {6, 16, 24};
  const std::vector<float> v3 = fixtures::random(dims3, 5);
  write("c3_values", v3);
  CascadeOptions o3;
  o3.conditioningDims = 1;
  o3.methods = {DimensionMethod::Uniform, DimensionMethod::Adaptive};
  o3.simplify.epsilon = 5e-3;
  const Cascade c3(v3, {GridAxis(6), GridAxis(16), GridAxis(24)}, o3);

  const std::size_t n = 4096;
  const std::vector<float> u = variates(2 * n, 12), condition = variates(n, 13);
  write("c_u", u);
  write("c3_condition", condition);
  std::vector<float> x2, pdf2, inv2, x3, pdf3, inv3;
  for (std::size_t i = 0; i < n; ++i) {
    const std::span<const float> ui(&u[2 * i], 2), ci(&condition[i], 1);
    const SampleND a = c2.sample(ui);
    x2.insert(x2.end(), a.x.begin(), a.x.begin() + 2);
    pdf2.push_back(c2.pdf(a.point()));
    float back[2];
    c2.invert({}, a.point(), back);
    inv2.insert(inv2.end(), back, back + 2);
    const SampleND b = c3.sample(ci, ui);
    x3.insert(x3.end(), b.x.begin(), b.x.begin() + 2);
    pdf3.push_back(b.pdf);
    c3.invert(ci, b.point(), back);
    inv3.insert(inv3.end(), back, back + 2);
  }
  write("c2_x", x2);
  write("c2_pdf", pdf2);
  write("c2_invert", inv2);
  write("c3_x", x3);
  write("c3_pdf", pdf3);
  write("c3_invert", inv3);
  write("c_bytes", std::vector<double>{double(c2.bytes()), double(c3.bytes())});
}

void environment() {
  const uint32_t width = 128, height = 64;
  const std::vector<float> luminance = fixtures::sunAndSky(width, height);
  Image image;
  image.width = width, image.height = height, image.channels = 3;
  for (float l : luminance) image.pixels.insert(image.pixels.end(), {l, 0.8f * l, 0.6f * l});
  writeExr((out / "sky.exr").string(), image);
  auto map = std::make_shared<const EnvironmentMap>(EnvironmentMap::load((out / "sky.exr").string()));
  const std::size_t n = 4096;
  const std::vector<float> u = variates(2 * n, 14);
  write("env_u", u);
  EnvironmentLightOptions options;
  options.worldFromMap = Rotation::aboutY(30.0 * 3.14159265358979323846 / 180.0);
  options.scale = 2.0f;
  const EnvironmentLight light(map, options);
  std::vector<double> dirs, pdf, pdfAt;
  std::vector<float> radiance;
  for (std::size_t i = 0; i < n; ++i) {
    const LightSample s = light.sample({}, u[2 * i], u[2 * i + 1]);
    dirs.insert(dirs.end(), {s.direction.x, s.direction.y, s.direction.z});
    radiance.insert(radiance.end(), {s.radiance.r, s.radiance.g, s.radiance.b});
    pdf.push_back(s.pdf);
    pdfAt.push_back(light.pdf({}, s.direction));
  }
  write("env_dirs", dirs);
  write("env_radiance", radiance);
  write("env_pdf", pdf);
  write("env_pdf_at", pdfAt);
}

void brdf() {
  const std::vector<double> table = AnalyticBrdf::preset("gold").merlTable();
  MerlBrdf::saveRaw(out / "gold.binary", table);
  auto model = std::make_shared<const MerlBrdf>(MerlBrdf::load(out / "gold.binary"));
  TabulatedBrdfOptions options;
  options.layout = TabulatedBrdfOptions::Layout::Isotropic;
  options.thetaOutCells = 16;
  options.thetaHalfCells = 64;
  options.phiHalfCells = 16;
  const TabulatedBrdfSampler sampler(model, options);
  const std::size_t n = 4096;
  const std::vector<float> u = variates(2 * n, 15), angles = variates(n, 16);
  write("brdf_u", u);
  std::vector<double> wo, wi, pdf, pdfAt;
  std::vector<float> weight, f;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d o = sphericalDirection(1.4 * angles[i], 6.0 * angles[i]);
    wo.insert(wo.end(), {o.x, o.y, o.z});
    const BrdfSample s = sampler.sample(o, u[2 * i], u[2 * i + 1]);
    wi.insert(wi.end(), {s.wi.x, s.wi.y, s.wi.z});
    weight.insert(weight.end(), {s.weight.r, s.weight.g, s.weight.b});
    pdf.push_back(s.pdf);
    pdfAt.push_back(sampler.pdf(o, s.wi));
    const Rgb v = sampler.eval(o, s.wi);
    f.insert(f.end(), {v.r, v.g, v.b});
  }
  write("brdf_wo", wo);
  write("brdf_wi", wi);
  write("brdf_weight", weight);
  write("brdf_pdf", pdf);
  write("brdf_pdf_at", pdfAt);
  write("brdf_eval", f);
  write("brdf_bytes", std::vector<double>{double(sampler.bytes())});
}

// A 64 x 128 map of 8 x 8 constant blocks saved in ProPhoto RGB with its D50 white (as Photoshop
// saves maps), for comparing acdf_envmap with Mitsuba's envmap on a file that declares its
// chromaticities: blocks_prophoto.exr, and its blocks' values as stored (prophoto_blocks). The
// blocks are inside Rec. 709's gamut (acdf clamps negative channels, Mitsuba keeps them).
void declaredPrimaries() {
  const uint32_t width = 128, height = 64, block = 8;
  const Chromaticities proPhoto{{0.7347, 0.2653}, {0.1596, 0.8404}, {0.0366, 0.0001}, {0.3457, 0.3585}};
  const ColorMatrix toProPhoto = rgbFromRgb(proPhoto, kRec709);
  Pcg32 rng(35, 1);
  std::vector<float> blocks;
  for (uint32_t b = 0; b < (width / block) * (height / block); ++b) {
    const double rgb[3] = {0.5 + 4.5 * rng.nextFloat(), 0.5 + 4.5 * rng.nextFloat(), 0.5 + 4.5 * rng.nextFloat()};
    for (const auto& row : toProPhoto)
      blocks.push_back(static_cast<float>(row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]));
  }
  Image image;
  image.width = width;
  image.height = height;
  image.channels = 3;
  for (uint32_t r = 0; r < height; ++r)
    for (uint32_t c = 0; c < width; ++c) {
      const float* v = &blocks[3 * ((r / block) * (width / block) + c / block)];
      image.pixels.insert(image.pixels.end(), v, v + 3);
    }
  writeExr((out / "blocks_prophoto.exr").string(), image, proPhoto);
  write("prophoto_blocks", blocks);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: python_reference OUTPUT_DIRECTORY\n";
    return 2;
  }
  out = argv[1];
  try {
    fs::create_directories(out);
    oneDimensional();
    cascades();
    environment();
    brdf();
    declaredPrimaries();
  } catch (const std::exception& e) {
    std::cerr << "python_reference: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

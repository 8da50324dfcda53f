// The RGL `.bsdf` reader and evaluator (tensor_file.h, rgl.h) and the writer of analytic ones
// (rgl_synthesis.h): files written from the GGX presets evaluate to the closed form within the
// tables' interpolation error; the argument order (ωo conditions the tables, cosθi divides); a
// spectral file converts to the RGB one's values; every malformed file is refused with a message
// naming the file and the field; the two real files of the shared data (when present) load.

#include "acdf/brdf/rgl.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/rgl_synthesis.h"
#include "acdf/brdf/spectrum.h"

namespace {

using namespace acdf;
namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;
const fs::path kSharedRgl = fs::path(ACDF_SOURCE_DIR) / ".." / "shared" / "data" / "rgl";

RglBrdf parsed(const TensorFile& t, const std::string& name = "test.bsdf") {
  return RglBrdf(TensorFile::parse(t.serialize(), name), name);
}

Vec3d direction(double thetaDeg, double phiDeg) { return sphericalDirection(thetaDeg * kPi / 180, phiDeg * kPi / 180); }

// f of a file written from a preset against the preset's closed form, over a spread of directions
// away from grazing: within 3% on the lobe (f at least 5% of its largest value here), 7% off it,
// where D is steep between the 128 vertices of the ndf and vndf tables (u = √(θ/(π/2)) spacing,
// about 0.9° at θm = 35°). The default resolution is the real files': 8 θo, 128² vndf, 32²
// reflectance.
TEST(RglBrdf, GeneratedFileEvaluatesToTheAnalyticModel) {
  for (const std::string preset : {"gold", "rough-aluminium"}) {
    const AnalyticBrdf model = AnalyticBrdf::preset(preset);
    const RglBrdf rgl = parsed(synthesizeRgl(model, {}, preset));
    struct Point {
      double f, rgl;
      std::string where;
    };
    std::vector<Point> points;
    double peak = 0;
    for (double to : {0.0, 20.0, 45.0, 60.0})
      for (double ti : {5.0, 30.0, 55.0, 70.0})
        for (double dphi : {0.0, 60.0, 150.0, 180.0}) {
          const Vec3d wo = direction(to, 10), wi = direction(ti, 10 + dphi);
          const HalfDiffAngles a = toHalfDiff(wo, wi);
          const std::array<double, 3> f = model.closedForm(a.thetaHalf, a.thetaDiff, a.phiDiff);
          const double y = 0.2126 * f[0] + 0.7152 * f[1] + 0.0722 * f[2];
          points.push_back({y, rgl.eval(wo, wi).luminance(),
                            std::to_string(int(to)) + "/" + std::to_string(int(ti)) + "/" + std::to_string(int(dphi))});
          peak = std::max(peak, y);
        }
    for (const Point& p : points) {
      if (p.f < 1e-3) continue;  // f ≈ 0, where a relative error means nothing
      EXPECT_NEAR(p.rgl, p.f, (p.f >= 0.05 * peak ? 0.03 : 0.07) * p.f)
          << preset << " at theta_o/theta_i/dphi " << p.where;
    }
  }
}

// A file of constant tables whose reflectance depends on the conditioning angle only: ρ = 1 at
// θ = 0, 3 at θ = π/2, so f(ωo, ωi) = ρ(θo) · 1 / (4 · 1 · cosθi). Swapping ωo and ωi (pbrt-v4's
// issue 207) conditions on θi and divides by cosθo instead.
TensorFile constantTables(float rhoAtGrazing) {
  TensorFile t;
  const float thetaIn[2] = {0.0f, static_cast<float>(kPi / 2)}, phiIn[1] = {0.0f};
  const std::vector<float> ones(4 * 4 * 2, 1.0f);
  std::vector<float> rgb(2 * 3 * 4);
  for (int i = 0; i < 12; ++i) rgb[i] = 1.0f, rgb[12 + i] = rhoAtGrazing;
  const unsigned char jacobian[1] = {1};
  t.add("theta_i", TensorField::floats({2}, thetaIn));
  t.add("phi_i", TensorField::floats({1}, phiIn));
  t.add("ndf", TensorField::floats({2, 2}, std::span(ones).first(4)));
  t.add("sigma", TensorField::floats({2, 2}, std::span(ones).first(4)));
  t.add("vndf", TensorField::floats({1, 2, 4, 4}, ones));
  t.add("luminance", TensorField::floats({1, 2, 2, 2}, std::span(ones).first(8)));
  t.add("rgb", TensorField::floats({1, 2, 3, 2, 2}, rgb));
  t.add("jacobian", TensorField::bytes({1}, jacobian));
  return t;
}

TEST(RglBrdf, TheOutgoingDirectionConditionsTheTables) {
  const RglBrdf rgl = parsed(constantTables(3.0f));
  const Vec3d wo = direction(60, 0), wi = direction(20, 100);
  const double rho = 1.0 + 2.0 * 60.0 / 90.0;
  EXPECT_NEAR(rgl.eval(wo, wi).g, rho / (4 * std::cos(20 * kPi / 180)), 1e-5);
  EXPECT_NEAR(rgl.eval(wi, wo).g, (1.0 + 2.0 * 20.0 / 90.0) / (4 * std::cos(60 * kPi / 180)), 1e-5);
  EXPECT_EQ(rgl.eval(wo, direction(95, 0)), Rgb{});
  EXPECT_EQ(rgl.eval(Vec3d{1, 0, 0}, wi), Rgb{});
}

TEST(RglBrdf, SpectralFileConvertsToTheReflectanceLuminance) {
  const AnalyticBrdf model = AnalyticBrdf::preset("gold");
  RglSynthesisOptions o;
  o.vndf = 32;
  const RglBrdf rgb = parsed(synthesizeRgl(model, o, "gold"));
  o.spectral = true;
  const RglBrdf spectral = parsed(synthesizeRgl(model, o, "gold"));
  EXPECT_TRUE(spectral.spectral());
  EXPECT_FALSE(rgb.spectral());
  for (double to : {0.0, 40.0})
    for (double ti : {10.0, 50.0}) {
      const Vec3d wo = direction(to, 0), wi = direction(ti, 170);
      const float y = rgb.eval(wo, wi).luminance();
      const Rgb s = spectral.eval(wo, wi);
      for (float c : {s.r, s.g, s.b}) EXPECT_NEAR(c, y, 2e-3 * y) << to << " " << ti;
    }
}

TEST(Spectrum, D65WhiteAndMonochromaticLight) {
  const float grid[3] = {300.0f, 550.0f, 900.0f};
  const double half[3] = {0.5, 0.5, 0.5};
  for (double c : reflectanceToLinearSrgb(grid, half)) EXPECT_NEAR(c, 0.5, 5e-4);
  // A narrow band at 450 nm is blue, at 610 nm red, at 530 nm green.
  const auto band = [](float centre) {
    const float l[4] = {centre - 6, centre - 5, centre + 5, centre + 6};
    const double r[4] = {0, 1, 1, 0};
    return reflectanceToLinearSrgb(l, r);
  };
  const auto blue = band(450), red = band(610), green = band(530);
  EXPECT_GT(blue[2], std::max(blue[0], blue[1]));
  EXPECT_GT(red[0], std::max(red[1], red[2]));
  EXPECT_GT(green[1], std::max(green[0], green[2]));
}

// A file from the constant tables with one change, parsed: the message must name the file and
// contain `expected`.
void expectRefused(const std::function<void(std::vector<unsigned char>&)>& corrupt, const std::string& expected,
                   const TensorFile& base = constantTables(3.0f)) {
  std::vector<unsigned char> bytes = base.serialize();
  corrupt(bytes);
  try {
    RglBrdf(TensorFile::parse(bytes, "bad.bsdf"), "bad.bsdf");
    ADD_FAILURE() << "accepted; expected an error containing '" << expected << "'";
  } catch (const FileError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("bad.bsdf: ", 0), 0u) << m;
    EXPECT_NE(m.find(expected), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TensorFile without(const std::string& name, const TensorFile& base = constantTables(3.0f)) {
  TensorFile t;
  for (const auto& [n, f] : base.fields())
    if (n != name) t.add(n, f);
  return t;
}

TensorFile replaced(const std::string& name, TensorField field) {
  const TensorFile base = constantTables(3.0f);
  TensorFile t;
  for (const auto& [n, f] : base.fields()) t.add(n, n == name ? field : f);
  return t;
}

// The constant tables with the first value of one field replaced.
TensorFile withFirstFloat(const std::string& name, float v) {
  TensorField f = *constantTables(3.0f).find(name);
  std::memcpy(f.data.data(), &v, sizeof v);
  return replaced(name, f);
}

TEST(RglBrdf, MalformedFilesAreRefusedNamingTheField) {
  const auto none = [](std::vector<unsigned char>&) {};
  expectRefused([](auto& b) { b[0] = 'x'; }, "not a tensor file");
  expectRefused([](auto& b) { b.resize(15); }, "truncated header");
  expectRefused([](auto& b) { b.resize(150); }, "truncated header: the file ends inside the header of field");
  expectRefused([](auto& b) { b[12] = 2; }, "version 2.0");
  expectRefused([](auto& b) { b.resize(b.size() - 4); }, "lies beyond the end of the file");
  expectRefused(
      [](auto& b) {
        b[14] = 0xff;
        b[15] = 0xff;
      },
      "fields, more than");
  expectRefused(none, "field 'vndf' is missing", without("vndf"));
  expectRefused(none, "field 'rgb' is missing", without("rgb"));
  expectRefused(none, "field 'ndf': dtype is uint8",
                replaced("ndf", TensorField::bytes({4}, std::vector<unsigned char>(4))));
  const std::vector<float> three(3, 1.0f), zeros(32, 0.0f);
  expectRefused(none, "field 'sigma': 1 dimensions", replaced("sigma", TensorField::floats({3}, three)));
  const std::vector<float> eighteen(18, 1.0f);  // luminance of 3 x 3 vertices, rgb still 2 x 2
  expectRefused(none, "field 'rgb': extent 2 in dimension 3, expected 3",
                replaced("luminance", TensorField::floats({1, 2, 3, 3}, eighteen)));
  expectRefused(none, "field 'vndf': slice 0 (theta_i 0", replaced("vndf", TensorField::floats({1, 2, 4, 4}, zeros)));
  expectRefused(none, "field 'phi_i': 3 values: an anisotropic", replaced("phi_i", TensorField::floats({3}, three)));
  for (const char* field : {"ndf", "vndf", "luminance", "rgb", "theta_i"})
    expectRefused(none, "field '" + std::string(field) + "': NaN",
                  withFirstFloat(field, std::numeric_limits<float>::quiet_NaN()));
  expectRefused(none, "field 'sigma': zero at index 0", withFirstFloat("sigma", 0.0f));
  expectRefused(none, "field 'ndf': negative", withFirstFloat("ndf", -1.0f));
  expectRefused(none, "field 'rgb': Inf", withFirstFloat("rgb", std::numeric_limits<float>::infinity()));
  expectRefused(none, "field 'theta_i': value 2", withFirstFloat("theta_i", 2.0f));
}

TEST(RglBrdf, MissingAndEmptyFilesAreRefused) {
  EXPECT_THROW(RglBrdf::load("/nonexistent/x.bsdf"), FileError);
  const fs::path empty = fs::temp_directory_path() / "acdf_rgl_empty.bsdf";
  { std::ofstream(empty.string()); }
  try {
    RglBrdf::load(empty);
    ADD_FAILURE();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
  fs::remove(empty);
}

TEST(RglBrdf, SavedFileRoundTripsAndIsRecognisedByContent) {
  const fs::path path = fs::temp_directory_path() / "acdf_rgl_roundtrip.dat";  // not named .bsdf
  RglSynthesisOptions o;
  o.vndf = 16, o.reflectance = 8, o.thetaIn = 3, o.ndf = 16;
  const TensorFile t = synthesizeRgl(AnalyticBrdf::preset("gold"), o, "gold");
  t.save(path);
  EXPECT_TRUE(RglBrdf::isRglFile(path));
  const RglBrdf a = RglBrdf::load(path), b = parsed(t);
  EXPECT_EQ(a.description(), "gold");
  const Vec3d wo = direction(30, 0), wi = direction(40, 160);
  EXPECT_EQ(a.eval(wo, wi), b.eval(wo, wi));
  ContentHash ha, hb;
  EXPECT_EQ(a.addToKey(ha), b.addToKey(hb));
  EXPECT_EQ(ha.digest(), hb.digest());
  fs::remove(path);
}

TEST(RglBrdf, SharedFilesLoad) {
  if (!fs::exists(kSharedRgl)) GTEST_SKIP() << "no shared RGL data at " << kSharedRgl;
  for (const char* name : {"paper_white_rgb.bsdf", "vch_golden_yellow_rgb.bsdf"}) {
    const RglBrdf rgl = RglBrdf::load(kSharedRgl / name);
    EXPECT_FALSE(rgl.spectral());
    EXPECT_TRUE(rgl.jacobian());
    EXPECT_EQ(rgl.thetaIn().size(), 8u);
    // A reflectance lobe: positive and finite at a few configurations.
    const Rgb f = rgl.eval(direction(30, 0), direction(30, 180));
    EXPECT_GT(f.luminance(), 0.0f) << name;
    EXPECT_TRUE(std::isfinite(f.luminance())) << name;
  }
}

}  // namespace

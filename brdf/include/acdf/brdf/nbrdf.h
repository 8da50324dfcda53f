#pragma once
// Neural BRDF fits of the 100 MERL materials (Sztrajman, Rainer, Ritschel & Weyrich, "Neural BRDF
// Representation and Importance Sampling", Computer Graphics Forum 2021; weights from
// asztr/Neural-BRDF, MIT licence; bundled in data/merl-nbrdf/).
//
// Each material is a small network evaluated in double exactly as the reference tool
// /work/shared/tools/nbrdf_to_merl.py does with numpy:
//
//   input  (hx, hy, hz, dx, dy, dz): the half vector with φh = 0, i.e. (sin θh, 0, cos θh), and
//          the Rusinkiewicz difference vector (sin θd cos φd, sin θd sin φd, cos θd)
//   Dense(21, relu) → Dense(21, relu) → Dense(3) → exp(x) − 1      (each layer y = x·W + b)
//
// The output is the linear RGB BRDF value (1/sr; MERL's channel scales are already applied).
// The fits were trained on θh, θd in [0, π/2], φd in [0, 2π); below the horizon they are
// meaningless. exp(x) − 1 can be slightly negative: values are returned as the network gives them.
//
// Weights file (JSON): { "<material>": { "layers": [ {"W": [[...]], "b": [...]}, x3 ] }, ... }
// with W of shapes 6×21, 21×21, 21×3 (rows = inputs) and b of sizes 21, 21, 3.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "acdf/brdf/coordinates.h"
#include "acdf/brdf/merl.h"  // MerlBrdf's table layout

namespace acdf {

class NeuralBrdf {
 public:
  static constexpr int kInputs = 6;
  static constexpr int kHidden = 21;
  static constexpr int kOutputs = 3;

  // The material's network from a weights file. Throws FileError ("<file>: <problem>") for
  // a missing or unreadable file, invalid JSON, an unknown material (naming a few that exist),
  // or layers of the wrong number, shape or type.
  static NeuralBrdf load(const std::filesystem::path& weightsFile, const std::string& material);

  // The material names in a weights file, sorted. Throws FileError as load() does.
  static std::vector<std::string> materials(const std::filesystem::path& weightsFile);

  const std::string& name() const { return name_; }

  // The network on an input vector (hx, hy, hz, dx, dy, dz): linear RGB, in double.
  std::array<double, 3> evalInput(const std::array<double, kInputs>& input) const;

  // The network at Rusinkiewicz angles (φh is irrelevant: isotropy), any θ, φ; no horizon test.
  std::array<double, 3> evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const;

  // For unit directions in the local frame (z = normal): 0 unless both are strictly above the
  // horizon, else the network at their half/difference angles.
  Rgb eval(const Vec3d& wo, const Vec3d& wi) const;

  // The full MERL table as nbrdf_to_merl.py builds it (tabulateMerl, merl_tabulation.h).
  std::vector<double> merlTable() const;

 private:
  NeuralBrdf() = default;

  std::string name_;
  // Row-major: w1_[k * kHidden + j] is W[k][j] of the first layer, and so on.
  std::array<double, kInputs * kHidden> w1_{};
  std::array<double, kHidden> b1_{};
  std::array<double, kHidden * kHidden> w2_{};
  std::array<double, kHidden> b2_{};
  std::array<double, kHidden * kOutputs> w3_{};
  std::array<double, kOutputs> b3_{};
};

}  // namespace acdf

#include "acdf/brdf/nbrdf.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <iterator>
#include <system_error>

#include <nlohmann/json.hpp>

#include "acdf/brdf/merl_tabulation.h"
#include "acdf/sampling/regular_file.h"

namespace acdf {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

json readJson(const fs::path& path) {
  const std::string name = path.string();
  if (const auto problem = regularFileProblem(path)) throw FileError(name, *problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(name, "cannot open file");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw FileError(name, "read error");
  try {
    json j = json::parse(text);
    if (!j.is_object()) throw FileError(name, "not a neural BRDF weights file: the top level is not a JSON object");
    return j;
  } catch (const json::exception& e) {  // a syntax error, or a number beyond double (out_of_range 406)
    throw FileError(name, std::string("invalid JSON (") + e.what() + ")");
  }
}

std::vector<std::string> sortedKeys(const json& j) {
  std::vector<std::string> names;
  for (auto it = j.begin(); it != j.end(); ++it) names.push_back(it.key());
  std::sort(names.begin(), names.end());
  return names;
}

// Copies a JSON array of `rows` arrays of `cols` numbers (or, with rows = 0, one array of `cols`
// numbers) into out, row-major; throws FileError describing the shape found otherwise.
void readMatrix(const json& value, std::size_t rows, std::size_t cols, double* out, const std::string& file,
                const std::string& what) {
  const auto shapeError = [&](const std::string& found) {
    const std::string expected = rows ? std::to_string(rows) + " x " + std::to_string(cols) : std::to_string(cols);
    return FileError(file, what + " is " + found + ", expected " + expected + " numbers");
  };
  const auto readRow = [&](const json& row, double* dst, const std::string& where) {
    if (!row.is_array()) throw shapeError(where + "not an array");
    if (row.size() != cols) throw shapeError(where + "of length " + std::to_string(row.size()));
    for (std::size_t c = 0; c < cols; ++c) {
      if (!row[c].is_number()) throw shapeError(where + "holding a non-number at position " + std::to_string(c));
      dst[c] = row[c].get<double>();
      if (!std::isfinite(dst[c])) throw shapeError(where + "holding a non-finite number");
    }
  };
  if (rows == 0) {
    readRow(value, out, "");
    return;
  }
  if (!value.is_array()) throw shapeError("not an array");
  if (value.size() != rows) throw shapeError("an array of " + std::to_string(value.size()) + " rows");
  for (std::size_t r = 0; r < rows; ++r) readRow(value[r], out + r * cols, "row " + std::to_string(r) + " ");
}

// One Dense layer, y = x·W + b, summed in index order as numpy's x @ W + b does per element.
template <int In, int Out>
void dense(const double* x, const double* w, const double* b, double* y) {
  for (int j = 0; j < Out; ++j) {
    double sum = 0.0;
    for (int k = 0; k < In; ++k) sum += x[k] * w[k * Out + j];
    y[j] = sum + b[j];
  }
}

}  // namespace

std::vector<std::string> NeuralBrdf::materials(const fs::path& weightsFile) {
  return sortedKeys(readJson(weightsFile));
}

NeuralBrdf NeuralBrdf::load(const fs::path& weightsFile, const std::string& material) {
  const std::string file = weightsFile.string();
  const json all = readJson(weightsFile);
  const auto found = all.find(material);
  if (found == all.end()) {
    const std::vector<std::string> names = sortedKeys(all);
    std::string known;
    for (std::size_t i = 0; i < names.size() && i < 5; ++i) known += (i ? ", " : "") + names[i];
    if (names.size() > 5) known += ", ...";
    throw FileError(file, "no material named '" + material + "' (it has " + std::to_string(names.size()) +
                              " materials: " + (names.empty() ? std::string("none") : known) +
                              "; see acdf merl-gen --list)");
  }
  const std::string prefix = "material '" + material + "': ";
  const json& entry = *found;
  if (!entry.is_object() || !entry.contains("layers") || !entry["layers"].is_array())
    throw FileError(file, prefix + "no \"layers\" array");
  const json& layers = entry["layers"];
  if (layers.size() != 3)
    throw FileError(file, prefix + std::to_string(layers.size()) + " layers, expected 3 (6 -> 21 -> 21 -> 3)");
  for (std::size_t l = 0; l < 3; ++l) {
    if (!layers[l].is_object() || !layers[l].contains("W") || !layers[l].contains("b"))
      throw FileError(file, prefix + "layer " + std::to_string(l) + " lacks \"W\" or \"b\"");
  }

  NeuralBrdf net;
  net.name_ = material;
  readMatrix(layers[0]["W"], kInputs, kHidden, net.w1_.data(), file, prefix + "layer 0 W");
  readMatrix(layers[0]["b"], 0, kHidden, net.b1_.data(), file, prefix + "layer 0 b");
  readMatrix(layers[1]["W"], kHidden, kHidden, net.w2_.data(), file, prefix + "layer 1 W");
  readMatrix(layers[1]["b"], 0, kHidden, net.b2_.data(), file, prefix + "layer 1 b");
  readMatrix(layers[2]["W"], kHidden, kOutputs, net.w3_.data(), file, prefix + "layer 2 W");
  readMatrix(layers[2]["b"], 0, kOutputs, net.b3_.data(), file, prefix + "layer 2 b");
  return net;
}

std::array<double, 3> NeuralBrdf::evalInput(const std::array<double, kInputs>& input) const {
  double h1[kHidden], h2[kHidden], out[kOutputs];
  dense<kInputs, kHidden>(input.data(), w1_.data(), b1_.data(), h1);
  for (double& v : h1) v = std::max(v, 0.0);
  dense<kHidden, kHidden>(h1, w2_.data(), b2_.data(), h2);
  for (double& v : h2) v = std::max(v, 0.0);
  dense<kHidden, kOutputs>(h2, w3_.data(), b3_.data(), out);
  // exp(x) − 1 as the tool writes it (not expm1), so the results agree to rounding.
  return {std::exp(out[0]) - 1.0, std::exp(out[1]) - 1.0, std::exp(out[2]) - 1.0};
}

std::array<double, 3> NeuralBrdf::evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const {
  const double sd = std::sin(thetaDiff);
  return evalInput({std::sin(thetaHalf), 0.0, std::cos(thetaHalf), sd * std::cos(phiDiff), sd * std::sin(phiDiff),
                    std::cos(thetaDiff)});
}

Rgb NeuralBrdf::eval(const Vec3d& wo, const Vec3d& wi) const {
  if (!(wi.z > 0 && wo.z > 0)) return {};
  const HalfDiffAngles a = toHalfDiff(wo, wi, false);
  const std::array<double, 3> f = evalHalfDiff(a.thetaHalf, a.thetaDiff, a.phiDiff);
  return {static_cast<float>(f[0]), static_cast<float>(f[1]), static_cast<float>(f[2])};
}

std::vector<double> NeuralBrdf::merlTable() const {
  return tabulateMerl([this](const MerlCellCoordinates& cell) {
    return evalInput({cell.half.x, cell.half.y, cell.half.z, cell.diff.x, cell.diff.y, cell.diff.z});
  });
}

}  // namespace acdf

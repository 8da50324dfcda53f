#pragma once
// A rotation of directions (an orthonormal 3×3 matrix, determinant +1): how an environment map is
// turned in the world. Double precision, like the directions it turns.

#include <array>
#include <cmath>
#include <stdexcept>

#include "acdf/sampling/sphere.h"

namespace acdf {

class Rotation {
 public:
  Rotation() = default;  // the identity

  // Rodrigues' formula: R = cos a · I + sin a · [k]× + (1 − cos a) · k kᵀ, k = axis / |axis|;
  // counter-clockwise by `radians` looking down the axis towards the origin. Throws
  // std::invalid_argument for a zero or non-finite axis or angle.
  static Rotation aboutAxis(const Vec3d& axis, double radians) {
    const double len = length(axis);
    if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(radians))
      throw std::invalid_argument("Rotation: the axis must be finite and non-zero, the angle finite");
    const Vec3d k = axis * (1.0 / len);
    const double c = std::cos(radians), s = std::sin(radians), t = 1.0 - c;
    Rotation r;
    r.rows_ = {Vec3d{c + t * k.x * k.x, t * k.x * k.y - s * k.z, t * k.x * k.z + s * k.y},
               Vec3d{t * k.y * k.x + s * k.z, c + t * k.y * k.y, t * k.y * k.z - s * k.x},
               Vec3d{t * k.z * k.x - s * k.y, t * k.z * k.y + s * k.x, c + t * k.z * k.z}};
    return r;
  }
  // Turning about the map's up axis (+Y): the usual way to aim an environment map's sun.
  static Rotation aboutY(double radians) { return aboutAxis({0.0, 1.0, 0.0}, radians); }

  Vec3d apply(const Vec3d& v) const { return {dot(rows_[0], v), dot(rows_[1], v), dot(rows_[2], v)}; }
  // The inverse rotation (the transpose).
  Vec3d applyInverse(const Vec3d& v) const { return rows_[0] * v.x + rows_[1] * v.y + rows_[2] * v.z; }

 private:
  std::array<Vec3d, 3> rows_{Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, 0, 1}};
};

}  // namespace acdf

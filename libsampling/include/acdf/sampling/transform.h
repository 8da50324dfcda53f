#pragma once
// Rotations and affine transforms of the world: how an environment map is turned (Rotation) and
// how a scene places its shapes (Transform). Double precision, like the directions and points they
// move. Eigen's geometry module builds them (AngleAxis, the affine composition; transform.cpp);
// each keeps the resulting matrix and applies it inline, so Eigen stays out of every header that
// includes this one (it costs seconds of compile time per file that parses it).

#include <array>

#include "acdf/sampling/sphere.h"

namespace acdf {

// A rotation of directions (an orthonormal 3×3 matrix, determinant +1).
class Rotation {
 public:
  Rotation() = default;  // the identity

  // Right-handed: counter-clockwise by `radians` looking down the axis towards the origin
  // (Rodrigues' formula). Throws std::invalid_argument for a zero or non-finite axis or angle.
  static Rotation aboutAxis(const Vec3d& axis, double radians);
  // Turning about the map's up axis (+Y): the usual way to aim an environment map's sun.
  static Rotation aboutY(double radians) { return aboutAxis({0.0, 1.0, 0.0}, radians); }

  Vec3d apply(const Vec3d& v) const { return {dot(rows_[0], v), dot(rows_[1], v), dot(rows_[2], v)}; }
  // The inverse rotation (the transpose).
  Vec3d applyInverse(const Vec3d& v) const { return rows_[0] * v.x + rows_[1] * v.y + rows_[2] * v.z; }

  const std::array<Vec3d, 3>& rows() const { return rows_; }

 private:
  std::array<Vec3d, 3> rows_{Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, 0, 1}};
};

// Scale (per axis, positive), then rotation, then translation: a shape's placement in the world.
class Transform {
 public:
  Transform() = default;  // the identity
  Transform(const Vec3d& scale, const Rotation& rotation, const Vec3d& translation);

  Vec3d point(const Vec3d& p) const { return vector(p) + translation_; }
  // A displacement (a quad's edge): the linear part alone.
  Vec3d vector(const Vec3d& v) const { return {dot(linear_[0], v), dot(linear_[1], v), dot(linear_[2], v)}; }

 private:
  std::array<Vec3d, 3> linear_{Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, 0, 1}};  // rows
  Vec3d translation_;
};

}  // namespace acdf

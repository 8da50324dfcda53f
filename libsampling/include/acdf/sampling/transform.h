#pragma once
// Rotations and affine transforms of the world, on Eigen's geometry module: how an environment
// map is turned (Rotation) and how a scene places its shapes (Transform). Double precision, like
// the directions and points they move. Vec3d (sphere.h) stays the tree's vector type; these types
// take and return it, so Eigen appears only here.

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

#include "acdf/sampling/sphere.h"

namespace acdf {

inline Eigen::Vector3d toEigen(const Vec3d& v) { return {v.x, v.y, v.z}; }
inline Vec3d fromEigen(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// A rotation of directions (an orthonormal 3×3 matrix, determinant +1).
class Rotation {
 public:
  Rotation() = default;  // the identity

  // Right-handed: counter-clockwise by `radians` looking down the axis towards the origin
  // (Rodrigues' formula, Eigen's AngleAxis). Throws std::invalid_argument for a zero or
  // non-finite axis or angle.
  static Rotation aboutAxis(const Vec3d& axis, double radians) {
    const double len = length(axis);
    if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(radians))
      throw std::invalid_argument("Rotation: the axis must be finite and non-zero, the angle finite");
    Rotation r;
    r.matrix_ = Eigen::AngleAxisd(radians, toEigen(axis) / len).toRotationMatrix();
    return r;
  }
  // Turning about the map's up axis (+Y): the usual way to aim an environment map's sun.
  static Rotation aboutY(double radians) { return aboutAxis({0.0, 1.0, 0.0}, radians); }

  Vec3d apply(const Vec3d& v) const { return fromEigen(matrix_ * toEigen(v)); }
  // The inverse rotation (the transpose).
  Vec3d applyInverse(const Vec3d& v) const { return fromEigen(matrix_.transpose() * toEigen(v)); }

  const Eigen::Matrix3d& matrix() const { return matrix_; }

 private:
  Eigen::Matrix3d matrix_ = Eigen::Matrix3d::Identity();
};

// Scale (per axis, positive), then rotation, then translation: a shape's placement in the world.
class Transform {
 public:
  Transform() = default;  // the identity
  Transform(const Vec3d& scale, const Rotation& rotation, const Vec3d& translation)
      : affine_(Eigen::Translation3d(toEigen(translation)) * rotation.matrix() * Eigen::Scaling(toEigen(scale))) {}

  Vec3d point(const Vec3d& p) const { return fromEigen(affine_ * toEigen(p)); }
  // A displacement (a quad's edge): the linear part alone.
  Vec3d vector(const Vec3d& v) const { return fromEigen(affine_.linear() * toEigen(v)); }

 private:
  Eigen::Affine3d affine_ = Eigen::Affine3d::Identity();
};

}  // namespace acdf

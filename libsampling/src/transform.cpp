#include "acdf/sampling/transform.h"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace acdf {
namespace {

Eigen::Vector3d toEigen(const Vec3d& v) { return {v.x, v.y, v.z}; }

std::array<Vec3d, 3> rowsOf(const Eigen::Matrix3d& m) {
  return {Vec3d{m(0, 0), m(0, 1), m(0, 2)}, Vec3d{m(1, 0), m(1, 1), m(1, 2)}, Vec3d{m(2, 0), m(2, 1), m(2, 2)}};
}

Eigen::Matrix3d matrixOf(const std::array<Vec3d, 3>& rows) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) m.row(r) = toEigen(rows[r]).transpose();
  return m;
}

}  // namespace

Rotation Rotation::aboutAxis(const Vec3d& axis, double radians) {
  const double len = length(axis);
  if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(radians))
    throw std::invalid_argument("Rotation: the axis must be finite and non-zero, the angle finite");
  Rotation r;
  r.rows_ = rowsOf(Eigen::AngleAxisd(radians, toEigen(axis) / len).toRotationMatrix());
  return r;
}

Transform::Transform(const Vec3d& scale, const Rotation& rotation, const Vec3d& translation) {
  const Eigen::Affine3d affine =
      Eigen::Translation3d(toEigen(translation)) * matrixOf(rotation.rows()) * Eigen::Scaling(toEigen(scale));
  linear_ = rowsOf(affine.linear());
  const Eigen::Vector3d t = affine.translation();
  translation_ = {t.x(), t.y(), t.z()};
}

}  // namespace acdf

#include "acdf/integrator/camera.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace acdf {

Camera::Camera(const Vec3d& eye, const Vec3d& target, const Vec3d& up, double fovDegrees, uint32_t width,
               uint32_t height, CropWindow crop)
    : eye_(eye), width_(width), height_(height), crop_(crop) {
  if (width == 0 || height == 0) throw std::invalid_argument("the image size must be at least 1 x 1");
  if (!(fovDegrees > 0 && fovDegrees < 180)) throw std::invalid_argument("fov must be in (0, 180) degrees");
  if (!(crop.x0 < crop.x1 && crop.x1 <= width && crop.y0 < crop.y1 && crop.y1 <= height))
    throw std::invalid_argument("the crop window must be a non-empty part of the image");
  const Vec3d view = target - eye;
  if (!(length(view) > 0)) throw std::invalid_argument("eye and target must differ");
  forward_ = normalize(view);
  const Vec3d side = cross(forward_, up);
  if (!(length(side) > 1e-9 * length(up))) throw std::invalid_argument("up must not be parallel to the view direction");
  right_ = normalize(side);
  up_ = cross(right_, forward_);
  tanHalfFov_ = std::tan(0.5 * fovDegrees * std::numbers::pi / 180.0);
  aspect_ = static_cast<double>(width_) / height_;
}

Ray Camera::generateRay(double x, double y) const {
  const double sx = (2.0 * x / width_ - 1.0) * tanHalfFov_ * aspect_;
  const double sy = (1.0 - 2.0 * y / height_) * tanHalfFov_;
  return {eye_, normalize(forward_ + right_ * sx + up_ * sy)};
}

}  // namespace acdf

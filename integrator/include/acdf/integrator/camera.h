#pragma once
// A pinhole camera: look-at placement, vertical field of view, image size in pixels, and a crop
// window (the part of the frame this render computes; a render farm splits a frame this way).

#include <cstdint>

#include "acdf/sampling/sphere.h"

namespace acdf {

struct Ray {
  Vec3d origin, direction;  // direction: unit length
};

// Pixels [x0, x1) × [y0, y1) of the full frame; row 0 is the top.
struct CropWindow {
  uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  uint32_t width() const { return x1 - x0; }
  uint32_t height() const { return y1 - y0; }
};

class Camera {
 public:
  // fovDegrees: vertical, in (0, 180). The crop must lie inside the frame and be non-empty;
  // throws std::invalid_argument otherwise (or for a degenerate look-at).
  Camera(const Vec3d& eye, const Vec3d& target, const Vec3d& up, double fovDegrees, uint32_t width, uint32_t height,
         CropWindow crop);

  // The ray through the full-frame film position (x, y) in pixels (x right, y down).
  Ray generateRay(double x, double y) const;

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  const CropWindow& crop() const { return crop_; }

 private:
  Vec3d eye_, forward_, right_, up_;
  double tanHalfFov_ = 0;
  double aspect_ = 0;  // width / height, divided once rather than per ray
  uint32_t width_, height_;
  CropWindow crop_;
};

}  // namespace acdf

#pragma once
// An orthonormal frame around a unit normal: the local shading frame of a surface point
// (materials see directions with z = the shading normal, brdf_sampler.h's convention) and the
// frame a cosine-weighted sample around any normal is drawn in. The tangent matters for tables
// indexed by the outgoing azimuth φo (the 4D BRDF tables): shapes pass a tangent hint that varies
// smoothly over the surface (a sphere's direction of increasing longitude, a quad's first edge),
// so φo is well defined and continuous there; the hint is only orthogonalised against the normal.

#include <cmath>

#include "acdf/sampling/sphere.h"

namespace acdf {

class Frame {
 public:
  // n: unit normal. A hint (nearly) parallel to n, or zero, falls back to a basis that depends
  // on n alone (Duff et al. 2017, continuous except on one great circle).
  explicit Frame(const Vec3d& n, const Vec3d& tangentHint = {}) : n_(n) {
    const Vec3d projected = tangentHint - n * dot(n, tangentHint);
    if (dot(projected, projected) > 1e-12) {
      s_ = normalize(projected);
      t_ = cross(n_, s_);
    } else {
      // Both tangents in closed form (t = n × s exactly, without the cross product's rounding).
      const double sign = std::copysign(1.0, n.z);
      const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
      s_ = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
      t_ = {b, sign + n.y * n.y * a, -n.y};
    }
  }

  Vec3d toLocal(const Vec3d& v) const { return {dot(v, s_), dot(v, t_), dot(v, n_)}; }
  Vec3d toWorld(const Vec3d& v) const { return s_ * v.x + t_ * v.y + n_ * v.z; }
  const Vec3d& normal() const { return n_; }

 private:
  Vec3d n_, s_, t_;
};

}  // namespace acdf

#include "acdf/integrator/geometry.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <immintrin.h>

namespace acdf {

namespace {

void check(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree: ") + what + " failed (error " + std::to_string(error) + ")");
}

// Each 16 bytes of the ray in one store: Embree loads them as vectors, and a load spanning several
// narrower stores waits for them to retire instead of being forwarded (measured: 6.7 % of a render
// stalled in the copy of a field-by-field ray).
void writeRay(RTCRay& r, const Ray& ray, double maxDistance) {
  const float tfar = maxDistance >= std::numeric_limits<float>::max() ? std::numeric_limits<float>::infinity()
                                                                      : static_cast<float>(maxDistance);
  const __m128d originXY = _mm_loadu_pd(&ray.origin.x), directionXY = _mm_loadu_pd(&ray.direction.x);
  const __m128 tnear = _mm_setzero_ps(), time = _mm_setzero_ps();
  _mm_store_ps(&r.org_x, _mm_movelh_ps(_mm_cvtpd_ps(originXY),
                                       _mm_unpacklo_ps(_mm_set_ss(static_cast<float>(ray.origin.z)), tnear)));
  _mm_store_ps(&r.dir_x, _mm_movelh_ps(_mm_cvtpd_ps(directionXY),
                                       _mm_unpacklo_ps(_mm_set_ss(static_cast<float>(ray.direction.z)), time)));
  // tfar, mask (every geometry), id, flags
  _mm_store_si128(reinterpret_cast<__m128i*>(&r.tfar), _mm_setr_epi32(std::bit_cast<int>(tfar), -1, 0, 0));
}

}  // namespace

Geometry::Geometry(std::vector<Sphere> spheres, std::vector<TriangleMesh> meshes)
    : spheres_(std::move(spheres)), meshes_(std::move(meshes)) {
  for (const Sphere& s : spheres_)
    if (!(s.radius > 0) || !std::isfinite(s.radius)) throw std::invalid_argument("a sphere's radius must be positive");
  for (TriangleMesh& m : meshes_) {
    for (const auto& tri : m.triangles)
      for (uint32_t v : tri)
        if (v >= m.positions.size()) throw std::invalid_argument("a triangle refers to a vertex that does not exist");
    std::erase_if(m.triangles, [&](const std::array<uint32_t, 3>& tri) {
      const Vec3d& a = m.positions[tri[0]];
      return !(length(cross(m.positions[tri[1]] - a, m.positions[tri[2]] - a)) > 0);
    });
  }

  device_ = rtcNewDevice(nullptr);
  if (!device_) throw std::runtime_error("Embree: cannot create a device");
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

  if (!spheres_.empty()) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres_.size()));
    check(device_, "allocating sphere buffers");
    for (std::size_t i = 0; i < spheres_.size(); ++i) {
      v[4 * i + 0] = static_cast<float>(spheres_[i].center.x);
      v[4 * i + 1] = static_cast<float>(spheres_[i].center.y);
      v[4 * i + 2] = static_cast<float>(spheres_[i].center.z);
      v[4 * i + 3] = static_cast<float>(spheres_[i].radius);
    }
    rtcCommitGeometry(g);
    sphereGeometryId_ = rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
  }
  for (const TriangleMesh& m : meshes_) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), m.positions.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangles.size()));
    check(device_, "allocating mesh buffers");
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      v[3 * i + 0] = static_cast<float>(m.positions[i].x);
      v[3 * i + 1] = static_cast<float>(m.positions[i].y);
      v[3 * i + 2] = static_cast<float>(m.positions[i].z);
    }
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
      std::copy(m.triangles[i].begin(), m.triangles[i].end(), idx + 3 * i);
    rtcCommitGeometry(g);
    meshGeometryIds_.push_back(rtcAttachGeometry(scene_, g));
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(scene_);
  check(device_, "building the scene");
}

Geometry::~Geometry() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

std::optional<SurfaceHit> Geometry::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  writeRay(rh.ray, ray, std::numeric_limits<double>::infinity());
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const double t = rh.ray.tfar;
  if (rh.hit.geomID == sphereGeometryId_) return sphereHit(ray, t, rh.hit.primID);
  const auto mesh = std::find(meshGeometryIds_.begin(), meshGeometryIds_.end(), rh.hit.geomID);
  return triangleHit(ray, t, static_cast<uint32_t>(mesh - meshGeometryIds_.begin()), rh.hit.primID);
}

bool Geometry::occluded(const Ray& ray, double maxDistance) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r;
  writeRay(r, ray, maxDistance);
  rtcOccluded1(scene_, &context, &r);
  return r.tfar < 0.0f;  // Embree marks a hit by tfar = −∞
}

Vec3d Geometry::offsetOrigin(const SurfaceHit& hit, const Vec3d& direction) {
  const Vec3d& p = hit.position;
  const double scale = 1.0 + std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  const double side = dot(direction, hit.normal) >= 0 ? 1.0 : -1.0;
  return p + hit.normal * (side * 1e-4 * scale);
}

SurfaceHit Geometry::sphereHit(const Ray& ray, double t, uint32_t index) const {
  const Sphere& s = spheres_[index];
  SurfaceHit hit;
  hit.distance = t;
  hit.material = s.material;
  Vec3d n = normalize(ray.origin + ray.direction * t - s.center);
  // Back onto the sphere in double: Embree's float t is off by ~1e-7 relative.
  hit.position = s.center + n * s.radius;
  if (dot(n, ray.direction) > 0) n = -n;  // seen from inside
  hit.normal = n;
  // Longitude direction about the world's up axis (+Y): zero at the poles, where Frame falls back.
  hit.tangentHint = {n.z, 0.0, -n.x};
  return hit;
}

SurfaceHit Geometry::triangleHit(const Ray& ray, double t, uint32_t mesh, uint32_t triangle) const {
  const TriangleMesh& m = meshes_[mesh];
  const auto& tri = m.triangles[triangle];
  const Vec3d& a = m.positions[tri[0]];
  const Vec3d e1 = m.positions[tri[1]] - a, e2 = m.positions[tri[2]] - a;
  Vec3d n = normalize(cross(e1, e2));
  if (dot(n, ray.direction) > 0) n = -n;  // two-sided
  SurfaceHit hit;
  hit.distance = t;
  hit.material = m.material;
  hit.normal = n;
  // On the triangle's plane in double.
  const Vec3d p = ray.origin + ray.direction * t;
  hit.position = p - n * dot(p - a, n);
  hit.tangentHint = m.tangent.value_or(Vec3d{});
  return hit;
}

}  // namespace acdf

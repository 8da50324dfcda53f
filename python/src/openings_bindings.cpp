// The openings of an enclosure found by tracing (acdf/integrator/openings.h), for a renderer that
// is not acdf's: its triangles and camera in, the portals to give acdf.EnvironmentLight out.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "acdf/integrator/openings.h"
#include "acdf/integrator/scene.h"
#include "arrays.h"
#include "bindings.h"

namespace acdf::python {

using namespace pybind11::literals;

namespace {

Vec3d point(const ArrayArg& arg, const char* name) {
  const Batch<double> b = batch<double>(arg, 3, name, true);
  if (b.rows != 1) throw py::value_error(std::string(name) + ": expected one point of shape (3,)");
  return vec3At(b.data, 1, 0);
}

// One (positions (n, 3), triangles (m, 3)) pair of `meshes`; the indices must be integers.
TriangleMesh meshOf(const py::handle& pair, std::size_t index) {
  const std::string name = "meshes[" + std::to_string(index) + "]";
  const auto parts = py::reinterpret_borrow<py::object>(pair);
  if (!py::isinstance<py::sequence>(parts) || py::len(parts) != 2)
    throw py::value_error(name + ": expected a (positions, triangles) pair");
  const std::string positionsName = name + "[0]", trianglesName = name + "[1]";
  const Batch<double> positions = batch<double>({parts[py::int_(0)]}, 3, positionsName.c_str());
  const py::array indices = py::array::ensure(parts[py::int_(1)]);
  if (!indices || (indices.dtype().kind() != 'i' && indices.dtype().kind() != 'u'))
    throw py::value_error(trianglesName + ": expected integer vertex indices of shape (m, 3)");
  const Batch<int64_t> triangles = batch<int64_t>({indices}, 3, trianglesName.c_str());
  TriangleMesh mesh;
  mesh.positions.reserve(positions.rows);
  for (std::size_t i = 0; i < positions.rows; ++i) {
    const Vec3d v = vec3At(positions.data, positions.rows, i);
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw py::value_error(positionsName + ": vertex " + std::to_string(i) + " is not finite");
    mesh.positions.push_back(v);
  }
  mesh.triangles.reserve(triangles.rows);
  for (std::size_t i = 0; i < triangles.rows; ++i) {
    std::array<uint32_t, 3> triangle{};
    for (std::size_t k = 0; k < 3; ++k) {
      const int64_t v = triangles.data[3 * i + k];
      if (v < 0 || static_cast<uint64_t>(v) >= positions.rows)
        throw py::value_error(trianglesName + ": triangle " + std::to_string(i) + " refers to vertex " +
                              std::to_string(v) + " of " + std::to_string(positions.rows));
      triangle[k] = static_cast<uint32_t>(v);
    }
    mesh.triangles.push_back(triangle);
  }
  return mesh;
}

py::tuple tupleOf(const Vec3d& v) { return py::make_tuple(v.x, v.y, v.z); }

constexpr const char* kDoc = R"(The openings of an enclosure (windows, doors, the gap of a door
ajar), found by tracing as `acdf render` finds them for a scene that declares no portals
(docs/scene-format.md): from points the camera sees, directions are traced about their normals;
where fewer than a quarter leave the scene, the regions where the escaping ones cross the box
around the scene become portals facing in, at most 8, the largest first. Fixed seed: the same
geometry and camera give the same openings.

find_openings(meshes, eye, target, up, fov, width, height, spheres=None) -> dict
  meshes: a list of (positions (n, 3) float64, triangles (m, 3) integer vertex indices) pairs,
    world frame; shapes are two-sided.
  eye, target, up (3,), fov (vertical, degrees, in (0, 180)), width, height: a pinhole camera
    as a scene file's.
  spheres: (k, 4) centres and radii, or None.
  Returns {"portals": [{"corner", "edge_u", "edge_v"} as 3-tuples, edge_u x edge_v into the
  enclosure: what acdf.EnvironmentLight's portals take], "escaped_share", "points", "rays",
  "escaped"}: the portals are empty for an open scene (escaped_share >= 0.25) or one nothing
  leaves. A portal is one technique among others, so a wrong guess costs variance, never bias.)";

}  // namespace

void bindOpenings(py::module_& m) {
  py::list sources;
  for (PortalSource source : {PortalSource::Auto, PortalSource::Declared, PortalSource::None})
    sources.append(std::string(toString(source)));
  m.attr("portal_sources") = py::tuple(sources);
  m.def(
      "find_openings",
      [](const py::list& meshes, const ArrayArg& eye, const ArrayArg& target, const ArrayArg& up, double fov,
         uint32_t width, uint32_t height, const std::optional<ArrayArg>& spheres) {
        std::vector<TriangleMesh> triangles;
        for (std::size_t i = 0; i < meshes.size(); ++i) triangles.push_back(meshOf(meshes[i], i));
        std::vector<Sphere> balls;
        if (spheres) {
          const Batch<double> s = batch<double>(*spheres, 4, "spheres");
          for (std::size_t i = 0; i < s.rows; ++i) {
            const double* v = s.data + 4 * i;
            if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
              throw py::value_error("spheres: row " + std::to_string(i) + " has a centre that is not finite");
            balls.push_back({.center = {v[0], v[1], v[2]}, .radius = v[3]});  // Geometry checks the radius
          }
        }
        // Geometry and Camera throw std::invalid_argument (ValueError) for what they cannot use.
        const Camera camera(point(eye, "eye"), point(target, "target"), point(up, "up"), fov, width, height,
                            {.x0 = 0, .y0 = 0, .x1 = width, .y1 = height});
        OpeningSearch found;
        {
          py::gil_scoped_release release;
          const Geometry geometry(std::move(balls), std::move(triangles));
          found = findOpenings(geometry, camera);
        }
        py::list portals;
        for (const Portal& p : found.openings)
          portals.append(py::dict("corner"_a = tupleOf(p.corner), "edge_u"_a = tupleOf(p.edgeU),
                                  "edge_v"_a = tupleOf(p.edgeV)));
        return py::dict("portals"_a = portals, "escaped_share"_a = found.escapedShare(), "points"_a = found.points,
                        "rays"_a = found.rays, "escaped"_a = found.escaped);
      },
      "meshes"_a, "eye"_a, "target"_a, "up"_a, "fov"_a, "width"_a, "height"_a, "spheres"_a = py::none(), kDoc);
}

}  // namespace acdf::python

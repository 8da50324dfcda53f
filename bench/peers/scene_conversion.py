"""An acdf scene file (docs/scene-format.md) as a Mitsuba 3 scene dict and as a Blender scene for Cycles 5.

The conventions (each checked by bench/peers/test_conventions.py on a tiny scene):

- acdf is +Y up; Blender is +Z up: Blender (x, y, z) = acdf (x, -z, y), a proper rotation. Mitsuba is +Y up.
- Environment maps: acdf and Mitsuba's `envmap` share OpenEXR's lat-long mapping; Cycles' environment
  texture needs the direction turned 90 degrees about its +Z first.
- acdf's `max_depth` d counts surface bounces (1 = direct light only): Cycles' max bounces d - 1,
  Mitsuba's `max_depth` d + 1 (which counts the camera ray's segment as well).
- `ggx-conductor` with f0 = 1 (acdf: GGX, separable Smith G1, Schlick Fresnel, so no Fresnel at f0 = 1):
  Cycles' Glossy BSDF with the GGX distribution (roughness sqrt(alpha)) and Mitsuba's `roughconductor`
  (GGX, alpha, `material` none).
- Shapes are two-sided in all three; the pixel filter is a one-pixel box.
- `environment.portals`: Cycles' portals (rectangular area lights marked as portals, lighting into the room);
  Mitsuba 3 has none, so its rows with `envmap` render the scene without them; with acdf's map plugin
  (`acdf_envmap`), nested rectangles whose normal points into the room. Portals change the noise, not the image.
- Cycles: adaptive sampling, denoising, clamping, the light threshold and "Filter Glossy" off (each makes it
  estimate something else); the map looked up at the nearest pixel, as acdf does (Mitsuba's `envmap` is
  bilinear, with no option); spheres are one-point point clouds, which Cycles intersects as true spheres.

acdf's sampling strategies (`render.sampler`, `mis`, `direct`, the environment's `sampling`, tables) change
the noise, not the image, and have no counterpart here; each peer samples its own way. What a peer cannot
express raises Unsupported, one line naming the scene file and the feature.
Everything but `build_blender_scene` and `load_mitsuba_scene` is pure Python (no bpy, no mitsuba).
"""
import json
import math
import os
from dataclasses import dataclass

# acdf's defaults (docs/scene-format.md) for keys a scene may omit.
DEFAULT_MAX_DEPTH = 8
DEFAULT_UP = (0.0, 1.0, 0.0)


class Unsupported(Exception):
    """A scene feature a peer renderer cannot express; str() is the one line to print."""


@dataclass
class Scene:
    """A scene file read as acdf reads it: the JSON with its file paths made absolute."""

    path: str
    data: dict

    @property
    def name(self):
        return os.path.splitext(os.path.basename(self.path))[0]

    @property
    def camera(self):
        return self.data["camera"]

    @property
    def max_depth(self):
        return self.data.get("render", {}).get("max_depth", DEFAULT_MAX_DEPTH)

    def used_materials(self):
        """name -> material of the materials a shape refers to (acdf loads only those)."""
        names = dict.fromkeys(shape["material"] for shape in self.data["shapes"])
        return {name: self.data["materials"][name] for name in names}


def read_scene(path, resolution=None):
    """The scene at `path`, its relative file paths resolved against the scene's directory, and its
    camera's (width, height) replaced by `resolution` when given."""
    with open(path) as f:
        data = json.load(f)
    if resolution:
        data["camera"]["width"], data["camera"]["height"] = resolution
    base = os.path.dirname(os.path.abspath(path))

    def resolve(node):
        if "file" in node:
            node["file"] = os.path.normpath(os.path.join(base, node["file"]))

    resolve(data["environment"])
    for material in data["materials"].values():
        resolve(material)
    for shape in data["shapes"]:
        resolve(shape)
    return Scene(path, data)


# ---- Pure conversions ----

def blender_from_acdf(v):
    """A point or direction of acdf's +Y-up world in Blender's +Z-up one."""
    x, y, z = v
    return (x, -z, y)


def cycles_max_bounces(max_depth):
    return max_depth - 1


def mitsuba_max_depth(max_depth):
    return max_depth + 1


def cycles_roughness(alpha):
    """Cycles' GGX roughness r has alpha = r^2."""
    return math.sqrt(alpha)


# Cycles' environment texture looks directions up 90 degrees about +Z away from OpenEXR's lat-long.
CYCLES_ENVIRONMENT_TURN_DEGREES = 90.0


def cycles_environment_z_rotation(acdf_rotation_degrees):
    """The Mapping node's rotation about Blender's +Z for a map acdf turns by `rotation` about +Y.

    acdf looks a world direction up in the map at R_Y(-rotation) of it; acdf's +Y is Blender's +Z and
    the change of frame is a proper rotation, so that is R_Z(-rotation) in Blender, then Cycles' turn.
    """
    return CYCLES_ENVIRONMENT_TURN_DEGREES - acdf_rotation_degrees


def _normalized(v):
    length = math.sqrt(sum(c * c for c in v))
    return tuple(c / length for c in v)


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def _scaled(a, k):
    return tuple(x * k for x in a)


def _columns_matrix(columns, translation):
    """A 4x4 row-major matrix (nested lists) whose linear part has the given three columns."""
    rows = [[columns[j][i] for j in range(3)] + [translation[i]] for i in range(3)]
    return rows + [[0.0, 0.0, 0.0, 1.0]]


def _matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))] for i in range(len(a))]


def apply_matrix(matrix, point):
    return tuple(sum(matrix[i][j] * c for j, c in enumerate(point)) + matrix[i][3] for i in range(3))


def axis_rotation(axis, degrees):
    """The 4x4 right-handed rotation by `degrees` about `axis` (Rodrigues)."""
    x, y, z = _normalized(axis)
    t = math.radians(degrees)
    c, s = math.cos(t), math.sin(t)
    d = 1 - c
    linear = [[c + x * x * d, x * y * d - z * s, x * z * d + y * s],
              [y * x * d + z * s, c + y * y * d, y * z * d - x * s],
              [z * x * d - y * s, z * y * d + x * s, c + z * z * d]]
    return [row + [0.0] for row in linear] + [[0.0, 0.0, 0.0, 1.0]]


def shape_transform(transform):
    """A shape's `transform` (scale, then rotation, then translation) as a 4x4 row-major matrix."""
    transform = transform or {}
    scale = transform.get("scale", 1.0)
    sx, sy, sz = (scale,) * 3 if isinstance(scale, (int, float)) else scale
    scaling = [[sx, 0, 0, 0], [0, sy, 0, 0], [0, 0, sz, 0], [0, 0, 0, 1]]
    rotate = transform.get("rotate")
    rotation = axis_rotation(rotate["axis"], rotate["degrees"]) if rotate else axis_rotation((0, 1, 0), 0)
    tx, ty, tz = transform.get("translate", (0.0, 0.0, 0.0))
    translation = [[1, 0, 0, tx], [0, 1, 0, ty], [0, 0, 1, tz], [0, 0, 0, 1]]
    return _matmul(translation, _matmul(rotation, scaling))


def quad_corners(shape):
    """The four world corners of a `quad` shape, in acdf's order (corner, +u, +u+v, +v)."""
    matrix = shape_transform(shape.get("transform"))
    corner, u, v = shape["corner"], shape["edge_u"], shape["edge_v"]
    local = [corner, _add(corner, u), _add(_add(corner, u), v), _add(corner, v)]
    return [apply_matrix(matrix, p) for p in local]


def read_obj(path):
    """(vertices, polygons) of an OBJ file: positions and 0-based vertex indices per face."""
    vertices, polygons = [], []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "v":
                vertices.append(tuple(float(c) for c in fields[1:4]))
            elif fields[0] == "f":
                # "i", "i/t", "i//n" or "i/t/n"; negative indices count from the end
                indices = [int(field.split("/")[0]) for field in fields[1:]]
                polygons.append([i - 1 if i > 0 else len(vertices) + i for i in indices])
    return vertices, polygons


def mesh_geometry(shape):
    """World vertices and polygons of a `mesh` shape (its OBJ file under its transform)."""
    vertices, polygons = read_obj(shape["file"])
    matrix = shape_transform(shape.get("transform"))
    return [apply_matrix(matrix, v) for v in vertices], polygons


def camera_basis(camera):
    """(right, up, forward) unit vectors of acdf's look-at camera."""
    eye, target = camera["eye"], camera["target"]
    forward = _normalized(_sub(target, eye))
    right = _normalized(_cross(forward, camera.get("up", DEFAULT_UP)))
    return right, _cross(right, forward), forward


def material_kind(scene, name, material, peer):
    """'diffuse' or 'ggx' for a material the peers render exactly as acdf; Unsupported otherwise."""
    kind = material["type"]
    where = f"{scene.path}: $.materials.{name}"
    if kind == "diffuse":
        return "diffuse"
    if kind == "measured":
        source = os.path.basename(material["file"]) if "file" in material else "preset " + material["preset"]
        raise Unsupported(f"{where}: {peer} cannot render the measured material {source} (a tabulated BRDF)")
    if kind == "ggx-conductor":
        if "preset" in material or _color(material["f0"]) != (1.0, 1.0, 1.0):
            raise Unsupported(f"{where}: {peer} has no GGX conductor with Schlick's Fresnel at f0 != 1")
        return "ggx"
    raise Unsupported(f"{where}: unknown material type {kind!r}")


def _color(value):
    return tuple(float(c) for c in value) if isinstance(value, list) else (float(value),) * 3


def check_peer_can_render(scene, peer):
    """Raise Unsupported for the first feature of `scene` that `peer` cannot express."""
    if "crop" in scene.camera:
        raise Unsupported(f"{scene.path}: $.camera.crop: crop windows are not converted for {peer}")
    for name, material in scene.used_materials().items():
        material_kind(scene, name, material, peer)


# ---- Mitsuba 3 ----

def mitsuba_look_at(camera):
    """Mitsuba's perspective sensor frame (its look_at: +X left, +Y up, +Z forward) as a matrix."""
    right, up, forward = camera_basis(camera)
    return _columns_matrix([_scaled(right, -1), up, forward], camera["eye"])


# The table acdf_envmap samples the map with when a Mitsuba row asks for acdf's: acdf render's default.
ACDF_MAP_STRATEGY = "compensated"


def mitsuba_rectangle(corner, u, v):
    """The to_world of Mitsuba's rectangle ([-1, 1]^2 of its local xy plane, normal +Z) spanning
    corner + s u + t v, s, t in [0, 1], its normal along u x v."""
    centre = _add(corner, _scaled(_add(u, v), 0.5))
    return _columns_matrix([_scaled(u, 0.5), _scaled(v, 0.5), _normalized(_cross(u, v))], centre)


def mitsuba_scene_dict(scene, sampler, spp, acdf_map=False):
    """The Mitsuba 3 scene dict of `scene` (transforms as nested lists: load_mitsuba_scene wraps them); with
    acdf_map, a map is acdf's plugin (acdf.mitsuba.register() first) instead of Mitsuba's `envmap`."""
    check_peer_can_render(scene, "Mitsuba 3")
    camera, environment = scene.camera, scene.data["environment"]
    result = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": mitsuba_max_depth(scene.max_depth)},
        "sensor": {
            "type": "perspective", "fov_axis": "y", "fov": camera["fov"], "to_world": mitsuba_look_at(camera),
            "sampler": {"type": sampler, "sample_count": spp},
            "film": {"type": "hdrfilm", "width": camera["width"], "height": camera["height"],
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
    }
    if environment["type"] == "map":
        result["environment"] = {"type": "envmap", "filename": environment["file"],
                                 "scale": environment.get("scale", 1.0),
                                 "to_world": axis_rotation((0, 1, 0), environment.get("rotation", 0.0))}
        if acdf_map:
            result["environment"].update(type="acdf_envmap", strategy=ACDF_MAP_STRATEGY)
            for index, portal in enumerate(environment.get("portals", [])):
                # acdf_envmap's portal: its normal (+Z) is the inner side edge_u x edge_v.
                result["environment"][f"portal-{index}"] = {
                    "type": "rectangle", "to_world": mitsuba_rectangle(portal["corner"], portal["edge_u"], portal["edge_v"])}
    else:
        result["environment"] = {"type": "constant",
                                 "radiance": {"type": "rgb", "value": _color(environment["radiance"])}}
    for name, material in scene.used_materials().items():
        if material_kind(scene, name, material, "Mitsuba 3") == "diffuse":
            bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": _color(material["albedo"])}}
        else:
            bsdf = {"type": "roughconductor", "distribution": "ggx", "alpha": material["alpha"], "material": "none"}
        result["bsdf-" + name] = {"type": "twosided", "bsdf": bsdf}
    for index, shape in enumerate(scene.data["shapes"]):
        reference = {"type": "ref", "id": "bsdf-" + shape["material"]}
        if shape["type"] == "sphere":
            entry = {"type": "sphere", "center": shape["center"], "radius": shape["radius"]}
        elif shape["type"] == "quad":
            corner, plus_u, _, plus_v = quad_corners(shape)
            entry = {"type": "rectangle",
                     "to_world": mitsuba_rectangle(corner, _sub(plus_u, corner), _sub(plus_v, corner))}
        else:  # mesh: flat shading, as acdf shades with the geometric normal
            entry = {"type": "obj", "filename": shape["file"], "face_normals": True,
                     "to_world": shape_transform(shape.get("transform"))}
        result[f"shape-{index}"] = dict(entry, bsdf=reference)
    return result


def load_mitsuba_scene(scene_dict):
    """mi.load_dict of mitsuba_scene_dict's result (a Mitsuba variant must be set)."""
    import mitsuba as mi

    def wrap(node):
        if isinstance(node, dict):
            return {key: mi.ScalarTransform4f(value) if key == "to_world" else wrap(value)
                    for key, value in node.items()}
        return node

    scene = wrap(scene_dict)
    if scene.get("environment", {}).get("type") == "acdf_envmap":
        import acdf.mitsuba  # gives acdf_envmap the scene: its bounds, and its openings where none are declared

        return acdf.mitsuba.load_dict(scene)
    return mi.load_dict(scene)


# ---- Cycles 5 (bpy) ----

def cycles_portal_light(portal):
    """(matrix, size_x, size_y) of the Cycles portal for an acdf portal, in Blender's frame: a
    rectangular area light, which Cycles' portals are, lights along its local -Z, so that axis is
    the portal's inner side edge_u x edge_v; its local X runs along edge_v and Y along edge_u (X x Y
    = -Z), centred on the rectangle."""
    u, v = portal["edge_u"], portal["edge_v"]
    inward = _normalized(_cross(u, v))
    centre = _add(portal["corner"], _scaled(_add(u, v), 0.5))
    columns = [blender_from_acdf(_normalized(v)), blender_from_acdf(_normalized(u)),
               blender_from_acdf(_scaled(inward, -1))]
    return _columns_matrix(columns, blender_from_acdf(centre)), math.hypot(*v), math.hypot(*u)


def cycles_camera_matrix(camera):
    """Blender's camera matrix (it looks along its -Z, +Y up) for acdf's camera, in Blender's frame."""
    right, up, forward = (blender_from_acdf(v) for v in camera_basis(camera))
    return _columns_matrix([right, up, _scaled(forward, -1)], blender_from_acdf(camera["eye"]))


def build_blender_scene(scene, threads, guiding):
    """Replace Blender's scene with `scene` set up for Cycles (factory settings first); returns bpy's scene,
    whose cycles.samples and cycles.seed the caller sets."""
    check_peer_can_render(scene, "Cycles")
    import bpy
    from mathutils import Matrix

    bpy.ops.wm.read_factory_settings(use_empty=True)
    blender = bpy.context.scene
    blender.render.engine = "CYCLES"
    camera = scene.camera
    blender.render.resolution_x, blender.render.resolution_y = camera["width"], camera["height"]
    blender.render.resolution_percentage = 100
    blender.render.threads_mode = "FIXED"
    blender.render.threads = threads
    blender.render.image_settings.file_format = "OPEN_EXR"
    blender.render.image_settings.color_depth = "32"
    blender.render.image_settings.color_mode = "RGB"
    blender.view_settings.view_transform = "Standard"
    _set_cycles_sampling(blender.cycles, scene, guiding)

    camera_data = bpy.data.cameras.new("camera")
    camera_data.sensor_fit = "VERTICAL"
    camera_data.angle_y = math.radians(camera["fov"])
    camera_data.clip_start, camera_data.clip_end = 1e-4, 1e6
    camera_object = bpy.data.objects.new("camera", camera_data)
    camera_object.matrix_world = Matrix(cycles_camera_matrix(camera))
    blender.collection.objects.link(camera_object)
    blender.camera = camera_object

    blender.world = _cycles_world(bpy, scene.data["environment"])
    for index, portal in enumerate(scene.data["environment"].get("portals", [])):
        matrix, size_x, size_y = cycles_portal_light(portal)
        light = bpy.data.lights.new(f"portal-{index}", "AREA")
        light.shape, light.size, light.size_y = "RECTANGLE", size_x, size_y
        light.cycles.is_portal = True
        obj = bpy.data.objects.new(f"portal-{index}", light)
        obj.matrix_world = Matrix(matrix)
        blender.collection.objects.link(obj)
    materials = {name: _cycles_material(bpy, name, scene, material)
                 for name, material in scene.used_materials().items()}
    for index, shape in enumerate(scene.data["shapes"]):
        material = materials[shape["material"]]
        if shape["type"] == "sphere":
            obj = _cycles_sphere(bpy, f"shape-{index}", shape, material)
        else:
            vertices, polygons = (quad_corners(shape), [[0, 1, 2, 3]]) if shape["type"] == "quad" \
                else mesh_geometry(shape)
            mesh = bpy.data.meshes.new(f"shape-{index}")
            mesh.from_pydata([blender_from_acdf(v) for v in vertices], [], polygons)
            mesh.materials.append(material)
            obj = bpy.data.objects.new(f"shape-{index}", mesh)
        blender.collection.objects.link(obj)
    return blender


def _set_cycles_sampling(cycles, scene, guiding):
    """Cycles' defaults, but for what would make it render something other than acdf's estimate."""
    cycles.device = "CPU"
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.blur_glossy = 0.0  # "Filter Glossy" blurs glossy lobes after a diffuse bounce: biased
    bounces = cycles_max_bounces(scene.max_depth)
    cycles.max_bounces = cycles.diffuse_bounces = cycles.glossy_bounces = bounces
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    cycles.use_guiding = cycles.use_surface_guiding = guiding


def _cycles_world(bpy, environment):
    world = bpy.data.worlds.new("environment")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    if environment["type"] == "map":
        texture = nodes.new("ShaderNodeTexEnvironment")
        texture.image = bpy.data.images.load(environment["file"])
        texture.interpolation = "Closest"  # acdf looks the map up at the nearest pixel
        mapping = nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        mapping.inputs["Rotation"].default_value = (
            0.0, 0.0, math.radians(cycles_environment_z_rotation(environment.get("rotation", 0.0))))
        links.new(nodes.new("ShaderNodeTexCoord").outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
        links.new(texture.outputs["Color"], background.inputs["Color"])
        background.inputs["Strength"].default_value = environment.get("scale", 1.0)
    else:
        background.inputs["Color"].default_value = (*_color(environment["radiance"]), 1.0)
        background.inputs["Strength"].default_value = 1.0
    return world


def _cycles_material(bpy, name, scene, material):
    result = bpy.data.materials.new(name)
    result.use_nodes = True
    nodes, links = result.node_tree.nodes, result.node_tree.links
    nodes.remove(nodes["Principled BSDF"])
    if material_kind(scene, name, material, "Cycles") == "diffuse":
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = (*_color(material["albedo"]), 1.0)
        bsdf.inputs["Roughness"].default_value = 0.0  # Lambert, not Oren-Nayar
    else:
        bsdf = nodes.new("ShaderNodeBsdfGlossy")
        bsdf.distribution = "GGX"  # the default is multiple-scattering GGX
        bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        bsdf.inputs["Roughness"].default_value = cycles_roughness(material["alpha"])
    links.new(bsdf.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    return result


def _cycles_sphere(bpy, name, shape, material):
    """A true sphere: one point of a point cloud, which Cycles intersects as a sphere (a mesh would be facets)."""
    tree = bpy.data.node_groups.new(name, "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    points = tree.nodes.new("GeometryNodePoints")
    points.inputs["Count"].default_value = 1
    points.inputs["Position"].default_value = blender_from_acdf(shape["center"])
    points.inputs["Radius"].default_value = shape["radius"]
    set_material = tree.nodes.new("GeometryNodeSetMaterial")
    set_material.inputs["Material"].default_value = material
    output = tree.nodes.new("NodeGroupOutput")
    tree.links.new(points.outputs["Points"], set_material.inputs["Geometry"])
    tree.links.new(set_material.outputs["Geometry"], output.inputs["Geometry"])
    obj = bpy.data.objects.new(name, bpy.data.meshes.new(name))
    obj.modifiers.new("sphere", "NODES").node_group = tree
    return obj

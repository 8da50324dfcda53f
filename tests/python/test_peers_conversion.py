"""bench/peers/scene_conversion.py's pure conversions (no bpy; Mitsuba only to load the dict, skipped without
it). The renders that check the conventions are bench/peers/test_conventions.py (`make bench-peers-check`)."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "bench", "peers"))
import scene_conversion as sc  # noqa: E402

SPHERES = os.path.join(ROOT, "bench", "peers", "scenes", "spheres.json")


def scene_file(name):
    return os.path.join(ROOT, "scenes", name + ".json")


def linear(matrix):
    return np.array(matrix, dtype=float)[:3, :3]


def test_blender_frame_is_a_proper_rotation_taking_up_to_z():
    columns = np.array([sc.blender_from_acdf(e) for e in np.eye(3)]).T
    assert np.allclose(columns @ columns.T, np.eye(3)) and np.isclose(np.linalg.det(columns), 1)
    assert sc.blender_from_acdf((0, 1, 0)) == (0, 0, 1)
    assert sc.blender_from_acdf((1, 2, 3)) == (1, -3, 2)


def test_depth_roughness_and_map_turn():
    assert (sc.cycles_max_bounces(1), sc.mitsuba_max_depth(1)) == (0, 2)  # direct light only
    assert (sc.cycles_max_bounces(6), sc.mitsuba_max_depth(6)) == (5, 7)
    assert sc.cycles_roughness(0.09) == pytest.approx(0.3)
    assert sc.cycles_environment_z_rotation(0) == 90 and sc.cycles_environment_z_rotation(40) == 50


def test_paths_resolve_against_the_scene_directory():
    scene = sc.read_scene(scene_file("cluster"))
    assert scene.data["environment"]["file"] == os.path.normpath(
        os.path.join(ROOT, "data", "envmaps", "sunset_1024x512.exr"))
    assert scene.data["shapes"][4]["file"] == os.path.normpath(os.path.join(ROOT, "scenes", "meshes", "cube.obj"))
    assert sc.read_scene(SPHERES, (32, 24)).camera["width"] == 32


@pytest.mark.parametrize("name, feature", [
    ("demo", "measured material nickel.binary"),
    ("cluster", "measured material preset rough-aluminium"),
    ("conductors", "Schlick's Fresnel at f0 != 1"),
])
def test_what_a_peer_cannot_express_is_refused_in_one_line(name, feature):
    scene = sc.read_scene(scene_file(name))
    for peer in ("Cycles", "Mitsuba 3"):
        with pytest.raises(sc.Unsupported) as refusal:
            sc.check_peer_can_render(scene, peer)
        message = str(refusal.value)
        assert "\n" not in message and message.startswith(scene_file(name)) and feature in message
        assert peer in message


def test_unused_materials_are_not_checked():
    scene = sc.read_scene(SPHERES)
    scene.data["materials"]["unused"] = {"type": "measured", "preset": "gold"}
    sc.check_peer_can_render(scene, "Cycles")


def test_shape_transform_scales_then_rotates_then_translates():
    matrix = sc.shape_transform({"scale": 2, "rotate": {"axis": [0, 1, 0], "degrees": 90}, "translate": [0, 1, 0]})
    assert np.allclose(sc.apply_matrix(matrix, (1, 0, 0)), (0, 1, -2))  # +X turns to -Z about +Y
    assert np.allclose(sc.apply_matrix(sc.shape_transform(None), (1, 2, 3)), (1, 2, 3))


def test_obj_faces_and_mesh_placement():
    vertices, polygons = sc.read_obj(os.path.join(ROOT, "scenes", "meshes", "cube.obj"))
    assert len(vertices) == 8 and len(polygons) == 6 and polygons[0] == [0, 3, 2, 1]
    shape = sc.read_scene(SPHERES).data["shapes"][1]
    world, _ = sc.mesh_geometry(shape)
    assert np.allclose(np.mean(world, axis=0), shape["transform"]["translate"])


def test_cameras_look_at_the_target():
    camera = {"eye": [1, 2, 3], "target": [0, 0.5, -1], "fov": 30}
    forward = np.subtract(camera["target"], camera["eye"])
    forward /= np.linalg.norm(forward)
    mitsuba = np.array(sc.mitsuba_look_at(camera))
    assert np.allclose(mitsuba[:3, 3], camera["eye"]) and np.allclose(mitsuba[:3, 2], forward)
    assert mitsuba[1, 1] > 0  # its +Y is up
    blender = np.array(sc.cycles_camera_matrix(camera))
    assert np.allclose(blender[:3, 3], sc.blender_from_acdf(camera["eye"]))
    assert np.allclose(-blender[:3, 2], sc.blender_from_acdf(forward))  # Blender's camera looks along -Z
    assert blender[2, 1] > 0  # and its +Y is Blender's up, +Z
    for matrix in (mitsuba, blender):
        assert np.isclose(np.linalg.det(matrix[:3, :3]), 1)


def test_mitsuba_dict():
    scene = sc.read_scene(SPHERES)
    scene_dict = sc.mitsuba_scene_dict(scene, "independent", 4)
    assert scene_dict["integrator"] == {"type": "path", "max_depth": 5}
    assert scene_dict["sensor"]["film"]["rfilter"] == {"type": "box"}
    assert scene_dict["sensor"]["sampler"] == {"type": "independent", "sample_count": 4}
    turn = math.radians(40)
    assert np.allclose(linear(scene_dict["environment"]["to_world"]),
                       [[math.cos(turn), 0, math.sin(turn)], [0, 1, 0], [-math.sin(turn), 0, math.cos(turn)]])
    assert scene_dict["bsdf-chrome"] == {"type": "twosided", "bsdf": {
        "type": "roughconductor", "distribution": "ggx", "alpha": 0.1, "material": "none"}}
    assert scene_dict["bsdf-clay"]["type"] == "twosided"
    floor = scene_dict["shape-2"]["to_world"]  # the rectangle [-1, 1]^2 onto the quad
    corners = sc.quad_corners(scene.data["shapes"][2])
    assert np.allclose(sc.apply_matrix(floor, (-1, -1, 0)), corners[0])
    assert np.allclose(sc.apply_matrix(floor, (1, 1, 0)), corners[2])
    assert scene_dict["shape-1"]["face_normals"] is True


def test_the_acdf_map_row_swaps_only_the_emitter_for_acdfs_plugin():
    scene = sc.read_scene(SPHERES)
    envmap = sc.mitsuba_scene_dict(scene, "multijitter", 4)["environment"]
    acdf_map = sc.mitsuba_scene_dict(scene, "multijitter", 4, acdf_map=True)["environment"]
    assert acdf_map == dict(envmap, type="acdf_envmap", strategy=sc.ACDF_MAP_STRATEGY)


def test_the_acdf_map_rows_strategy_is_acdf_renders_default(tmp_path):
    program = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))
    if not os.path.exists(program):
        pytest.skip(f"no acdf program at {program}")
    scene = sc.read_scene(SPHERES, (4, 3))
    path = tmp_path / "spheres.json"
    path.write_text(json.dumps(scene.data))
    report = subprocess.run([program, "render", str(path), "-o", str(tmp_path / "x.exr"), "--no-png", "--spp", "1",
                             "--json"], check=True, capture_output=True, text=True).stdout
    assert json.loads(report)["env_sampling"] == sc.ACDF_MAP_STRATEGY


def test_mitsuba_loads_the_dict():
    mi = pytest.importorskip("mitsuba", reason="mitsuba is not importable (run with the project's venv)")
    mi.set_variant("scalar_rgb")
    scene = sc.load_mitsuba_scene(sc.mitsuba_scene_dict(sc.read_scene(SPHERES, (8, 6)), "independent", 1))
    assert len(scene.shapes()) == 3
    bounds = scene.bbox()
    assert bounds.min.y == pytest.approx(0, abs=1e-6) and bounds.max.x == pytest.approx(20)


def test_a_portal_becomes_a_cycles_area_light_lighting_into_the_room():
    portal = sc.read_scene(scene_file("room-portal")).data["environment"]["portals"][0]
    matrix, size_x, size_y = sc.cycles_portal_light(portal)
    frame = linear(matrix)
    assert np.allclose(frame.T @ frame, np.eye(3)) and np.isclose(np.linalg.det(frame), 1)
    # The window is in the wall z = 2 and lights towards -z (acdf), +y in Blender: the light's -Z.
    assert np.allclose(frame[:, 2], [0, -1, 0]) and (size_x, size_y) == pytest.approx((1.4, 1.1))
    assert np.allclose(np.array(matrix)[:3, 3], sc.blender_from_acdf((0.0, 1.45, 2.0)))


def test_a_portal_becomes_acdf_envmaps_rectangle_and_acdf_samples_it_as_declared():
    """With acdf's map plugin, a portal is a rectangle nested in the emitter on the window, its normal
    into the room; Mitsuba's envmap row has none. acdf_envmap reads it back as the declared portal."""
    scene = sc.read_scene(scene_file("room-portal"))
    portal = scene.data["environment"]["portals"][0]
    assert not any(key.startswith("portal") for key in sc.mitsuba_scene_dict(scene, "multijitter", 4)["environment"])
    environment = sc.mitsuba_scene_dict(scene, "multijitter", 4, acdf_map=True)["environment"]
    rectangle = environment["portal-0"]
    assert rectangle["type"] == "rectangle"
    matrix = rectangle["to_world"]
    assert np.allclose(sc.apply_matrix(matrix, (-1, -1, 0)), portal["corner"])
    assert np.allclose(linear(matrix) @ [0, 0, 1], sc._normalized(sc._cross(portal["edge_u"], portal["edge_v"])))
    mi = pytest.importorskip("mitsuba", reason="mitsuba is not importable (run with the project's venv)")
    pytest.importorskip("acdf.mitsuba", reason="acdf is not importable (build/python on PYTHONPATH)")
    import acdf.mitsuba

    mi.set_variant("scalar_rgb")
    acdf.mitsuba.register()
    emitter = sc.load_mitsuba_scene({"type": "scene", "sky": environment}).emitters()[0]
    (read,) = emitter.portals
    for key in ("corner", "edge_u", "edge_v"):
        assert np.allclose(read[key], portal[key], atol=1e-6), key

"""The conversion's conventions, checked by rendering: a tiny copy of bench/peers/scenes/spheres.json (a GGX
conductor sphere with f0 = 1, a diffuse OBJ cube, a diffuse floor quad) under a turned, smooth, lopsided and
coloured map renders to the same image in acdf, Cycles and Mitsuba, within noise: the image means and the
means of 4 x 4 blocks per channel agree to the Sidak bound at level 0.01, z-scores from the seeds' spread;
the blocks' with a 0.5 % allowance for the map seen directly, which has almost no noise and which the
renderers filter differently (acdf and Cycles: the nearest pixel; Mitsuba: bilinear). Each convention broken
on purpose fails (mean z): Cycles' map turned 0 or -90 degrees instead of 90 (-99, -406), Cycles' bounces d
instead of d - 1 (+12.8), its roughness alpha instead of sqrt(alpha) (+6.5), its default multiple-scattering
GGX (+4.6), Mitsuba's max_depth d instead of d + 1 (-36), one-sided Mitsuba BSDFs (-566).

Needs .venv-peers (scripts/install-peers); run by `make bench-peers-check` (and first by `make bench-peers`):

    .venv-peers/bin/python -m pytest -q bench/peers
"""
import json
import os

import numpy as np
import pytest

import efficiency
import renderers
import scene_conversion

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes", "spheres.json")
RESOLUTION = (32, 24)
SEEDS = list(range(1, 9))
SPP = 16
ALPHA = 0.01
BLOCKS = (4, 4)
MAP_FILTER_ALLOWANCE = 0.005
PEERS = ["cycles", "cycles-guiding", "mitsuba-independent", "mitsuba-multijitter", "mitsuba-multijitter-acdf"]


def write_lopsided_map(path, width=512, height=256):
    """A smooth map: a warm lobe towards +X and up with a narrower one inside it (what a glossy lobe's width
    shows), blue towards -Z; a turned, mirrored or flipped lookup changes every surface's light. In acdf's
    lat-long layout (README, "Environment maps"), fine enough that pixel-centre conventions do not show."""
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    theta = np.pi * (np.arange(height) + 0.5) / height
    phi = 2 * np.pi * (np.arange(width) + 0.5) / width
    theta, phi = np.meshgrid(theta, phi, indexing="ij")
    x, y, z = np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)
    towards_lobe = (1 + 0.6 * x + 0.8 * y) / 2
    warm = towards_lobe ** 3 + 2 * towards_lobe ** 40
    blue = (1 - z) ** 2 / 4
    rgb = np.stack([0.2 + 3 * warm, 0.2 + 2 * warm + 0.3 * blue, 0.2 + warm + 1.5 * blue], axis=-1)
    mi.Bitmap(rgb.astype(np.float32)).write(path)


@pytest.fixture(scope="module")
def scene_path(tmp_path_factory):
    """The test scene under the lopsided map turned 40 degrees, depth 2 (a depth off by one changes the
    floor's light), the floor's edges swapped so that its geometric normal faces down (two-sidedness)."""
    directory = tmp_path_factory.mktemp("conventions")
    environment_map = str(directory / "sky.exr")
    write_lopsided_map(environment_map)
    scene = scene_conversion.read_scene(SCENE, RESOLUTION)
    scene.data["environment"]["file"] = environment_map
    scene.data["render"]["max_depth"] = 2
    floor = scene.data["shapes"][-1]
    floor["edge_u"], floor["edge_v"] = floor["edge_v"], floor["edge_u"]
    path = directory / "conventions.json"
    path.write_text(json.dumps(scene.data))
    return str(path)


def render(name, scene_path):
    return renderers.run_in_subprocess(name, scene_path, [SPP], SEEDS, threads=2)["images"][0]


@pytest.fixture(scope="module")
def acdf_images(scene_path):
    return render("acdf", scene_path)


@pytest.mark.parametrize("peer", PEERS)
def test_peer_renders_the_same_image_as_acdf(peer, scene_path, acdf_images):
    images = render(peer, scene_path)
    z_mean = efficiency.mean_z(images, acdf_images)
    z_blocks = efficiency.block_z_scores(images, acdf_images, BLOCKS, MAP_FILTER_ALLOWANCE)
    bound = efficiency.sidak_z_bound(z_blocks.size + 1, ALPHA)
    mean, error = efficiency.mean_and_standard_error(images)
    acdf_mean, acdf_error = efficiency.mean_and_standard_error(acdf_images)
    print(f"{peer}: mean {mean:.5f} ± {error:.5f} (acdf {acdf_mean:.5f} ± {acdf_error:.5f}), z {z_mean:+.2f}; "
          f"blocks: max |z| {np.abs(z_blocks).max():.2f} (without the allowance "
          f"{np.abs(efficiency.block_z_scores(images, acdf_images, BLOCKS)).max():.2f}), bound {bound:.2f}")
    assert abs(z_mean) < bound
    assert np.abs(z_blocks).max() < bound, np.array2string(z_blocks[..., 1], precision=1)

"""The batched calls: domains, edge variates, broadcasting, threads, and the documented help."""
import os
import pydoc
import subprocess

import numpy as np
import pytest

import acdf
from conftest import ROOM_CAMERA, ROOM_QUADS, WINDOW_QUAD, assert_portal_covers_window

ONE_MINUS_EPSILON = np.nextafter(np.float32(1), np.float32(0))


def test_cascade_samples_inside_the_domain_with_positive_pdf(rng):
    values = rng.random((64, 32), dtype=np.float32) ** 8
    values[10:20] = 0
    c = acdf.Cascade(values, axes=[(-2.0, 2.0), (0.0, 0.5)])
    edges = np.array([[0, 0], [0, ONE_MINUS_EPSILON], [ONE_MINUS_EPSILON, 0], [ONE_MINUS_EPSILON] * 2], np.float32)
    x, pdf = c.sample(np.concatenate([edges, rng.random((10000, 2), dtype=np.float32)]))
    assert np.all((x[:, 0] > -2) & (x[:, 0] < 2) & (x[:, 1] > 0) & (x[:, 1] < 0.5))
    assert np.all(np.isfinite(pdf)) and np.all(pdf > 0)
    np.testing.assert_array_equal(c.pdf(x), pdf)
    assert abs(c.cell_probabilities().sum() - 1) < 1e-9
    assert c.cell_probabilities().shape == (64, 32)
    assert c.shape == (64, 32) and c.sampled_dims == 2 and c.bytes > 0


def test_large_batches_run_in_parallel_and_agree_with_small_ones(rng):
    c = acdf.Cascade(rng.random((128, 64), dtype=np.float32))
    u = rng.random((50000, 2), dtype=np.float32)
    x, pdf = c.sample(u)  # 50000 rows: oneTBB, without the GIL
    small = [c.sample(u[i:i + 1000]) for i in range(0, len(u), 1000)]
    np.testing.assert_array_equal(x, np.concatenate([s[0] for s in small]))
    np.testing.assert_array_equal(pdf, np.concatenate([s[1] for s in small]))


def test_one_dimensional_breakpoints_and_round_trip(rng):
    f = np.exp(-((np.arange(512) - 200.0) / 20.0) ** 2).astype(np.float32) + 1e-3
    table = acdf.AdaptiveCdf1D(f, epsilon=1e-3)
    vertices, cdf = table.breakpoints
    assert vertices[0] == 0 and vertices[-1] == 512 and cdf[0] == 0 and cdf[-1] == 1
    assert 2 < table.points < 100 and table.points == len(vertices)
    x, _ = table.sample(rng.random(1000, dtype=np.float32))
    np.testing.assert_allclose(table.sample(table.invert(x))[0], x, atol=1e-5)


def test_cascade_breakpoints_and_serialization(rng):
    c = acdf.Cascade(rng.random((32, 16), dtype=np.float32), epsilon=0.02)
    rows = c.breakpoints(0)
    assert len(rows) == 1 and len(c.breakpoints(1)) == len(rows[0]) - 1
    copy = acdf.Cascade.deserialize(c.serialize())
    u = rng.random((100, 2), dtype=np.float32)
    np.testing.assert_array_equal(copy.sample(u)[0], c.sample(u)[0])


def test_brdf_broadcasts_one_outgoing_direction(rng):
    sampler = acdf.GgxBrdfSampler(acdf.AnalyticBrdf.preset("gold"))
    wo = np.array([0.3, 0.1, 0.9])
    u = rng.random((1000, 2), dtype=np.float32)
    wi, weight, pdf = sampler.sample(wo, u)
    wi_each, _, pdf_each = sampler.sample(np.tile(wo, (1000, 1)), u)
    np.testing.assert_array_equal(wi, wi_each)
    np.testing.assert_array_equal(pdf, pdf_each)
    assert np.all(pdf > 0) and weight.shape == (1000, 3)


def test_environment_light_strategies_integrate_to_one():
    rgb = np.ones((16, 32, 3), np.float32)
    rgb[3, 5] = 500
    for strategy in ["uniform", "alias", "adaptive", "hierarchical"]:
        light = acdf.EnvironmentLight(acdf.EnvironmentMap(rgb), strategy=strategy)
        p = light.pixel_probabilities()
        assert p.shape == (16, 32) and abs(p.sum() - 1) < 1e-6, strategy
        assert light.strategy == strategy and not light.emits_nothing
    black = acdf.EnvironmentLight(acdf.EnvironmentMap(np.zeros((4, 8, 3), np.float32)))
    _, _, pdf = black.sample(np.zeros((3, 2), np.float32))
    assert black.emits_nothing and np.all(pdf == 0)


def test_every_environment_sampling_is_listed_described_and_accepted():
    strategies = acdf.environment_samplings()
    names = [s["name"] for s in strategies]
    assert "adaptive" in names and "local-compensated" in names and len(set(names)) == len(names)
    world = acdf.EnvironmentMap(np.ones((8, 16, 3), np.float32))
    for s in strategies:
        assert len(s["description"]) > 20, s
        assert acdf.EnvironmentLight(world, strategy=s["name"]).strategy == s["name"]
    with pytest.raises(ValueError, match="local-compensated"):
        acdf.EnvironmentLight(world, strategy="no-such-strategy")


def test_portals_let_the_map_through_from_inside_and_bad_ones_are_refused():
    """A constant map of radiance 1 seen through a window: from a point inside, the mixture's samples
    weigh 1 on average over the whole sphere (the light's power is unchanged); the portals' share of
    them (and a few of the table's) pass through the window; behind the window, or without a position, the light samples as it does
    without portals. Portals acdf cannot use are refused naming the portal and the problem."""
    window = {"corner": [-0.5, 0.2, 1.0], "edge_u": [0.0, 0.6, 0.0], "edge_v": [1.0, 0.0, 0.0]}
    world = acdf.EnvironmentMap(np.ones((16, 32, 3), np.float32))
    light = acdf.EnvironmentLight(world, portals=[window])
    plain = acdf.EnvironmentLight(world)
    u = np.random.default_rng(5).random((200_000, 2), dtype=np.float32)
    inside = np.array([0.1, 0.5, 0.0])
    d, radiance, pdf = light.sample(u, position=inside)
    np.testing.assert_allclose(light.pdf(d, position=inside), pdf, rtol=1e-12)
    weights = radiance[:, 0] / pdf
    assert abs(weights.mean() - 4 * np.pi) < 5 * weights.std() / np.sqrt(len(u))
    hits = (1.0 - inside[2]) / d[:, 2]
    x, y = inside[0] + hits * d[:, 0], inside[1] + hits * d[:, 1]
    through = (hits > 0) & (np.abs(x) <= 0.5) & (y >= 0.2) & (y <= 0.8)
    share = acdf.EnvironmentLight.portal_share()
    assert share < through.mean() < share + 0.1
    # Where MIS with BSDF samples covers the rest (allow_incomplete_pdf), every sample goes through.
    assert acdf.EnvironmentLight.portal_share(allow_incomplete_pdf=True) == 1.0
    d, _, pdf = light.sample(u, position=inside, allow_incomplete_pdf=True)
    np.testing.assert_allclose(light.pdf(d, position=inside, allow_incomplete_pdf=True), pdf, rtol=1e-12)
    hits = (1.0 - inside[2]) / d[:, 2]
    x, y = inside[0] + hits * d[:, 0], inside[1] + hits * d[:, 1]
    assert np.all((hits > 0) & (np.abs(x) <= 0.5 + 1e-9) & (y >= 0.2 - 1e-9) & (y <= 0.8 + 1e-9))
    for position in ([0.1, 0.5, 1.5], None):
        np.testing.assert_array_equal(light.sample(u[:100], position=position)[0], plain.sample(u[:100])[0])
    assert acdf.portal_problem(window) is None
    bad = [({**window, "edge_v": [1.0, 0.1, 0.0]}, "portals \\[0\\]: edge_u and edge_v must be perpendicular"),
           ({**window, "edge_u": [0.0, 0.0, 0.0]}, "portals \\[0\\]: its edges must not be zero"),
           ({"corner": [0, 0, 0], "edge_u": [1, 0, 0]}, "portals\\[0\\]: needs corner, edge_u and edge_v"),
           ({**window, "corner": [0, 0]}, "portals\\[0\\].corner: expected 3 numbers"),
           ({**window, "normal": [0, 0, 1]}, "portals\\[0\\]: unknown key normal")]
    for portal, message in bad:
        with pytest.raises(ValueError, match=message):
            acdf.EnvironmentLight(world, portals=[portal])


def test_help_states_the_conventions():
    assert "per steradian" in acdf.__doc__ and "lat-long" in acdf.__doc__
    for name in ["Cascade", "EnvironmentLight", "BrdfSampler", "TabulatedBrdfSampler", "SimplifyOptions"]:
        assert len(getattr(acdf, name).__doc__) > 200, name


def room_meshes(window=True):
    """The room of conftest.py as triangles (two per quad), its window open unless window is False."""
    meshes = []
    for corner, u, v in ROOM_QUADS + ([] if window else [WINDOW_QUAD]):
        c, u, v = (np.array(x, dtype=np.float64) for x in (corner, u, v))
        meshes.append((np.array([c, c + u, c + u + v, c + v]), np.array([[0, 1, 2], [0, 2, 3]])))
    return meshes


def test_find_openings_finds_a_rooms_window_and_refuses_bad_geometry():
    """The window of a room of triangles becomes one portal covering it (to 3 % of the wall, in the
    wall's plane to 3 %), facing in, the same on every call; a sealed room and an open floor get none;
    bad meshes, spheres and cameras are refused naming the argument."""
    found = acdf.find_openings(room_meshes(), **ROOM_CAMERA, spheres=np.array([[0.0, 0.5, 0.0, 0.5]]))
    assert 0 < found["escaped_share"] < 0.25 and found["rays"] > 0 and found["points"] > 0
    assert found == acdf.find_openings(room_meshes(), **ROOM_CAMERA, spheres=np.array([[0.0, 0.5, 0.0, 0.5]]))
    other_layouts = [(np.asfortranarray(p), np.asfortranarray(t.astype(np.int32))) for p, t in room_meshes()]
    assert found == acdf.find_openings(other_layouts, **ROOM_CAMERA, spheres=[[0, 0.5, 0, 0.5]])
    (portal,) = found["portals"]
    assert_portal_covers_window(portal)
    light = acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((8, 16, 3), np.float32)), portals=found["portals"])
    assert light.portal_arrays()[0]["length_u"] > 0

    assert acdf.find_openings(room_meshes(window=False), **ROOM_CAMERA)["portals"] == []
    open_floor = [(np.array([[-5, 0, -5], [5, 0, -5], [5, 0, 5], [-5, 0, 5]], float), np.array([[0, 1, 2], [0, 2, 3]]))]
    found = acdf.find_openings(open_floor, **ROOM_CAMERA)
    assert found["portals"] == [] and found["escaped_share"] >= 0.25

    floor = open_floor[0]
    bad = [(dict(meshes=[(floor[0], floor[1].astype(float))]), "meshes\\[0\\]\\[1\\]: expected integer vertex indices"),
           (dict(meshes=[(floor[0], floor[1] + 2)]), "meshes\\[0\\]\\[1\\]: triangle 0 refers to vertex 4 of 4"),
           (dict(meshes=[(floor[0] * np.nan, floor[1])]), "meshes\\[0\\]\\[0\\]: vertex 0 is not finite"),
           (dict(meshes=[floor[0]]), "meshes\\[0\\]: expected a \\(positions, triangles\\) pair"),
           (dict(meshes=[floor], spheres=np.array([[0.0, 1.0, 0.0, -1.0]])), "radius must be positive"),
           (dict(meshes=[floor], spheres=np.zeros((1, 3))), "spheres: expected shape \\(n, 4\\)"),
           (dict(meshes=[floor], fov=180), "fov must be in"),
           (dict(meshes=[floor], eye=[0.5, 0.8, -1.2]), "eye and target must differ")]
    for arguments, message in bad:
        with pytest.raises(ValueError, match=message):
            acdf.find_openings(**{**ROOM_CAMERA, **arguments})
    assert acdf.portal_sources == ("auto", "declared", "none")


def test_table_options_are_the_scene_formats_and_all_reach_the_table():
    options = acdf.table_options()
    keys = [o["key"] for o in options]
    assert keys[:5] == ["layout", "theta_out", "phi_out", "theta_half", "phi_half"]
    for o in options:
        assert o["key"] in acdf.TabulatedBrdfSampler.__doc__ and o["type"] in ("count", "number", "boolean", "name")
    gold = acdf.AnalyticBrdf.preset("gold")
    small = {"layout": "isotropic", "theta_out": 4, "phi_out": 2, "theta_half": 16, "phi_half": 8,
             "mirror": True, "supersampling": 1, "chi2_epsilon": 1e-4, "tolerance": "constant",
             "slice_grouping": 0.0, "cosine_weight": 0.1}
    assert sorted(small) == sorted(keys)
    sampler = acdf.TabulatedBrdfSampler(gold, method="uniform", **small)
    unmirrored = acdf.TabulatedBrdfSampler(gold, method="uniform", **{**small, "mirror": False})
    assert unmirrored.bytes > sampler.bytes
    defaults = acdf.TabulatedBrdfSampler(gold, method="uniform", layout="isotropic")
    assert defaults.bytes > sampler.bytes


def test_the_package_and_the_program_are_the_ones_under_test():
    # The build tree's (python.pytest) or the pip-installed ones (python.pip_installed).
    assert os.path.dirname(acdf.__file__) == os.environ["ACDF_PACKAGE_DIR"]
    version = subprocess.run([os.environ["ACDF_PROGRAM"], "--version"], check=True, capture_output=True,
                             text=True).stdout
    assert version == f"acdf {acdf.__version__}\n"


def test_the_program_finds_its_bundled_files_where_it_is_installed(tmp_path):
    # Installed (the wheel), merl-gen's fits and bench-error's plot script are the copies beside the
    # program (<prefix>/share/acdf), so that the program works without the source tree.
    program = os.environ["ACDF_PROGRAM"]
    beside = os.path.join(os.path.dirname(os.path.dirname(program)), "share", "acdf")
    if not os.path.isdir(beside):
        pytest.skip(f"{program} is the build tree's (no {beside}): its defaults are the source tree's")
    help_text = subprocess.run([program, "merl-gen", "--help"], check=True, capture_output=True, text=True).stdout
    assert os.path.join(beside, "merl_nbrdf_weights.json") in help_text
    subprocess.run([program, "merl-gen", "--nbrdf", "nickel", "-o", str(tmp_path / "nickel.binary")], check=True,
                   capture_output=True)
    assert os.path.getsize(tmp_path / "nickel.binary") == 12 + 3 * 8 * 90 * 90 * 180
    assert os.path.join(beside, "error_report.py") in subprocess.run(
        [program, "bench-error", "--help"], check=True, capture_output=True, text=True).stdout


def test_the_package_names_itself_and_the_project_version():
    assert acdf.__version__ == os.environ["ACDF_VERSION"]
    # help(acdf), reprs and signatures name the package users import, not the extension inside it.
    assert acdf.Cascade.__module__ == "acdf" and acdf.FileError.__module__ == "acdf"
    assert "acdf.SimplifyOptions" in acdf.Cascade.__init__.__doc__ and "_acdf" not in acdf.Cascade.__init__.__doc__
    assert "class Cascade" in pydoc.render_doc(acdf, renderer=pydoc.plaintext)


def test_simplify_options_reach_the_table(rng):
    values = rng.random((32, 16), dtype=np.float32)
    budget = acdf.SimplifyOptions(method="greedy", max_points=4, weight_bound=0.0)
    assert budget.method == "greedy" and "max_points=4" in repr(budget)
    c = acdf.Cascade(values, simplify=budget)
    assert c.points == [4, 12]  # 4 points at level 0, 3 intervals x 4 points at level 1
    assert acdf.Cascade(values, simplify=budget, epsilon=0.5).points[0] <= 4
    # The module's enum spellings are the C++ ones.
    uniform = acdf.Cascade(values, methods=["uniform", "adaptive"], conditional="average-of-normalized",
                           tolerance="mass-scaled")
    assert uniform.points[0] == 33

"""acdf.mitsuba's plugins against Mitsuba 3's own envmap and measured, in the scalar and the LLVM
variant."""
import glob
import os
import subprocess
import sys

import numpy as np
from scipy.stats import norm
import pytest

mi = pytest.importorskip("mitsuba", reason="mitsuba is not importable (run with the project's venv)")

import drjit as dr  # noqa: E402

import acdf  # noqa: E402
import acdf.mitsuba  # noqa: E402
from conftest import ROOM_CAMERA, ROOM_QUADS, WINDOW_QUAD, assert_portal_covers_window  # noqa: E402

VARIANTS = ["scalar_rgb", "llvm_ad_rgb"]
BLOCK = 8
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARED_DATA = os.environ.get("ACDF_SHARED_DATA", os.path.join(ROOT, "..", "shared", "data"))
sys.path.insert(0, os.path.join(ROOT, "bench", "peers"))
import scene_conversion as sc  # noqa: E402  (its Mitsuba rectangles)
SHARED_RGL = os.path.join(SHARED_DATA, "rgl")


@pytest.fixture(params=VARIANTS)
def variant(request):
    if request.param not in mi.variants():
        pytest.skip(f"mitsuba has no {request.param} variant")
    mi.set_variant(request.param)
    acdf.mitsuba.register()
    return request.param


@pytest.fixture(scope="module")
def block_map(tmp_path_factory):
    """A 64 x 128 map of 8 x 8 constant blocks: nearest and bilinear lookups agree in a block's middle."""
    rng = np.random.default_rng(35)
    blocks = rng.uniform(0.1, 5.0, size=(8, 16, 3)).astype(np.float32)
    path = tmp_path_factory.mktemp("maps") / "blocks.exr"
    mi.set_variant("scalar_rgb")
    mi.Bitmap(np.repeat(np.repeat(blocks, BLOCK, 0), BLOCK, 1)).write(str(path))
    return str(path), blocks


def rotation():
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    return mi.ScalarTransform4f().rotate(list(axis), 40.0)


def wide(rows):
    """Rows (n, 3) as the variant's Vector3f: one per row in scalar variants, one wide array otherwise."""
    if mi.variant().startswith("scalar"):
        return [mi.Vector3f(*r) for r in rows]
    return [mi.Vector3f(rows[:, 0], rows[:, 1], rows[:, 2])]


def rows_of(values):
    a = np.asarray(values, dtype=np.float64)
    return a.reshape(1, -1) if a.ndim <= 1 else a.T


def call(rows, f):
    """f applied to the wide form of rows, results stacked as (n, k)."""
    return np.concatenate([rows_of(f(v)) for v in wide(rows)])


def block_centres():
    r, c = np.meshgrid(np.arange(8), np.arange(16), indexing="ij")
    theta = (r.ravel() * BLOCK + BLOCK / 2) / 64 * np.pi
    phi = (c.ravel() * BLOCK + BLOCK / 2) / 128 * 2 * np.pi
    return np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], 1)


@pytest.mark.parametrize("to_world", ["identity", "rotated"])
def test_eval_equals_envmap(variant, block_map, to_world):
    path, blocks = block_map
    transform = rotation() if to_world == "rotated" else mi.ScalarTransform4f()
    common = {"filename": path, "to_world": transform, "scale": 2.0}
    ours = mi.load_dict({"type": "acdf_envmap", **common})
    theirs = mi.load_dict({"type": "envmap", **common})
    world = block_centres() @ np.array(transform.matrix)[:3, :3].T

    def evaluate(emitter):
        def f(v):
            si = mi.SurfaceInteraction3f()
            si.wi = -v
            return emitter.eval(si)

        return call(world, f)

    expected = 2.0 * blocks.reshape(-1, 3)
    np.testing.assert_allclose(evaluate(theirs), expected, rtol=1e-5)
    np.testing.assert_allclose(evaluate(ours), expected, rtol=1e-5)


@pytest.mark.parametrize("strategy", ["uniform", "alias", "adaptive", "hierarchical"])
def test_pdf_integrates_to_one_and_matches_samples(variant, block_map, strategy):
    path, _ = block_map
    emitter = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": strategy, "to_world": rotation()})
    it = mi.Interaction3f()
    # The integral: Monte Carlo over uniform directions would be noisy; a midpoint rule in
    # (cos theta, phi) with 512 x 1024 cells resolves the 64 x 128 pixels exactly up to edges.
    n_t, n_p = 512, 1024
    cos_t = 1 - 2 * (np.arange(n_t) + 0.5) / n_t
    phi = 2 * np.pi * (np.arange(n_p) + 0.5) / n_p
    c, p = np.meshgrid(cos_t, phi, indexing="ij")
    s = np.sqrt(1 - c**2)
    dirs = np.stack([s * np.sin(p), c, -s * np.cos(p)], -1).reshape(-1, 3)
    if mi.variant().startswith("scalar"):
        dirs = dirs[::257]  # a subsample: one call per direction in scalar mode
        cell = 4 * np.pi / len(dirs)
    else:
        cell = 4 * np.pi / (n_t * n_p)

    def pdf(v):
        ds = mi.DirectionSample3f()
        ds.d = v
        return emitter.pdf_direction(it, ds)

    integral = float(np.sum(call(dirs, pdf), dtype=np.float64) * cell)
    assert integral == pytest.approx(1.0, abs=1e-3 if not mi.variant().startswith("scalar") else 0.1)

    rng = np.random.default_rng(7)
    u = rng.random((4096 if not mi.variant().startswith("scalar") else 64, 2)).astype(np.float32)
    if mi.variant().startswith("scalar"):
        samples = [emitter.sample_direction(it, mi.Point2f(*x)) for x in u]
        returned = np.array([float(ds.pdf) for ds, _ in samples])
        again = np.array([float(emitter.pdf_direction(it, ds)) for ds, _ in samples])
    else:
        ds, _ = emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
        returned = np.asarray(ds.pdf, dtype=np.float64)
        again = np.asarray(emitter.pdf_direction(it, ds), dtype=np.float64)
    assert np.all(returned > 0) and np.all(np.isfinite(returned))
    np.testing.assert_allclose(again, returned, rtol=1e-5)


def test_bad_parameters_are_refused(variant, block_map):
    path, _ = block_map
    with pytest.raises(Exception, match="unknown strategy 'nonsense'"):
        mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": "nonsense"})
    with pytest.raises(Exception, match="textured scales are not supported"):
        mi.load_dict({"type": "acdf_envmap", "filename": path, "scale": {"type": "checkerboard"}})


@pytest.mark.parametrize("content", [None, b"", b"v/\x01\x01 not an exr at all"])
def test_bad_files_raise_naming_the_file(variant, tmp_path, block_map, content):
    path = tmp_path / "broken.exr"
    if content is not None:
        path.write_bytes(content)
    elif path.exists():
        path.unlink()
    with pytest.raises(Exception, match="broken.exr"):
        mi.load_dict({"type": "acdf_envmap", "filename": str(path)})


def test_truncated_file_raises_naming_the_file(variant, tmp_path, block_map):
    source, _ = block_map
    data = open(source, "rb").read()
    path = tmp_path / "truncated.exr"
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(Exception, match="truncated.exr"):
        mi.load_dict({"type": "acdf_envmap", "filename": str(path)})


def render_mean(emitter, seed, res, spp):
    """The image mean of a diffuse floor seen from above under the emitter (direct light, MIS),
    and the variance of that mean (pixels are independent)."""
    look = mi.ScalarTransform4f().look_at(origin=[0, 5, 0], target=[0, 0, 0], up=[0, 0, 1])
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 2},
        "sensor": {"type": "perspective", "fov": 30, "to_world": look,
                   "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "floor": {"type": "rectangle", "bsdf": {"type": "diffuse"},
                  "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(10)},
        "light": emitter,
    })
    pixels = np.asarray(mi.render(scene, seed=seed), dtype=np.float64).reshape(-1, 3)
    return pixels.mean(0), pixels.var(0, ddof=1) / len(pixels)


RENDERED_STRATEGIES = ["uniform", "adaptive", "local", "compensated"]


@pytest.mark.parametrize("strategy", RENDERED_STRATEGIES)
def test_render_mean_equals_envmap(variant, tmp_path, strategy):
    """The image means of one scene under envmap and acdf_envmap agree within noise (z-test,
    alpha = 0.01 Sidak-corrected over the channels and the cases of this test). The map is
    constant in theta and in blocks of 16 columns, where nearest and bilinear lookups integrate
    alike; one column is 40x brighter than the rest, so sampling matters."""
    rng = np.random.default_rng(3)
    columns = rng.uniform(0.05, 1.0, size=(1, 8, 3)).astype(np.float32)
    columns[0, 3] = 40.0
    path = str(tmp_path / "columns.exr")
    mi.Bitmap(np.repeat(np.repeat(columns, 64, 0), 16, 1)).write(path)
    common = {"filename": path, "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], 30)}
    res, spp = (16, 16) if variant.startswith("scalar") else (64, 64)
    m0, v0 = render_mean({"type": "envmap", **common}, 1, res, spp)
    m1, v1 = render_mean({"type": "acdf_envmap", "strategy": strategy, **common}, 2, res, spp)
    z = (m1 - m0) / np.sqrt(v0 + v1)
    tests = 3 * len(RENDERED_STRATEGIES) * len(VARIANTS)
    bound = norm.ppf(1 - acdf.sidak_alpha(0.01, tests) / 2)
    assert np.all(np.abs(z) < bound), f"z = {z}, bound {bound:.2f}, means {m0} vs {m1}"


def test_a_map_declaring_other_primaries_is_the_same_light_as_envmaps(variant, reference):
    """A map saved in ProPhoto RGB with a D50 white (its EXR declares the chromaticities): acdf
    converts it to Rec. 709 as Mitsuba does, so the radiance at every block's centre equals
    envmap's, and so does the image mean of a floor under it (z-test, alpha 0.01 Sidak-corrected
    over the channels and the variants)."""
    path = reference.path("blocks_prophoto.exr")
    ours = mi.load_dict({"type": "acdf_envmap", "filename": path})
    theirs = mi.load_dict({"type": "envmap", "filename": path})

    def evaluate(emitter):
        def f(v):
            si = mi.SurfaceInteraction3f()
            si.wi = -v
            return emitter.eval(si)

        return call(block_centres(), f)

    expected = evaluate(theirs)
    np.testing.assert_allclose(evaluate(ours), expected, rtol=1e-5)
    declared = acdf.EnvironmentMap.load(path).declared_chromaticities
    assert declared["white"] == pytest.approx((0.3457, 0.3585), abs=1e-6)
    assert acdf.EnvironmentMap.load(reference.path("sky.exr")).declared_chromaticities is None
    stored = reference.f32("prophoto_blocks").reshape(-1, 3)
    assert np.max(np.abs(expected / stored - 1)) > 0.1, "the file's values needed no conversion"
    res, spp = (16, 16) if variant.startswith("scalar") else (64, 64)
    m0, v0 = render_mean({"type": "envmap", "filename": path}, 1, res, spp)
    m1, v1 = render_mean({"type": "acdf_envmap", "filename": path}, 2, res, spp)
    z = (m1 - m0) / np.sqrt(v0 + v1)
    bound = norm.ppf(1 - acdf.sidak_alpha(0.01, 3 * len(VARIANTS)) / 2)
    assert np.all(np.abs(z) < bound), f"z = {z}, bound {bound:.2f}, means {m0} vs {m1}"


WEIGHED_STRATEGIES = ["uniform", "alias", "adaptive", "local", "hierarchical"]


def mean_emitter_weight(emitter, n, seed):
    """The mean of an emitter's sample_direction weights (L / pdf) over n uniform variates from an
    interaction without a normal, and its standard error, per channel."""
    u = np.random.default_rng(seed).random((n, 2)).astype(np.float32)
    if mi.variant().startswith("scalar"):
        it = mi.Interaction3f()
        weights = np.array([np.asarray(emitter.sample_direction(it, mi.Point2f(*x))[1]) for x in u], np.float64)
    else:
        _, w = emitter.sample_direction(dr.zeros(mi.Interaction3f, n), mi.Point2f(u[:, 0], u[:, 1]))
        weights = rows_of(w)
    return weights.mean(0), weights.std(0, ddof=1) / np.sqrt(n)


@pytest.mark.parametrize("strategy", WEIGHED_STRATEGIES)
def test_mean_sample_weight_equals_envmaps(variant, block_map, strategy):
    """An emitter sample's weight is L / pdf of its own direction, so its mean is the map's power
    whichever the sampling: acdf_envmap's equals envmap's within their standard errors (z-test,
    alpha 0.01 Sidak-corrected over channels, strategies and variants). With a module that reads
    NumPy 2's arrays wrongly, every lane of a wavefront got lane 0's pdf: a mean off by 1000x."""
    path, _ = block_map
    n = 4000 if variant.startswith("scalar") else 1 << 18
    common = {"filename": path, "to_world": rotation()}
    theirs, se0 = mean_emitter_weight(mi.load_dict({"type": "envmap", **common}), n, 1)
    ours, se1 = mean_emitter_weight(mi.load_dict({"type": "acdf_envmap", "strategy": strategy, **common}), n, 2)
    z = (ours - theirs) / np.sqrt(se0**2 + se1**2)
    bound = norm.ppf(1 - acdf.sidak_alpha(0.01, 3 * len(WEIGHED_STRATEGIES) * len(VARIANTS)) / 2)
    assert np.all(np.abs(z) < bound), f"z = {z}, bound {bound:.2f}, means {theirs} vs {ours}"


def test_scalar_render_of_the_example_returns(tmp_path, block_map):
    """examples/mitsuba/render.py in scalar_rgb, as a user would start it, finishes (in its own
    process, so that a render that never returns fails here instead of stalling the suite) and
    writes a finite, lit image."""
    if "scalar_rgb" not in mi.variants():
        pytest.skip("mitsuba has no scalar_rgb variant")
    path, _ = block_map
    program = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))
    material = str(tmp_path / "gold.bsdf")
    subprocess.run([program, "rgl-gen", "--preset", "gold", "-o", material], check=True, capture_output=True)
    image = str(tmp_path / "scalar.exr")
    subprocess.run([sys.executable, os.path.join(ROOT, "examples", "mitsuba", "render.py"), path, material, image,
                    "--variant", "scalar_rgb", "--spp", "2", "--size", "24x18"], check=True, capture_output=True,
                   timeout=300)
    mi.set_variant("scalar_rgb")
    pixels = np.asarray(mi.Bitmap(image), dtype=np.float64)
    assert pixels.shape[:2] == (18, 24) and np.all(np.isfinite(pixels)) and pixels.mean() > 0.01


def test_compensated_pdf_leaves_out_the_dim_directions(variant, block_map):
    """compensated's pdf is zero somewhere (the map minus its mean) and integrates to less than one
    with the rest of its mass where the map is bright; adaptive's is positive everywhere."""
    path, blocks = block_map
    dirs = block_centres()
    it = mi.Interaction3f()

    def pdfs(strategy):
        emitter = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": strategy})

        def pdf(v):
            ds = mi.DirectionSample3f()
            ds.d = v
            return emitter.pdf_direction(it, ds)

        return call(dirs, pdf).ravel()

    luminance = blocks.reshape(-1, 3) @ np.array([0.2126, 0.7152, 0.0722])
    compensated, adaptive = pdfs("compensated"), pdfs("adaptive")
    assert np.all(adaptive > 0)
    assert np.any(compensated == 0)
    assert np.all(compensated[luminance < 0.5 * luminance.mean()] == 0)
    assert np.all(compensated[luminance > 2.0 * luminance.mean()] > 0)


def test_sample_ray_carries_the_lights_power(variant, block_map):
    """Rays leaving acdf_envmap: each starts outside the scene's bounding sphere and passes through
    it, its weight is pi R^2 L(-d) / pdf(-d), and their mean weight is the power pi R^2 \u222b L,
    the integral taken over the map's pixels exactly (z-test, alpha 0.01 Sidak-corrected)."""
    path, blocks = block_map
    scene_dict = {
        "type": "scene",
        "ball": {"type": "sphere", "center": [0.5, 0, 0], "radius": 2.0 / np.sqrt(3)},
        "light": {"type": "acdf_envmap", "filename": path, "to_world": rotation()},
    }
    unbounded = mi.load_dict(scene_dict).emitters()[0]
    with pytest.raises(Exception, match="bounding sphere"):
        unbounded.sample_ray(0.0, 0.5, mi.Point2f(0.5, 0.5), mi.Point2f(0.5, 0.5))
    emitter = acdf.mitsuba.load_dict(scene_dict).emitters()[0]
    radius = 2.0 * (1 + 1e-4)
    n = 200 if variant.startswith("scalar") else 200000
    u = np.random.default_rng(7).random((n, 4)).astype(np.float32)
    if variant.startswith("scalar"):
        rays = [emitter.sample_ray(0.0, 0.5, mi.Point2f(*r[:2]), mi.Point2f(*r[2:])) for r in u]
        origins = np.array([np.asarray(r.o) for r, _ in rays], dtype=np.float64)
        dirs = np.array([np.asarray(r.d) for r, _ in rays], dtype=np.float64)
        weights = np.array([np.asarray(w) for _, w in rays], dtype=np.float64)
    else:
        ray, w = emitter.sample_ray(0.0, 0.5, mi.Point2f(u[:, 0], u[:, 1]), mi.Point2f(u[:, 2], u[:, 3]))
        origins, dirs, weights = rows_of(ray.o), rows_of(ray.d), rows_of(w)
    centre = np.array([0.5, 0.0, 0.0])
    to_centre = centre - origins
    assert np.all(np.linalg.norm(to_centre, axis=1) >= radius * (1 - 1e-5))
    along = np.sum(to_centre * dirs, axis=1)
    assert np.all(along > 0)
    miss = np.linalg.norm(to_centre - along[:, None] * dirs, axis=1)
    assert np.all(miss <= radius * (1 + 1e-5))

    light = acdf.EnvironmentLight.load(path)
    map_dirs = -dirs @ np.array(rotation().matrix)[:3, :3]  # world to map: the rotation's inverse
    expected = np.pi * radius**2 * light.eval(map_dirs) / light.pdf(map_dirs)[:, None]
    np.testing.assert_allclose(weights, expected, rtol=2e-3)

    rows, columns = 64, 128
    edges = np.cos(np.arange(rows + 1) * np.pi / rows)
    solid_angles = (edges[:-1] - edges[1:]) * 2 * np.pi / columns
    pixels = np.repeat(np.repeat(blocks, BLOCK, 0), BLOCK, 1).astype(np.float64)
    power = np.pi * radius**2 * np.einsum("r,rcx->x", solid_angles, pixels)
    z = (weights.mean(0) - power) / (weights.std(0, ddof=1) / np.sqrt(n))
    bound = norm.ppf(1 - acdf.sidak_alpha(0.01, 3 * len(VARIANTS)) / 2)
    assert np.all(np.abs(z) < bound), f"z = {z}, bound {bound:.2f}"


PIXEL_TABLE_STRATEGIES = ["uniform", "alias", "adaptive", "compensated", "hierarchical"]


def sunset_or(block_map):
    """The shared sunset map, else the block map."""
    shared = os.path.join(SHARED_DATA, "envmaps", "sunset_1024x512.exr")
    return shared if os.path.exists(shared) else block_map[0]


def native_envmap(block_map, strategy):
    """acdf_envmap of the shared sunset map (else the block map) turned by rotation(), sampled in drjit, and
    acdf's C++ light of the same file and strategy (the plugin keeps only its drjit arrays)."""
    path = sunset_or(block_map)
    emitter = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": strategy, "to_world": rotation()})
    assert "Native" in type(emitter).__name__
    return emitter, acdf.EnvironmentLight.load(path, strategy=strategy)


def map_pixels(d, width, height):
    """The row-major pixel of each map-frame direction (acdf's lat-long mapping), in double."""
    theta = np.arctan2(np.hypot(d[:, 0], d[:, 2]), d[:, 1])
    phi = np.mod(np.arctan2(d[:, 0], -d[:, 2]), 2 * np.pi)
    row = np.minimum((theta / np.pi * height).astype(np.int64), height - 1)
    return row * width + np.minimum((phi / (2 * np.pi) * width).astype(np.int64), width - 1)


@pytest.mark.parametrize("strategy", PIXEL_TABLE_STRATEGIES)
def test_llvm_envmap_samples_acdfs_table_in_drjit(block_map, strategy):
    """In llvm_ad_rgb acdf_envmap samples acdf's own table with drjit operations. 10^6 samples of the
    shared sunset map (or the block map): pdf_direction of each sample is its returned pdf, bit for
    bit; the pdf is acdf's at that direction (float32 against double, 1e-5); the sample lies in the
    pixel acdf's C++ sampler picks for the same variates (all but rounding cases at pixel edges); and
    the pixels' counts fit acdf's exact pixel probabilities (chi-square, cells pooled to an expected
    count >= 5, alpha 0.01 Sidak-corrected over the strategies). At the corners of the variates' range
    (0 and the largest float below 1) a sample is a unit direction with finite weight and a finite
    positive pdf, and so is pdf_direction there (not necessarily equal: the corners' pixels touch the
    poles, where the rotation's float32 rounding can move a direction into the next column)."""
    if "llvm_ad_rgb" not in mi.variants():
        pytest.skip("mitsuba has no llvm_ad_rgb variant")
    mi.set_variant("llvm_ad_rgb")
    acdf.mitsuba.register()
    from test_chi_square import pooled_chi_square

    emitter, light = native_envmap(block_map, strategy)
    n = 1_000_000
    it = dr.zeros(mi.Interaction3f)
    below_one = np.nextafter(np.float32(1), np.float32(0))
    corners = np.array([[0, 0], [0, below_one], [below_one, 0], [below_one, below_one]], dtype=np.float32)
    ds, weight = emitter.sample_direction(it, mi.Point2f(corners[:, 0], corners[:, 1]))
    np.testing.assert_allclose(np.linalg.norm(rows_of(ds.d), axis=1), 1, rtol=1e-6)
    for pdf in (np.asarray(ds.pdf), np.asarray(emitter.pdf_direction(it, ds))):
        assert np.all(pdf > 0) and np.all(np.isfinite(pdf)) and np.all(np.isfinite(rows_of(weight)))

    u = np.random.default_rng(1).random((n, 2)).astype(np.float32)
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
    pdf = np.asarray(ds.pdf)
    assert np.all(pdf > 0) and np.all(np.isfinite(pdf))
    np.testing.assert_array_equal(np.asarray(emitter.pdf_direction(it, ds)), pdf)

    dirs = rows_of(ds.d) @ np.array(rotation().matrix)[:3, :3]  # world to map: the rotation's inverse
    np.testing.assert_allclose(light.pdf(dirs, allow_incomplete_pdf=emitter.incomplete), pdf, rtol=1e-5)
    width, height = light.map.width, light.map.height

    acdf_dirs, acdf_radiance, acdf_pdf = light.sample(u, allow_incomplete_pdf=emitter.incomplete)
    ours = map_pixels(dirs, width, height)
    assert np.count_nonzero(ours != map_pixels(acdf_dirs, width, height)) <= n * 1e-5
    np.testing.assert_allclose(rows_of(weight).mean(0), (acdf_radiance / acdf_pdf[:, None]).mean(0), rtol=1e-5)

    probabilities = light.pixel_probabilities(allow_incomplete_pdf=emitter.incomplete).reshape(-1)
    observed = np.bincount(ours, minlength=probabilities.size).astype(np.float64)
    statistic, dof = pooled_chi_square(observed, probabilities * n)
    alpha = acdf.sidak_alpha(0.01, len(PIXEL_TABLE_STRATEGIES))
    from scipy.stats import chi2

    assert chi2.sf(statistic, dof) > alpha, f"chi-square {statistic:.1f} with {dof} degrees of freedom"


def window():
    """A 1.4 x 1.1 rectangle in the plane z = 2 whose normal (-z) points into a room around the origin."""
    return {"type": "rectangle",
            "to_world": mi.ScalarTransform4f().translate([0.0, 1.45, 2.0]).rotate([0, 1, 0], 180).scale([0.7, 0.55, 1])}


@pytest.mark.parametrize("strategy", ["adaptive", "compensated", "local", "hierarchical", "uniform-sphere"])
def test_llvm_portals_sample_as_acdfs_light_in_drjit(block_map, strategy):
    """acdf_envmap with a nested rectangle as a portal, in drjit, at 10^6 lanes lit from points inside
    the room (and some behind the window, which see no portal): pdf_direction of each sample is its
    returned pdf, bit for bit; acdf's C++ light with the plugin's portals gives the same direction for
    the same variates and point (through the portal all but 1e-4 of the lanes within 1e-6 rad, from
    the tables in the same pixel) and the same pdf at it (float32 against double); every portal
    sample of the lanes inside (all but 1e-4) passes through the window, so at least the portal
    share of their samples does; the pdf integrates to 1 over the sphere from a point inside (Monte
    Carlo within 5 standard errors)."""
    if "llvm_ad_rgb" not in mi.variants():
        pytest.skip("mitsuba has no llvm_ad_rgb variant")
    mi.set_variant("llvm_ad_rgb")
    acdf.mitsuba.register()
    path = sunset_or(block_map)
    emitter = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": strategy, "to_world": rotation(),
                            "window": window()})
    assert "Native" in type(emitter).__name__ and len(emitter.portals) == 1
    to_map = np.array(rotation().matrix)[:3, :3].T
    light = acdf.EnvironmentLight.load(path, strategy=strategy, portals=[
        {key: to_map @ value for key, value in portal.items()} for portal in emitter.portals])

    n = 1_000_000
    rng = np.random.default_rng(7)
    u = rng.random((n, 2)).astype(np.float32)
    points = rng.uniform([-1.5, 0.1, -1.5], [1.5, 2.5, 1.9], (n, 3)).astype(np.float32)
    points[: n // 10, 2] = 2.5  # behind the window: no portal seen
    normals = rng.normal(size=(n, 3))
    normals = (normals / np.linalg.norm(normals, axis=1, keepdims=True)).astype(np.float32)
    it = dr.zeros(mi.SurfaceInteraction3f, n)
    it.p = mi.Point3f(*points.T)
    it.n = mi.Normal3f(*normals.T)
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
    pdf = np.asarray(ds.pdf)
    assert np.all(pdf > 0) and np.all(np.isfinite(pdf))
    np.testing.assert_array_equal(np.asarray(emitter.pdf_direction(it, ds)), pdf)

    world = rows_of(ds.d)
    dirs = world @ to_map.T
    in_map = points.astype(np.float64) @ to_map.T
    normal_in_map = normals.astype(np.float64) @ to_map.T
    incomplete = emitter.incomplete
    acdf_dirs, _, acdf_pdf = light.sample(u, normal=normal_in_map, position=in_map, allow_incomplete_pdf=incomplete)
    # Through the portal the direction is acdf's to float32; from a table, in the same pixel.
    inside = np.arange(n) >= n // 10
    share = acdf.EnvironmentLight.portal_share(incomplete)
    portal_lanes = inside & (u[:, 0] < share)
    apart = np.linalg.norm(acdf_dirs - dirs / np.linalg.norm(dirs, axis=1, keepdims=True), axis=1)  # ~ the angle
    assert np.count_nonzero(apart[portal_lanes] > 1e-6) <= n * 1e-4
    if strategy != "uniform-sphere":  # Mitsuba's sphere warp is not acdf's; its pdf is checked below
        width, height = light.map.width, light.map.height
        assert np.count_nonzero(map_pixels(dirs, width, height) != map_pixels(acdf_dirs, width, height)) <= n * 1e-4
    ours = light.pdf(dirs, normal=normal_in_map, position=in_map, allow_incomplete_pdf=incomplete)
    assert np.count_nonzero(np.abs(ours - pdf) > 1e-4 * ours) <= n * 1e-4

    hits = (2.0 - points[:, 2]) / world[:, 2]
    x, y = points[:, 0] + hits * world[:, 0], points[:, 1] + hits * world[:, 1]
    through = (hits > 0) & (np.abs(x) <= 0.7) & (y >= 0.9) & (y <= 2.0)
    assert np.count_nonzero(~through[portal_lanes]) <= n * 1e-4
    assert through[inside].mean() >= share and through[~inside].mean() < 0.5

    point = np.array([[0.3, 1.2, 0.5]])
    w = rng.normal(size=(2_000_000, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    lanes = len(w)
    it = dr.zeros(mi.SurfaceInteraction3f, lanes)
    it.p = mi.Point3f(*np.repeat(point, lanes, 0).astype(np.float32).T)
    it.n = mi.Normal3f(*np.repeat([[0.0, 0.0, 1.0]], lanes, 0).astype(np.float32).T)
    dsw = dr.zeros(mi.DirectionSample3f, lanes)
    dsw.d = mi.Vector3f(*w.astype(np.float32).T)
    f = 4 * np.pi * np.asarray(emitter.pdf_direction(it, dsw), dtype=np.float64)
    assert abs(f.mean() - 1.0) < 5 * f.std() / np.sqrt(lanes)


def test_portals_are_rectangles_that_acdf_can_use(variant, block_map):
    """A portal that is not a rectangle, or a degenerate one, is refused naming it; one declared in an XML
    scene is read, and is not geometry; in the scalar variant (batched calls) the samples are acdf's
    light's from the interaction's point."""
    path = block_map[0]
    for child, problem in [({"type": "sphere"}, "must be a rectangle"),
                           ({"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([1, 0, 1])}, "edges")]:
        with pytest.raises(RuntimeError, match=f"acdf_envmap: portal door: .*{problem}"):
            mi.load_dict({"type": "acdf_envmap", "filename": path, "door": child})
    scene = mi.load_string(f"""<scene version="3.0.0"><shape type="sphere"/>
        <emitter type="acdf_envmap"><string name="filename" value="{path}"/>
            <shape type="rectangle" name="window"><transform name="to_world"><scale x="0.7" y="0.55"/>
                <rotate y="1" angle="180"/><translate x="0" y="1.45" z="2"/></transform></shape></emitter></scene>""")
    (portal,) = scene.emitters()[0].portals
    assert len(scene.shapes()) == 1  # a portal is not geometry
    assert np.allclose(portal["corner"], [0.7, 0.9, 2.0]) and np.allclose(portal["edge_v"], [0, 1.1, 0])
    if not variant.startswith("scalar"):
        return
    emitter = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": "compensated", "window": window()})
    light = acdf.EnvironmentLight.load(path, strategy="compensated", portals=emitter.portals)
    it = mi.SurfaceInteraction3f()
    it.p = mi.Point3f(0.3, 1.2, 0.5)
    it.n = mi.Normal3f(0, 1, 0)
    rng = np.random.default_rng(3)
    for u in rng.random((32, 2)).astype(np.float32):
        ds, _ = emitter.sample_direction(it, mi.Point2f(*u))
        d, _, pdf = light.sample(u.reshape(1, 2), position=[0.3, 1.2, 0.5], allow_incomplete_pdf=True)
        np.testing.assert_allclose(rows_of(ds.d)[0], d[0], atol=1e-6)
        np.testing.assert_allclose(float(ds.pdf), pdf[0], rtol=1e-6)
        np.testing.assert_allclose(float(emitter.pdf_direction(it, ds)), pdf[0], rtol=1e-5)


def room_scene(path, emitter_options, window=True, extra_shapes=()):
    """conftest's room in Mitsuba: rectangles, a sphere, its camera (fov along y) and acdf_envmap."""
    camera = ROOM_CAMERA
    scene = {"type": "scene",
             "sensor": {"type": "perspective", "fov": camera["fov"], "fov_axis": "y",
                        "to_world": mi.ScalarTransform4f().look_at(origin=camera["eye"], target=camera["target"],
                                                                   up=camera["up"]),
                        "film": {"type": "hdrfilm", "width": camera["width"], "height": camera["height"]}},
             "ball": {"type": "sphere", "center": [0.0, 0.5, 0.0], "radius": 0.5},
             "light": {"type": "acdf_envmap", "filename": path, **emitter_options}}
    quads = ROOM_QUADS + ([] if window else [WINDOW_QUAD])
    scene.update({f"wall-{i}": {"type": "rectangle", "to_world": mi.ScalarTransform4f(sc.mitsuba_rectangle(*quad))}
                  for i, quad in enumerate(quads)})
    scene.update({f"extra-{i}": shape for i, shape in enumerate(extra_shapes)})
    return scene


def test_load_dict_finds_a_rooms_window_and_makes_it_a_portal(variant, block_map):
    """acdf.mitsuba.load_dict gives acdf_envmap its scene: where no portal is declared (portals "auto",
    the default) the window of a room is found (acdf.find_openings on the scene's meshes and spheres
    from its sensor) and becomes the light's portal, sampled from inside (every sample of a
    compensated light from a point inside passes through the window, in drjit too). "declared" and
    "none" do not search, "none" drops declared portals; a scene with a shape the search cannot read
    (a disk), a sealed room, or mi.load_dict (which does not call Python emitters' set_scene) get
    none; an unknown value is refused."""
    path = block_map[0]
    emitter = acdf.mitsuba.load_dict(room_scene(path, {"strategy": "compensated"})).emitters()[0]
    (portal,) = emitter.openings["portals"]
    assert_portal_covers_window(portal)
    assert 0 < emitter.openings["escaped_share"] < 0.25
    (used,) = emitter.portals
    np.testing.assert_array_equal(used["corner"], portal["corner"])
    u = np.random.default_rng(5).random((64 if variant.startswith("scalar") else 4096, 2)).astype(np.float32)
    if variant.startswith("scalar"):
        it = mi.SurfaceInteraction3f()
        it.p, it.n = mi.Point3f(0.3, 1.2, 0.5), mi.Normal3f(0, 1, 0)
        d = np.concatenate([rows_of(emitter.sample_direction(it, mi.Point2f(*row))[0].d) for row in u])
    else:  # the drjit tables of the portal found
        it = dr.zeros(mi.SurfaceInteraction3f, len(u))
        it.p, it.n = mi.Point3f(0.3, 1.2, 0.5), mi.Normal3f(0, 1, 0)
        d = rows_of(emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))[0].d)
    hit = np.array([0.3, 1.2, 0.5]) + ((2.0 - 0.5) / d[:, 2])[:, None] * d
    assert np.all((d[:, 2] > 0) & (np.abs(hit[:, 0]) <= 0.75) & (hit[:, 1] >= 0.85) & (hit[:, 1] <= 2.05))

    for options in [{"portals": "declared"}, {"portals": "none", "door": window()}]:
        emitter = acdf.mitsuba.load_dict(room_scene(path, options)).emitters()[0]
        assert emitter.openings is None and emitter.portals == []
    declared = acdf.mitsuba.load_dict(room_scene(path, {"door": window()})).emitters()[0]
    assert declared.openings is None and len(declared.portals) == 1
    sealed = acdf.mitsuba.load_dict(room_scene(path, {}, window=False)).emitters()[0]
    assert sealed.openings["portals"] == [] and sealed.openings["escaped_share"] == 0 and sealed.portals == []
    unreadable = acdf.mitsuba.load_dict(room_scene(path, {}, extra_shapes=[{"type": "disk"}])).emitters()[0]
    assert unreadable.openings is None and unreadable.portals == []
    assert mi.load_dict(room_scene(path, {})).emitters()[0].openings is None
    with pytest.raises(RuntimeError, match="acdf_envmap: unknown portals 'sometimes'; one of auto, declared, none"):
        mi.load_dict({"type": "acdf_envmap", "filename": path, "portals": "sometimes"})


LOCAL_STRATEGIES = ["local", "local-compensated"]


@pytest.mark.parametrize("strategy", LOCAL_STRATEGIES)
def test_llvm_local_envmap_samples_each_normals_table_in_drjit(block_map, strategy):
    """In llvm_ad_rgb acdf_envmap with local tables samples, in drjit, the table of each lane's normal
    cell (it.n in the map frame), and lanes without a normal the complete adaptive table, as acdf's
    C++ light does. 10^6 samples of the shared sunset map (or the block map) at random normals, one
    lane in 8 without one: pdf_direction of each sample is its returned pdf, bit for bit; the pdf is
    acdf's for that normal (float32 against double, 1e-5); the sample lies in the pixel acdf's C++
    sampler picks for the same variates and normal (all but rounding cases at pixel edges); and at one
    tilted normal the pixels' counts fit acdf's exact pixel probabilities, its pdf times the pixel's
    solid angle (chi-square, cells pooled to an expected count >= 5, alpha 0.01 Sidak-corrected over
    the strategies)."""
    if "llvm_ad_rgb" not in mi.variants():
        pytest.skip("mitsuba has no llvm_ad_rgb variant")
    mi.set_variant("llvm_ad_rgb")
    acdf.mitsuba.register()
    from scipy.stats import chi2
    from test_chi_square import pooled_chi_square

    emitter, light = native_envmap(block_map, strategy)
    incomplete = emitter.incomplete
    width, height = light.map.width, light.map.height
    to_map = np.array(rotation().matrix, dtype=np.float64)[:3, :3]  # world to map: rows @ to_map
    n = 1_000_000
    rng = np.random.default_rng(5)
    u = rng.random((n, 2)).astype(np.float32)
    normals = rng.normal(size=(n, 3)).astype(np.float32)
    normals[::8] = 0  # no normal: a medium interaction's
    it = dr.zeros(mi.Interaction3f, n)
    it.n = mi.Normal3f(normals[:, 0], normals[:, 1], normals[:, 2])
    ds, weight = emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
    pdf = np.asarray(ds.pdf)
    assert np.all(pdf > 0) and np.all(np.isfinite(pdf))
    np.testing.assert_array_equal(np.asarray(emitter.pdf_direction(it, ds)), pdf)

    has_normal = np.any(normals != 0, axis=1)

    def acdf_calls(f, rows):
        """The results of f(rows, ...) of acdf's C++ light: lanes with a normal given it, the others not."""
        parts = (f(rows[has_normal], normal=normals[has_normal].astype(np.float64) @ to_map,
                   allow_incomplete_pdf=incomplete), f(rows[~has_normal], allow_incomplete_pdf=incomplete))
        merged = []
        for with_normal, without in zip(*(p if isinstance(p, tuple) else (p,) for p in parts)):
            result = np.empty((n, *with_normal.shape[1:]), with_normal.dtype)
            result[has_normal], result[~has_normal] = with_normal, without
            merged.append(result)
        return merged

    dirs = rows_of(ds.d) @ to_map
    np.testing.assert_allclose(acdf_calls(light.pdf, dirs)[0], pdf, rtol=1e-5)
    acdf_dirs, acdf_radiance, acdf_pdf = acdf_calls(light.sample, u)
    ours = map_pixels(dirs, width, height)
    assert np.count_nonzero(ours != map_pixels(acdf_dirs, width, height)) <= n * 1e-5
    np.testing.assert_allclose(rows_of(weight).mean(0), (acdf_radiance / acdf_pdf[:, None]).mean(0), rtol=1e-5)

    tilted = np.array([0.3, 0.8, 0.5], dtype=np.float32) / np.float32(np.linalg.norm([0.3, 0.8, 0.5]))
    it = dr.zeros(mi.Interaction3f, n)
    it.n = mi.Normal3f(*(np.full(n, x, dtype=np.float32) for x in tilted))
    ds, _ = emitter.sample_direction(it, mi.Point2f(u[:, 0], u[:, 1]))
    observed = np.bincount(map_pixels(rows_of(ds.d) @ to_map, width, height), minlength=width * height)
    observed = observed.astype(np.float64)
    edges = np.cos(np.arange(height + 1) * np.pi / height)
    theta = np.repeat((np.arange(height) + 0.5) * np.pi / height, width)
    phi = np.tile((np.arange(width) + 0.5) * 2 * np.pi / width, height)
    centres = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], 1)
    solid_angles = np.repeat((edges[:-1] - edges[1:]) * 2 * np.pi / width, width)
    probabilities = light.pdf(centres, normal=tilted.astype(np.float64) @ to_map,
                              allow_incomplete_pdf=incomplete) * solid_angles
    assert probabilities.sum() == pytest.approx(1.0, abs=1e-5)
    statistic, dof = pooled_chi_square(observed, probabilities * n)
    alpha = acdf.sidak_alpha(0.01, len(LOCAL_STRATEGIES))
    assert chi2.sf(statistic, dof) > alpha, f"chi-square {statistic:.1f} with {dof} degrees of freedom"


def test_unknown_parameters_are_refused_and_table_options_reach_acdf(variant, block_map, rgl_files):
    path, _ = block_map
    with pytest.raises(Exception, match="acdf_envmap: unsupported parameter.*mis_compensation"):
        mi.load_dict({"type": "acdf_envmap", "filename": path, "mis_compensation": True})
    with pytest.raises(Exception, match="acdf_measured: unsupported parameter.*alpha"):
        mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "alpha": 0.1})
    with pytest.raises(Exception, match="apply to adaptive and uniform sampling, not rgl"):
        mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "sampling": "rgl", "chi2_epsilon": 1e-3})
    coarse = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": "local", "normal_rows": 4,
                           "normal_columns": 8, "block_size": 4})
    fine = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": "local"})
    same = acdf.EnvironmentLight.load(path, strategy="local", normal_rows=4, normal_columns=8, block_size=4)
    for light in [same] + [emitter.light for emitter in (coarse, fine) if hasattr(emitter, "light")]:
        light.local_arrays()  # builds every normal cell's table (the drjit plugin's have), so bytes compare
    assert coarse.bytes == same.bytes != fine.bytes
    small = mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "sampling": "uniform",
                          "theta_half": 32, "phi_half": 8})
    default = mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "sampling": "uniform"})
    assert small.bytes < default.bytes


def test_scenes_in_xml_name_the_plugins(variant, block_map, rgl_files):
    path, _ = block_map
    scene = mi.load_string(f"""<scene version="3.0.0">
        <emitter type="acdf_envmap"><string name="filename" value="{path}"/>
            <string name="strategy" value="compensated"/><float name="scale" value="2"/></emitter>
        <shape type="sphere"><bsdf type="acdf_measured"><string name="filename" value="{rgl_files[0]}"/>
            <string name="sampling" value="adaptive"/></bsdf></shape>
    </scene>""")
    assert "AcdfEnvmap[strategy=compensated" in str(scene.emitters()[0])
    assert "AcdfMeasured[sampling=adaptive" in str(scene.shapes()[0].bsdf())


def test_jit_variants_get_the_drjit_classes_and_scalar_ones_the_batched(variant, block_map, rgl_files):
    """Whatever the strategy (every one of acdf.environment_samplings()) or the sampling, register()
    gives JIT variants the plugins that sample in drjit and scalar variants the batched ones."""
    kind = "Batched" if variant.startswith("scalar") else "Native"
    path, _ = block_map
    for strategy in (s["name"] for s in acdf.environment_samplings()):
        emitter = mi.load_dict({"type": "acdf_envmap", "filename": path, "strategy": strategy})
        assert type(emitter).__name__ == f"{kind}Envmap", strategy
    for sampling in ("adaptive", "uniform", "rgl", "cosine"):
        bsdf = mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "sampling": sampling})
        assert type(bsdf).__name__ == f"{kind}Measured", sampling


@pytest.mark.parametrize("strategy", ["adaptive", "local", "local-compensated", "alias", "hierarchical"])
def test_llvm_renders_make_no_acdf_call(tmp_path, block_map, strategy):
    """In llvm_ad_rgb a render of 32 x 32 pixels at 4 spp makes no acdf call at all: acdf_envmap,
    whatever its strategy, and acdf_measured, whatever its sampling (here the file's own warps, rgl,
    on the sphere and acdf's table on the floor), hold only drjit arrays, which drjit samples. The
    render runs with drjit's symbolic modes on: register() leaves them as they are."""
    if "llvm_ad_rgb" not in mi.variants():
        pytest.skip("mitsuba has no llvm_ad_rgb variant")
    mi.set_variant("llvm_ad_rgb")
    symbolic = (dr.JitFlag.SymbolicLoops, dr.JitFlag.SymbolicCalls, dr.JitFlag.SymbolicConditionals)
    for flag in symbolic:
        dr.set_flag(flag, True)
    acdf.mitsuba.register()
    path, _ = block_map
    program = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))
    material = str(tmp_path / "aluminium.bsdf")
    subprocess.run([program, "rgl-gen", "--preset", "rough-aluminium", "-o", material], check=True, capture_output=True)
    sensor = {"type": "perspective", "fov": 40,
              "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
              "film": {"type": "hdrfilm", "width": 32, "height": 32, "rfilter": {"type": "box"}},
              "sampler": {"type": "independent", "sample_count": 4}}
    scene = mi.load_dict({"type": "scene", "integrator": {"type": "path", "max_depth": 3}, "sensor": sensor,
                          "ball": {"type": "sphere", "bsdf": {"type": "acdf_measured", "filename": material,
                                                             "sampling": "rgl"}},
                          "floor": {"type": "rectangle", "bsdf": {"type": "acdf_measured", "filename": material},
                                    "to_world": mi.ScalarTransform4f().translate([0, 0, -1]).scale(3)},
                          "light": {"type": "acdf_envmap", "filename": path, "strategy": strategy}})
    assert all(dr.flag(flag) for flag in symbolic)
    emitter = scene.emitters()[0]
    bsdfs = [shape.bsdf() for shape in scene.shapes()]
    assert [type(bsdf).__name__ for bsdf in bsdfs] == ["NativeMeasured", "NativeMeasured"]
    # None holds an acdf object to call (nor its memory), only drjit arrays.
    assert not any(hasattr(bsdf, "sampler") or hasattr(bsdf, "model") for bsdf in bsdfs)
    assert not hasattr(emitter, "light")
    assert f"bytes={emitter.bytes}" in str(emitter) and emitter.bytes > 0
    image = np.asarray(mi.render(scene))
    assert np.all(np.isfinite(image)) and image.mean() > 0


def test_shadow_rays_reach_past_a_large_scene(variant, block_map):
    """A point inside a closed sphere of radius 100 sees none of the light: every emitter sample's
    shadow ray is blocked, whatever the scene's size."""
    path, _ = block_map
    scene = mi.load_dict({
        "type": "scene",
        "shell": {"type": "sphere", "radius": 100.0, "flip_normals": True},
        "light": {"type": "acdf_envmap", "filename": path},
    })
    it = dr.zeros(mi.Interaction3f)
    it.p = mi.Point3f(1.0, 2.0, 3.0)
    u = np.random.default_rng(11).random((64, 2)).astype(np.float32)
    points = [mi.Point2f(*r) for r in u] if variant.startswith("scalar") else [mi.Point2f(u[:, 0], u[:, 1])]
    for point in points:
        ds, weight = scene.sample_emitter_direction(it, point, True)
        assert np.all(np.asarray(weight) == 0)
        assert np.all(np.asarray(ds.dist) > 1e3)


_ELEMENT_BYTES = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 8, 8: 8, 9: 2, 10: 4, 11: 8}


def with_field(path, out_path, name, values):
    """Copies the tensor file (RGL .bsdf) `path` to `out_path` with field `name` replaced by `values`
    (1D, the field's dtype)."""
    with open(path, "rb") as f:
        data = f.read()
    count = int.from_bytes(data[14:18], "little")
    at, fields = 18, []
    for _ in range(count):
        n = int.from_bytes(data[at:at + 2], "little")
        key = data[at + 2:at + 2 + n].decode()
        at += 2 + n
        ndim, code = int.from_bytes(data[at:at + 2], "little"), data[at + 2]
        offset = int.from_bytes(data[at + 3:at + 11], "little")
        shape = [int.from_bytes(data[at + 11 + 8 * d:at + 19 + 8 * d], "little") for d in range(ndim)]
        at += 11 + 8 * ndim
        size = _ELEMENT_BYTES[code] * int(np.prod(shape, dtype=np.int64))
        fields.append([key, code, shape, data[offset:offset + size]])
    for field in fields:
        if field[0] == name:
            dtype = {10: "<f4", 11: "<f8"}[field[1]]
            field[2], field[3] = [len(values)], np.asarray(values, dtype=dtype).tobytes()
    align = lambda n: (n + 7) // 8 * 8  # noqa: E731
    header = 18 + sum(2 + len(key) + 2 + 1 + 8 + 8 * len(shape) for key, _, shape, _ in fields)
    out, offset = bytearray(data[:18]), align(header)
    for key, code, shape, payload in fields:
        out += len(key).to_bytes(2, "little") + key.encode() + len(shape).to_bytes(2, "little") + bytes([code])
        out += offset.to_bytes(8, "little") + b"".join(e.to_bytes(8, "little") for e in shape)
        offset = align(offset + len(payload))
    for _, _, _, payload in fields:
        out += bytes(align(len(out)) - len(out)) + payload
    with open(out_path, "wb") as f:
        f.write(bytes(out))


def test_anisotropic_rgl_file_is_refused_naming_it(variant, rgl_files, tmp_path):
    same = str(tmp_path / "same.bsdf")
    with_field(rgl_files[0], same, "phi_i", [0.0])  # the reader's own value: the copy must load
    mi.load_dict({"type": "acdf_measured", "filename": same})
    anisotropic = str(tmp_path / "anisotropic.bsdf")
    with_field(rgl_files[0], anisotropic, "phi_i", [0.0, np.pi, 2 * np.pi])
    with pytest.raises(Exception, match="anisotropic.bsdf.*anisotropic"):
        mi.load_dict({"type": "acdf_measured", "filename": anisotropic})


def test_measured_merl_renders_the_same_under_every_sampling(variant, tmp_path):
    """A MERL material through acdf_measured in mi.render: a sphere under a constant sky (direct
    light, MIS) has the same image mean whichever of acdf's samplers draws the BSDF's directions,
    and that mean is the albedo a uniform-sphere quadrature of eval gives (z-test, alpha 0.01
    Sidak-corrected over channels and cases)."""
    program = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))
    path = str(tmp_path / "nickel.binary")
    subprocess.run([program, "merl-gen", "--nbrdf", "nickel", "-o", path], check=True, capture_output=True)
    res, spp = (8, 16) if variant.startswith("scalar") else (48, 64)
    samplings = ["cosine", "adaptive", "uniform"]
    means, variances = [], []
    for seed, sampling in enumerate(samplings):
        scene = mi.load_dict({
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 2},
            "sensor": {"type": "orthographic",
                       "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0])
                       @ mi.ScalarTransform4f().scale([0.6, 0.6, 1]),
                       "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
                       "sampler": {"type": "independent", "sample_count": spp}},
            "ball": {"type": "sphere", "bsdf": {"type": "acdf_measured", "filename": path, "sampling": sampling}},
            "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
        })
        pixels = np.asarray(mi.render(scene, seed=seed), dtype=np.float64).reshape(-1, 3)
        means.append(pixels.mean(0))
        variances.append(pixels.var(0, ddof=1) / len(pixels))
    bound = norm.ppf(1 - acdf.sidak_alpha(0.01, 3 * (len(samplings) - 1) * len(VARIANTS)) / 2)
    for m, v in zip(means[1:], variances[1:]):
        z = (m - means[0]) / np.sqrt(v + variances[0])
        assert np.all(np.abs(z) < bound), f"z = {z}, bound {bound:.2f}, means {means}"
    assert np.all(means[0] > 0.05)


@pytest.fixture(scope="module")
def merl_file(tmp_path_factory):
    """A MERL file acdf merl-gen writes (the nickel fit of the shared NBRDF weights)."""
    program = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))
    path = str(tmp_path_factory.mktemp("merl") / "nickel.binary")
    subprocess.run([program, "merl-gen", "--nbrdf", "nickel", "-o", path], check=True, capture_output=True)
    return path


@pytest.fixture(scope="module")
def rgl_files(tmp_path_factory):
    """RGL files to compare with Mitsuba's measured: one acdf rgl-gen writes (a GGX preset in the
    paper's tables) and the shared measured ones when /work/shared is there."""
    program = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))
    path = str(tmp_path_factory.mktemp("rgl") / "rough-aluminium.bsdf")
    subprocess.run([program, "rgl-gen", "--preset", "rough-aluminium", "-o", path], check=True, capture_output=True)
    measured = sorted(glob.glob(os.path.join(SHARED_RGL, "*.bsdf")))
    return [path] + measured


def hemisphere(rng, n, max_theta=1.45):
    t, p = rng.uniform(0.0, max_theta, n), rng.uniform(0.0, 2 * np.pi, n)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], 1)


def bsdf_eval_pdf(bsdf, viewer, light):
    """Mitsuba's eval (f cos theta of the light direction) and pdf, with si.wi = viewer."""
    ctx = mi.BSDFContext()
    if mi.variant().startswith("scalar"):
        out = []
        for v, l in zip(viewer, light):
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(*v)
            f, p = bsdf.eval(ctx, si, mi.Vector3f(*l)), bsdf.pdf(ctx, si, mi.Vector3f(*l))
            out.append(np.append(np.asarray(f, dtype=np.float64), float(p)))
        out = np.array(out)
        return out[:, :3], out[:, 3]
    si = dr.zeros(mi.SurfaceInteraction3f, len(viewer))
    si.wi = mi.Vector3f(viewer[:, 0], viewer[:, 1], viewer[:, 2])
    wo = mi.Vector3f(light[:, 0], light[:, 1], light[:, 2])
    return rows_of(bsdf.eval(ctx, si, wo)), np.asarray(bsdf.pdf(ctx, si, wo), dtype=np.float64)


def test_measured_eval_and_pdf_equal_mitsubas(variant, rgl_files):
    if len(rgl_files) == 1:
        print("no shared RGL files under ACDF_SHARED_DATA/rgl: comparing the generated one only")
    rng = np.random.default_rng(11)
    viewer, light = hemisphere(rng, 64), hemisphere(rng, 64)
    for path in rgl_files:
        theirs = mi.load_dict({"type": "measured", "filename": path})
        ours = mi.load_dict({"type": "acdf_measured", "filename": path, "sampling": "rgl"})
        f0, p0 = bsdf_eval_pdf(theirs, viewer, light)
        f1, p1 = bsdf_eval_pdf(ours, viewer, light)
        # Mitsuba's measured can return negative channels where the file's RGB interpolates below
        # zero (the golden-yellow film near its highlight); acdf clamps them to 0.
        f0 = np.maximum(f0, 0.0)
        np.testing.assert_allclose(f1, f0, rtol=1e-4, atol=1e-7, err_msg=path)
        np.testing.assert_allclose(p1, p0, rtol=1e-4, atol=1e-7, err_msg=path)
        # The order matters: Mitsuba's eval carries the cosine of its wo, and the rgl pdf is not
        # symmetric, so swapping the two directions must not give the same values.
        f_swapped, p_swapped = bsdf_eval_pdf(ours, light, viewer)
        assert not np.allclose(f_swapped, f0, rtol=1e-3) and not np.allclose(p_swapped, p0, rtol=1e-3)


@pytest.mark.parametrize("sampling", ["adaptive", "uniform", "rgl", "cosine"])
def test_measured_samples_agree_with_pdf(variant, rgl_files, sampling):
    bsdf = mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "sampling": sampling})
    rng = np.random.default_rng(5)
    n = 16 if mi.variant().startswith("scalar") else 2048
    viewer, u = hemisphere(rng, n, 1.3), rng.random((n, 2)).astype(np.float32)
    ctx = mi.BSDFContext()
    if mi.variant().startswith("scalar"):
        rows = []
        for v, x in zip(viewer, u):
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(*v)
            bs, w = bsdf.sample(ctx, si, 0.5, mi.Point2f(*x))
            f = np.asarray(bsdf.eval(ctx, si, bs.wo), dtype=np.float64)
            rows.append([float(bs.pdf), float(bsdf.pdf(ctx, si, bs.wo)), *np.asarray(w), *f, *np.asarray(bs.wo)])
        rows = np.array(rows)
        pdf, again, weight, f, wo = rows[:, 0], rows[:, 1], rows[:, 2:5], rows[:, 5:8], rows[:, 8:11]
    else:
        si = dr.zeros(mi.SurfaceInteraction3f, n)
        si.wi = mi.Vector3f(viewer[:, 0], viewer[:, 1], viewer[:, 2])
        bs, w = bsdf.sample(ctx, si, mi.Float(np.full(n, 0.5)), mi.Point2f(u[:, 0], u[:, 1]))
        pdf, again = np.asarray(bs.pdf, dtype=np.float64), np.asarray(bsdf.pdf(ctx, si, bs.wo), dtype=np.float64)
        weight, f, wo = rows_of(w), rows_of(bsdf.eval(ctx, si, bs.wo)), rows_of(bs.wo)
    up = wo[:, 2] > 0
    assert up.mean() > 0.5
    np.testing.assert_allclose(again[up], pdf[up], rtol=1e-3)
    # The weight is eval / pdf, Mitsuba's eval already carrying the cosine.
    np.testing.assert_allclose(weight[up], f[up] / pdf[up, None], rtol=1e-3, atol=1e-6)


# (file, sampling, table options): the generated GGX file under each table the plugin lays out in drjit,
# the shared measured files and a generated MERL file under the default table, and the RGL files' own warps.
NATIVE_MEASURED_CASES = [
    ("nickel", "adaptive", {}),
    ("rough-aluminium", "adaptive", {}),
    ("rough-aluminium", "uniform", {}),
    ("rough-aluminium", "adaptive", {"layout": "4d", "theta_half": 64, "phi_half": 16}),
    ("rough-aluminium", "adaptive", {"mirror": False}),
    ("nickel", "adaptive", {"slice_grouping": 0.05}),
    ("rough-aluminium", "cosine", {}),
    ("paper_white_rgb", "adaptive", {}),
    ("vch_golden_yellow_rgb", "adaptive", {}),
    ("rough-aluminium", "rgl", {}),
    ("paper_white_rgb", "rgl", {}),
    ("vch_golden_yellow_rgb", "rgl", {}),
]
VIEWERS = [(0.3, 0.4), (1.0, 2.5), (1.45, 5.0)]  # (theta, phi) of the directions towards the viewer


def warp_cells(viewer, light, sampler, cells=32, sub=8):
    """The counts of the pairs' half vectors on cells x cells cells of the RGL warps' unit coordinates
    (v = (phi_h - phi_o + pi) / 2 pi, u = sqrt(theta_h / (pi / 2))), and each cell's probability under
    acdf's C++ pdf (the midpoint rule on sub x sub points per cell; the density of (v, u) is p(omega_i)
    4 |omega_o.omega_h| 2 pi^2 u sin theta_h)."""
    h = viewer + light
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    h = np.where(h[:, 2:] < 0, -h, h)  # the sampled half vector, not its opposite (omega_o.omega_h < 0)
    phi_o = np.arctan2(viewer[1], viewer[0])
    v = np.mod((np.arctan2(h[:, 1], h[:, 0]) - phi_o + np.pi) / (2 * np.pi), 1)
    u = np.sqrt(np.arctan2(np.hypot(h[:, 0], h[:, 1]), h[:, 2]) / (np.pi / 2))
    index = np.minimum((u * cells).astype(np.int64), cells - 1) * cells + np.minimum((v * cells).astype(np.int64),
                                                                                      cells - 1)
    observed = np.bincount(index, minlength=cells * cells).astype(np.float64)
    at = (np.arange(cells * sub) + 0.5) / (cells * sub)
    u, v = [g.ravel() for g in np.meshgrid(at, at, indexing="ij")]
    theta, phi = u * u * (np.pi / 2), (2 * v - 1) * np.pi + phi_o
    wh = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=1)
    cos_out = wh @ viewer
    wi = wh * (2 * cos_out[:, None]) - viewer
    jacobian = 4 * np.abs(cos_out) * 2 * np.pi**2 * u * np.sin(theta)
    density = sampler.pdf(np.broadcast_to(viewer, wi.shape), wi) * jacobian
    probabilities = density.reshape(cells, sub, cells, sub).sum((1, 3)).ravel() / (cells * sub) ** 2
    assert abs(probabilities.sum() - 1) < 1e-3, probabilities.sum()
    return observed, probabilities


def half_vector_cells(viewer, light, table, options):
    """The s and azimuth cells of each pair's half vector on acdf's table, as brdf/outgoing_cells.h
    defines them (in double, from the float32 directions Mitsuba holds)."""
    h = viewer + light
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    h = np.where(h[:, 2:] < 0, -h, h)
    s_cells, phi_cells = table.shape[-2:]
    lo, hi = table.domains[-1]
    s = np.sqrt(np.arctan2(np.hypot(h[:, 0], h[:, 1]), h[:, 2]) / (np.pi / 2))
    s_cell = np.minimum(s * s_cells, s_cells - 1).astype(np.int64)
    phi = np.mod(np.arctan2(h[:, 1], h[:, 0]), 2 * np.pi)
    if options["layout"] == "isotropic":
        phi = np.mod(phi - np.arctan2(viewer[:, 1], viewer[:, 0]), 2 * np.pi)
        if options["mirror"] == "true":
            phi = np.where(phi > np.pi, 2 * np.pi - phi, phi)
    on_axis = np.minimum(phi.astype(np.float32), np.nextafter(np.float32(hi), np.float32(0))).astype(np.float64)
    phi_cell = np.minimum((on_axis - lo) / ((hi - lo) / phi_cells), phi_cells - 1).astype(np.int64)
    return s_cell * phi_cells + phi_cell


@pytest.mark.parametrize("name,sampling,options", NATIVE_MEASURED_CASES,
                         ids=[f"{n}-{s}-{'-'.join(map(str, o.values())) or 'default'}"
                              for n, s, o in NATIVE_MEASURED_CASES])
def test_llvm_measured_samples_acdfs_table_in_drjit(rgl_files, merl_file, name, sampling, options):
    """In llvm_ad_rgb acdf_measured samples acdf's own half-vector table, or the RGL file's warps, with
    drjit operations. 10^6 samples at each of three viewer directions: in float64, the table's pdf of
    each sample is its returned pdf (to 1e-9; the warps' bit for bit) and positive and finite even at
    the extreme variates; through
    Mitsuba's float32 directions to 1e-5, all but a few in 10^5 (half vectors rounded across a cell
    edge); the direction, pdf and weight are those of acdf's C++ sampler for the same variates; and
    the half vectors' cells fit the table's exact cell probabilities (the cosine-weighted share of
    the samples, 1 - z^2 and phi, uniform; the warps' half vectors, 32 x 32 cells of their unit
    coordinates, the C++ pdf integrated over each), chi-square with cells pooled to an expected count >= 5,
    alpha 0.01 Sidak-corrected over cases, viewers and the two parts."""
    if "llvm_ad_rgb" not in mi.variants():
        pytest.skip("mitsuba has no llvm_ad_rgb variant")
    path = {"rough-aluminium": rgl_files[0], "nickel": merl_file}.get(name, os.path.join(SHARED_RGL, name + ".bsdf"))
    if not os.path.exists(path):
        pytest.skip(f"{path} is absent (the shared RGL files are not in the repository)")
    mi.set_variant("llvm_ad_rgb")
    acdf.mitsuba.register()
    from scipy.stats import chi2
    from test_chi_square import pooled_chi_square

    bsdf = mi.load_dict({"type": "acdf_measured", "filename": path, "sampling": sampling, **options})
    assert type(bsdf).__name__ == "NativeMeasured"
    table = bsdf.table
    # acdf's C++ sampler of the same parameters (its tables do not depend on the thread count).
    model = acdf.MerlBrdf.load(path) if path.endswith(".binary") else acdf.RglBrdf.load(path)
    if sampling in ("cosine", "rgl"):
        sampler = {"cosine": acdf.CosineBrdfSampler, "rgl": acdf.RglBrdfSampler}[sampling](model)
    else:
        sampler = acdf.TabulatedBrdfSampler(model, method=sampling, **{"layout": "isotropic", **options})
    if "slice_grouping" in options:  # slices that share a distribution (Cascade.distributions)
        assert sampler.table.distinct_slices < sampler.table.slices
    n = 1_000_000
    below_one = np.nextafter(np.float32(1), np.float32(0))
    extremes = np.array([[0, 0], [below_one, below_one], [0, below_one], [below_one, 0], [0.05, 0.5], [0.5, 0.5]],
                        dtype=np.float32)
    alpha = acdf.sidak_alpha(0.01, len(NATIVE_MEASURED_CASES) * len(VIEWERS) * 2)
    ctx = mi.BSDFContext()
    for seed, (theta, phi) in enumerate(VIEWERS):
        u = np.concatenate([extremes, np.random.default_rng(seed).random((n, 2)).astype(np.float32)])
        viewer = np.tile(np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)],
                                  dtype=np.float32), (len(u), 1))
        si = dr.zeros(mi.SurfaceInteraction3f, len(u))
        si.wi = mi.Vector3f(viewer[:, 0], viewer[:, 1], viewer[:, 2])
        bs, weight = bsdf.sample(ctx, si, mi.Float(0.5), mi.Point2f(u[:, 0], u[:, 1]))
        light, pdf, weight = rows_of(bs.wo), np.asarray(bs.pdf, dtype=np.float64), rows_of(weight)
        up = light[:, 2] > 0
        assert np.all(np.isfinite(pdf)) and np.all(pdf[up] > 0) and np.all(pdf[~up] == 0)
        assert np.all(np.isfinite(weight)) and np.all(weight >= 0)

        # acdf's C++ sampler, the same variates and the float32 viewer direction.
        viewer64 = viewer.astype(np.float64)
        c_light, c_weight, c_pdf = sampler.sample(viewer64, u)
        far = np.abs(light - c_light).max(1) > 1e-6
        assert np.count_nonzero(far) <= len(u) * 1e-5, f"{np.count_nonzero(far)} directions differ from acdf's"
        off = up & (np.abs(pdf - c_pdf) > 1e-5 * c_pdf)
        assert np.count_nonzero(off) <= len(u) * 1e-5, f"{np.count_nonzero(off)} pdfs differ from acdf's"
        # An RGL file's values are Mitsuba's measured in float32 against acdf's RglBrdf in double,
        # which part by up to 1.5e-3 at the grazing viewer (3e-5 elsewhere), and by up to 7e-2 inside
        # the golden-yellow film's specular spike at the grazing viewer, which the file's own warps
        # sample densely (there the pdfs agree to 1e-7); a MERL file's are acdf's cells, in drjit and
        # in C++ (test_llvm_merl_values_are_acdfs).
        np.testing.assert_allclose(weight.mean(0), c_weight.astype(np.float64).mean(0), rtol=3e-5)
        apart = np.abs(weight - c_weight).max(1) / np.maximum(c_weight.max(1), 1e-3)
        assert np.count_nonzero(apart > 1e-4) <= len(u) * 1e-3, np.sort(apart)[-10:]
        assert path.endswith(".binary") or apart.max() < (0.1 if sampling == "rgl" else 5e-3), np.sort(apart)[-10:]

        # pdf() of the float32 directions Mitsuba passes back: the sample's density to float32
        # rounding, but where the rounding moved the half vector across a cell edge. The warps'
        # density varies inside their cells: there the rounding shows as that slope times 1e-7 (at
        # the grazing viewer, in the golden-yellow film's specular spike, up to 2e-3; a few percent
        # at the extreme variates, whose half vectors lie by the normal, where the density per
        # steradian has its 1 / theta_m spike).
        again = np.asarray(bsdf.pdf(ctx, si, bs.wo), dtype=np.float64)
        crossed = up & (np.abs(again - pdf) > 1e-5 * pdf)
        share = 1e-4 if sampling == "rgl" else 3e-5
        assert np.count_nonzero(crossed) <= len(u) * share, f"{np.count_nonzero(crossed)} pdfs differ"
        if table is None:
            continue

        # The table in float64: the pdf of each sample is its density (to 1e-16 / |wo.wh|^2, which
        # recovering wh from wi costs; below |wo.wh| = 1e-3 the sample reports pdf() itself).
        v = dr.normalize(mi.Vector3d(viewer64[:, 0], viewer64[:, 1], viewer64[:, 2]))
        wi, density = table.sample(v, mi.Point2f(u[:, 0], u[:, 1]), mi.Bool(True))
        density = np.asarray(density)
        assert np.all(np.isfinite(density)) and np.all(density > 0)
        found = np.asarray(table.pdf(v, wi, mi.Bool(True)))
        if sampling == "rgl":
            # A sample reports pdf() of its omega_i, but where inverting the warp in float32 lands
            # in a cell of no luminance density (pdf() 0): the density along its path.
            assert np.count_nonzero(found == 0) <= len(u) * 1e-5, np.count_nonzero(found == 0)
            np.testing.assert_array_equal(found[found > 0], density[found > 0])
            observed, probabilities = warp_cells(viewer64[0], rows_of(wi), sampler)
            statistic, dof = pooled_chi_square(observed, probabilities * len(u))
            assert chi2.sf(statistic, dof) > alpha, f"warps: chi-square {statistic:.1f}, {dof} degrees of freedom"
            continue
        np.testing.assert_allclose(found, density, rtol=1e-9)

        # Chi-square of each part of the mixture.
        drawn = u[:, 0] >= table.cosine_weight
        options_of = sampler.table_options
        condition = [np.float32(theta)] + ([np.float32(phi)] if options_of["layout"] == "4d" else [])
        probabilities = sampler.table.cell_probabilities(sampler.table.slice_of(np.array(condition))).reshape(-1)
        cells = half_vector_cells(viewer64[drawn], light[drawn], sampler.table, options_of)
        observed = np.bincount(cells, minlength=probabilities.size).astype(np.float64)
        statistic, dof = pooled_chi_square(observed, probabilities * np.count_nonzero(drawn))
        assert chi2.sf(statistic, dof) > alpha, f"table part: chi-square {statistic:.1f}, {dof} degrees of freedom"
        cosine = light[~drawn]
        bins = (np.minimum(((1 - cosine[:, 2] ** 2) * 32).astype(np.int64), 31) * 32
                + np.minimum((np.mod(np.arctan2(cosine[:, 1], cosine[:, 0]), 2 * np.pi) / (2 * np.pi) * 32)
                             .astype(np.int64), 31))
        statistic, dof = pooled_chi_square(np.bincount(bins, minlength=1024).astype(np.float64),
                                           np.full(1024, len(cosine) / 1024))
        assert chi2.sf(statistic, dof) > alpha, f"cosine part: chi-square {statistic:.1f}, {dof} degrees of freedom"


def test_llvm_merl_values_are_acdfs(merl_file):
    """In llvm_ad_rgb acdf_measured looks a MERL file up in drjit: for 10^6 random pairs of
    directions (and pairs with one on the normal, where acdf fixes phi_d) its eval is acdf's f times
    the cosine of the light direction (to float32 rounding), all but the pairs whose angles round
    across a cell edge differently in drjit's atan2 (at most 1 in 10^5)."""
    if "llvm_ad_rgb" not in mi.variants():
        pytest.skip("mitsuba has no llvm_ad_rgb variant")
    mi.set_variant("llvm_ad_rgb")
    acdf.mitsuba.register()
    bsdf = mi.load_dict({"type": "acdf_measured", "filename": merl_file})
    assert type(bsdf).__name__ == "NativeMeasured"
    rng = np.random.default_rng(8)
    n = 1_000_000
    viewer, light = hemisphere(rng, n, np.pi / 2), hemisphere(rng, n, np.pi / 2)
    viewer[:1000] = light[1000:2000] = [0.0, 0.0, 1.0]
    viewer, light = viewer.astype(np.float32).astype(np.float64), light.astype(np.float32).astype(np.float64)
    ours, _ = bsdf_eval_pdf(bsdf, viewer, light)
    model = acdf.MerlBrdf.load(merl_file)
    up = (viewer[:, 2] > 0) & (light[:, 2] > 0)
    theirs = np.where(up[:, None], model.eval(viewer, light) * light[:, 2:], 0.0)
    differ = np.any(np.abs(ours - theirs) > 1e-6 * theirs, axis=1)  # float32 products apart
    assert np.count_nonzero(differ) <= n * 1e-5, f"{np.count_nonzero(differ)} values differ"
    assert np.all(ours[~differ] >= 0) and ours[up].mean() > 0


def test_measured_bad_parameters_and_files(variant, rgl_files, tmp_path):
    with pytest.raises(Exception, match="unknown sampling 'nonsense'"):
        mi.load_dict({"type": "acdf_measured", "filename": rgl_files[0], "sampling": "nonsense"})
    with pytest.raises(Exception, match="expected a MERL .binary or an RGL .bsdf"):
        mi.load_dict({"type": "acdf_measured", "filename": str(tmp_path / "x.png")})
    data = open(rgl_files[0], "rb").read()
    for name, content in [("missing.bsdf", None), ("empty.bsdf", b""), ("truncated.bsdf", data[: len(data) // 3]),
                          ("garbage.binary", b"\x01\x02\x03"), ("missing.binary", None)]:
        path = tmp_path / name
        if content is not None:
            path.write_bytes(content)
        with pytest.raises(Exception, match=name):
            mi.load_dict({"type": "acdf_measured", "filename": str(path)})

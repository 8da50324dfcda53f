"""Every batched call: a batch of n rows equals its n one-row calls, element for element, whatever
the arrays' dtype and layout (C order, Fortran order, a slice with a step, negative strides,
float32 and float64); what cannot be read as numbers of the expected shape is refused naming the
argument; and the arrays the module returns hold what they say. Under NumPy 2 with a pybind11
older than 2.12, batches came back with every row equal to row 0's: these tests fail then."""
import inspect
from dataclasses import dataclass, field

import numpy as np
import pytest
from scipy.stats import norm

import acdf

ROWS = 9
F32, F64 = np.float32, np.float64


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def upper_hemisphere(rng, n):
    v = unit(rng.normal(size=(n, 3)))
    v[:, 2] = np.abs(v[:, 2]) + 0.05
    return unit(v)


def sky(rng):
    """A 16 x 32 map: a smooth sky and a bright patch (the tables keep few points elsewhere)."""
    rgb = (0.2 + rng.random((16, 32, 3))).astype(F32)
    rgb[3:5, 20:23] = 200.0
    return acdf.EnvironmentMap(rgb)


@dataclass
class Arg:
    """An argument of a batched call: its values (rows) and the dtype the binding computes in."""
    values: np.ndarray
    native: type


@dataclass
class Case:
    name: str
    call: object  # a bound method
    args: dict
    kwargs: dict = field(default_factory=dict)
    row_kwargs: object = None  # row i -> extra keyword arguments of its one-row call


def cases(rng):
    n = ROWS
    u1 = Arg(rng.random(n, dtype=F32), F32)
    u2 = Arg(rng.random((n, 2), dtype=F32), F32)
    x1 = Arg(rng.uniform(-1, 3, n).astype(F32), F32)

    def dirs(k=n):
        return Arg(unit(rng.normal(size=(k, 3))), F64)

    def local_dirs(k=n):
        return Arg(upper_hemisphere(rng, k), F64)

    f = (rng.random(64) ** 4 + 0.01).astype(F32)
    out = []
    for table in (acdf.PiecewiseConstant1D(f, -1, 3), acdf.AdaptiveCdf1D(f, -1, 3, epsilon=1e-3),
                  acdf.AliasTable1D(f, -1, 3)):
        kind = type(table).__name__
        out += [Case(f"{kind}.sample", table.sample, {"u": u1}), Case(f"{kind}.pdf", table.pdf, {"x": x1})]
        if hasattr(table, "invert"):
            out.append(Case(f"{kind}.invert", table.invert, {"x": x1}))

    plain = acdf.Cascade(rng.random((24, 16), dtype=F32) ** 4, axes=[(-1, 1), (0, 2)], epsilon=1e-3)
    x2 = Arg(np.stack([rng.uniform(-1, 1, n), rng.uniform(0, 2, n)], 1).astype(F32), F32)
    conditioned = acdf.Cascade(rng.random((6, 16, 12), dtype=F32) ** 4, conditioning_dims=1, epsilon=1e-3)
    condition = Arg(rng.random((n, 1), dtype=F32), F32)
    x3 = Arg(rng.random((n, 2), dtype=F32), F32)
    one_axis = acdf.Cascade(rng.random((5, 32), dtype=F32), conditioning_dims=1)
    for kind, c, points, cond in [("Cascade", plain, x2, {}), ("Cascade|condition", conditioned, x3,
                                                                {"condition": condition})]:
        out += [Case(f"{kind}.sample", c.sample, {"u": u2, **cond}),
                Case(f"{kind}.pdf", c.pdf, {"x": points, **cond}),
                Case(f"{kind}.invert", c.invert, {"x": points, **cond})]
    out.append(Case("Cascade|one axis.sample", one_axis.sample, {"u": u1, "condition": condition}))

    light = acdf.EnvironmentLight(sky(rng), strategy="adaptive", rotation=30.0)
    local = acdf.EnvironmentLight(sky(rng), strategy="local", normal_rows=4, normal_columns=8, block_size=4)
    normals = dirs()
    towards = Arg(unit(normals.values + 0.8 * unit(rng.normal(size=(n, 3)))), F64)  # above each normal
    out += [Case("EnvironmentLight.sample", light.sample, {"u": u2}),
            Case("EnvironmentLight.pdf", light.pdf, {"dirs": dirs()}),
            Case("EnvironmentLight.eval", light.eval, {"dirs": dirs()}),
            Case("EnvironmentLight|normal.sample", local.sample, {"u": u2, "normal": normals},
                 {"allow_incomplete_pdf": True}),
            Case("EnvironmentLight|normal.pdf", local.pdf, {"dirs": towards, "normal": normals},
                 {"allow_incomplete_pdf": True})]
    # Points inside a room around the origin, lit through a window in the plane z = 1, and a few behind it.
    window = {"corner": [-0.5, 0.2, 1.0], "edge_u": [0.0, 0.6, 0.0], "edge_v": [1.0, 0.0, 0.0]}
    portal = acdf.EnvironmentLight(sky(rng), strategy="compensated", portals=[window])
    points = Arg(rng.uniform([-1.0, 0.0, -1.0], [1.0, 1.0, 1.3], (n, 3)), F64)
    out += [Case("EnvironmentLight|position.sample", portal.sample, {"u": u2, "position": points},
                 {"allow_incomplete_pdf": True}),
            Case("EnvironmentLight|position.pdf", portal.pdf, {"dirs": dirs(), "position": points},
                 {"allow_incomplete_pdf": True})]

    gold = acdf.AnalyticBrdf.preset("gold")
    tabulated = acdf.TabulatedBrdfSampler(gold, layout="isotropic", theta_out=4, theta_half=16, phi_half=8)
    out.append(Case("BrdfModel.eval", gold.eval, {"wo": local_dirs(), "wi": local_dirs()}))
    for sampler in (tabulated, acdf.GgxBrdfSampler(gold)):
        kind = type(sampler).__name__
        out += [Case(f"{kind}.sample", sampler.sample, {"wo": local_dirs(), "u": u2}),
                Case(f"{kind}.pdf", sampler.pdf, {"wo": local_dirs(), "wi": local_dirs()}),
                Case(f"{kind}.eval", sampler.eval, {"wo": local_dirs(), "wi": local_dirs()})]

    product = acdf.ProductSampler(light, tabulated, candidates=3)
    normal = dirs()
    wo = Arg(unit(normal.values + 0.5 * unit(rng.normal(size=(n, 3)))), F64)
    out += [Case("ProductSampler.sample", product.sample, {"wo": wo, "normal": normal}, {"seed": 5},
                 row_kwargs=lambda i: {"first_stream": i}),
            Case("ProductSampler.mixture_pdf", product.mixture_pdf, {"wo": wo, "normal": normal, "wi": dirs()})]
    return out


def with_layout(a, layout):
    """The same values as an array of another layout (a view where the layout is a view's)."""
    if layout == "C":
        return np.ascontiguousarray(a)
    if layout == "F":
        return np.asfortranarray(a)
    if layout == "step":
        base = np.zeros((2 * a.shape[0],) + a.shape[1:], a.dtype)
        base[::2] = a
        return base[::2]
    if layout == "reversed":
        return a[::-1].copy()[::-1]
    if layout == "column step" and a.ndim == 2:
        base = np.zeros((a.shape[0], 2 * a.shape[1]), a.dtype)
        base[:, ::2] = a
        return base[:, ::2]
    return np.ascontiguousarray(a)


LAYOUTS = [(layout, dtype) for layout in ["C", "F", "step", "reversed", "column step"] for dtype in [F32, F64]]


def results(value):
    return value if isinstance(value, tuple) else (value,)


@pytest.fixture(scope="module")
def all_cases():
    return cases(np.random.default_rng(41))


def case_names():
    return [c.name for c in cases(np.random.default_rng(41))]


@pytest.mark.parametrize("layout,dtype", LAYOUTS, ids=[f"{l}-{np.dtype(d).name}" for l, d in LAYOUTS])
def test_a_batch_equals_its_one_row_calls(all_cases, layout, dtype):
    for case in all_cases:
        given = {k: with_layout(a.values.astype(dtype), layout) for k, a in case.args.items()}
        batch = results(case.call(**given, **case.kwargs))
        # Each row alone, C-contiguous, in the dtype the binding computes in: the values given above.
        canonical = {k: np.ascontiguousarray(a.values.astype(dtype).astype(a.native)) for k, a in case.args.items()}
        rows = [results(case.call(**{k: v[i:i + 1] for k, v in canonical.items()}, **case.kwargs,
                                  **(case.row_kwargs(i) if case.row_kwargs else {})))
                for i in range(ROWS)]
        for j, whole in enumerate(batch):
            assert whole.shape[0] == ROWS, case.name
            np.testing.assert_array_equal(whole, np.concatenate([r[j] for r in rows]), err_msg=case.name)
            assert whole.dtype == rows[0][j].dtype and whole.flags.c_contiguous, case.name
        # Rows differ: a batch answering row 0's values for every row fails here too.
        assert any(np.unique(whole, axis=0).shape[0] > 1 for whole in batch), case.name


def public_methods():
    """Every public method and function of the module, as "Class.method" or "function"."""
    names = set()
    for name, value in vars(acdf).items():
        if name.startswith("_"):
            continue
        if inspect.isclass(value) and not issubclass(value, BaseException):
            for attr, member in vars(value).items():
                if not attr.startswith("_") and not isinstance(member, property) and callable(
                        getattr(value, attr)):
                    names.add(f"{name}.{attr}")
        elif callable(value) and not inspect.isclass(value):
            names.add(name)
    return names


# Methods that take or return arrays but not as batches of rows, each tested where named.
NOT_BATCHED = {
    "Cascade.slice_of": "one row; test_arrays_in_any_layout",
    "Cascade.integral": "no array",
    "Cascade.cell_probabilities": "an output; test_returned_arrays",
    "Cascade.breakpoints": "an output; test_returned_arrays",
    "Cascade.arrays": "an output; test_returned_arrays",
    "Cascade.serialize": "bytes; test_api",
    "Cascade.deserialize": "bytes; test_api",
    "EnvironmentLight.load": "a file",
    "EnvironmentLight.pixel_probabilities": "an output; test_returned_arrays",
    "EnvironmentLight.cascade_arrays": "an output; test_returned_arrays",
    "EnvironmentLight.local_arrays": "an output; test_returned_arrays",
    "EnvironmentLight.alias_arrays": "an output; test_returned_arrays",
    "EnvironmentLight.hierarchical_arrays": "an output; test_returned_arrays",
    "EnvironmentLight.portal_arrays": "an output; test_returned_arrays",
    "EnvironmentLight.portal_share": "no array; test_api",
    "EnvironmentMap.load": "a file",
    "EnvironmentMap.pixel_power": "an output; test_returned_arrays",
    "MerlBrdf.load": "a file",
    "RglBrdf.load": "a file",
    "AnalyticBrdf.preset": "no array",
    "AnalyticBrdf.preset_names": "no array",
    "AnalyticBrdf.conductor": "no array",
    "AnalyticBrdf.coated_diffuse": "no array",
    "compare_cell_probabilities": "whole arrays; test_arrays_in_any_layout",
    "chi_square_test": "whole arrays; test_arrays_in_any_layout",
    "sidak_alpha": "no array",
    "environment_samplings": "no array",
    "portal_problem": "no array; test_api",
    "find_openings": "a whole scene, not rows; test_api (in any layout)",
    "table_options": "no array",
}
# BrdfSampler's methods are one binding each, shared by its subclasses, which cases() call.
SHARED_BINDINGS = {"BrdfSampler.sample", "BrdfSampler.pdf", "BrdfSampler.eval"}


def test_every_batched_method_is_tested_above():
    tested = {name.split("|")[0].split(".")[0] + "." + name.split(".")[-1] for name in case_names()}
    tested |= SHARED_BINDINGS
    untested = public_methods() - tested - set(NOT_BATCHED)
    assert not untested, f"batched methods without a case in cases(): {sorted(untested)}"
    assert not (set(NOT_BATCHED) - public_methods()), "NOT_BATCHED names a method that is gone"


def test_arrays_in_any_layout(rng):
    """Arguments read whole (tables' values, maps, cell probabilities) in every layout give what
    C-contiguous float32 gives."""
    values = (rng.random((24, 16)) ** 3).astype(F32)
    rgb = (rng.random((8, 16, 3)) + 0.1).astype(F32)
    p, q = rng.random(50), rng.random(50)
    p, q = p / p.sum(), q / q.sum()
    u = rng.random((100, 2), dtype=F32)
    reference = {
        "cascade": acdf.Cascade(values).sample(u)[1],
        "1d": acdf.AdaptiveCdf1D(values[3]).sample(u[:, 0])[1],
        "map": acdf.EnvironmentMap(rgb).rgb,
        "compare": acdf.compare_cell_probabilities(p, q).chi2_divergence,
        "chi2": acdf.chi_square_test(p * 1000, q * 1000).statistic,
    }
    conditioned = acdf.Cascade(rng.random((6, 4, 5), dtype=F32), axes=[(0, 3), (0, 1), (0, 1)], conditioning_dims=1)
    for layout, dtype in LAYOUTS:
        def given(a):
            return with_layout(a.astype(dtype), layout)

        assert np.array_equal(acdf.Cascade(given(values)).sample(u)[1], reference["cascade"]), layout
        assert np.array_equal(acdf.AdaptiveCdf1D(given(values[3])).sample(u[:, 0])[1], reference["1d"]), layout
        assert np.array_equal(acdf.EnvironmentMap(given(rgb)).rgb, reference["map"]), layout
        assert acdf.compare_cell_probabilities(given(p), given(q)).chi2_divergence == pytest.approx(
            reference["compare"], rel=1e-5 if dtype == F32 else 1e-15)
        assert acdf.chi_square_test(given(p * 1000), given(q * 1000)).statistic == pytest.approx(
            reference["chi2"], rel=1e-5 if dtype == F32 else 1e-15)
        assert conditioned.slice_of(given(np.array([2.6]))[::-1]) == 5, layout


def probabilities_of_cascade(levels, height, width, distribution=0):
    """Each cell's probability from EnvironmentLight.cascade_arrays or Cascade.arrays (first-level CDF
    `distribution`): the product of its row's and column's interval masses, spread evenly over the
    interval's cells."""
    rows, columns = levels
    assert len(columns["start"]) == len(rows["vertex"]) - len(rows["start"]) + 2
    p = np.zeros((height, width))
    for j in range(rows["start"][distribution], rows["start"][distribution + 1] - 1):
        a, b = rows["vertex"][j : j + 2]
        row_mass = float(rows["value"][j + 1]) - float(rows["value"][j])
        # Below interval j of the first level lies CDF j of the next, intervals counted across CDFs.
        first, end = columns["start"][j - distribution : j - distribution + 2]
        vertex, value = columns["vertex"][first:end], columns["value"][first:end].astype(F64)
        assert vertex[0] == 0 and vertex[-1] == width and value[0] == 0 and value[-1] == 1
        for k in range(len(vertex) - 1):
            c, d = vertex[k : k + 2]
            p[a:b, c:d] = row_mass * (value[k + 1] - value[k]) / ((b - a) * (d - c))
    return p


def portal_arrays_give_the_lights_density(world):
    """A portal's arrays (portal_arrays) are its table: the summed-area table and the rows' running
    integrals integrate the coarse density, and from a point in the room the light's pdf of its
    samples is the mixture of the table's density per steradian through the window (the window's
    mass integrated cell by cell here) and the strategy's pdf."""
    window = {"corner": [-0.5, 0.2, 1.0], "edge_u": [0.0, 0.6, 0.0], "edge_v": [1.0, 0.0, 0.0]}
    light = acdf.EnvironmentLight(world, portals=[window])
    (p,) = light.portal_arrays()
    A, B = p["column_vertices"], p["row_vertices"]
    columns, rows = len(A) - 1, len(B) - 1
    density = p["density"].reshape(rows, columns)
    running = np.concatenate([np.zeros((rows, 1)), np.cumsum(density * np.diff(A), axis=1)], axis=1)
    np.testing.assert_allclose(p["row_integral"].reshape(rows, columns + 1), running, rtol=1e-12, atol=1e-300)
    area = np.concatenate([np.zeros((1, columns + 1)), np.cumsum(running * np.diff(B)[:, None], axis=0)])
    np.testing.assert_allclose(p["summed_area"].reshape(rows + 1, columns + 1), area, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(p["min_power"], 1e-12 * p["summed_area"][-1], rtol=1e-12)  # kMinShare of the whole
    fine_columns = np.searchsorted(A, (np.arange(len(p["coarse_column_of_fine"])) + 0.5)
                                   / len(p["coarse_column_of_fine"])) - 1
    np.testing.assert_array_equal(p["coarse_column_of_fine"], fine_columns)
    np.testing.assert_allclose(p["normal"], np.cross(p["axis_u"], p["axis_v"]), atol=1e-15)
    np.testing.assert_allclose(np.multiply(p["axis_u"], p["length_u"]), window["edge_u"], atol=1e-15)

    inside = np.array([0.1, 0.5, 0.0])
    u = np.random.default_rng(2).random((2000, 2), dtype=np.float32)
    u[:, 0] *= acdf.EnvironmentLight.portal_share()  # every sample through the window
    d, _, pdf = light.sample(u, position=inside)
    to_corner = np.asarray(p["corner"]) - inside
    h = -to_corner @ p["normal"]

    def coordinate(x, height):
        return 0.5 * (1 + x / np.sqrt(x * x + height * height))

    u0, v0 = to_corner @ p["axis_u"], to_corner @ p["axis_v"]
    a0, a1, b0, b1 = coordinate(u0, h), coordinate(u0 + p["length_u"], h), coordinate(v0, h), coordinate(
        v0 + p["length_v"], h)
    overlap_a = np.clip(np.minimum(A[1:], a1) - np.maximum(A[:-1], a0), 0, None)
    overlap_b = np.clip(np.minimum(B[1:], b1) - np.maximum(B[:-1], b0), 0, None)
    power = overlap_b @ density @ overlap_a
    du, dv, dn = d @ p["axis_u"], d @ p["axis_v"], -(d @ p["normal"])
    qu, qv = np.sqrt(du * du + dn * dn), np.sqrt(dv * dv + dn * dn)
    a, b = 0.5 * (1 + du / qu), 0.5 * (1 + dv / qv)
    fine = len(p["coarse_column_of_fine"])
    cell = density[p["coarse_row_of_fine"][np.minimum((b * fine).astype(int), fine - 1)],
                   p["coarse_column_of_fine"][np.minimum((a * fine).astype(int), fine - 1)]]
    through = cell / (4 * qu**3 * qv**3 / dn**3) / power
    share = acdf.EnvironmentLight.portal_share()
    np.testing.assert_allclose(pdf, share * through + (1 - share) * light.pdf(d), rtol=1e-9)


def test_returned_arrays(rng):
    """Outputs hold what they say: a map's pixels, its power per pixel, exact cell probabilities
    and the kept breakpoints."""
    rgb = (rng.random((8, 16, 3)) + 0.1).astype(F32)
    rgb[2, 5] = 50
    world = acdf.EnvironmentMap(rgb)
    np.testing.assert_array_equal(world.rgb, rgb)
    edges = np.cos(np.arange(9) * np.pi / 8)
    solid_angle = (edges[:-1] - edges[1:]) * 2 * np.pi / 16
    power = (rgb.astype(F64) @ [0.2126, 0.7152, 0.0722]) * solid_angle[:, None]
    np.testing.assert_allclose(world.pixel_power(), power, rtol=1e-5)
    uniform = acdf.EnvironmentLight(world, strategy="uniform").pixel_probabilities()
    np.testing.assert_allclose(uniform, power / power.sum(), rtol=1e-5)
    values = (rng.random((12, 10)) + 0.01).astype(F32)
    cascade = acdf.Cascade(values, methods=["uniform", "uniform"])
    np.testing.assert_allclose(cascade.cell_probabilities(), values / values.sum(dtype=F64), rtol=1e-5)
    rows = cascade.breakpoints(0)[0]
    np.testing.assert_array_equal(rows, np.arange(13))
    for strategy in ("uniform", "adaptive", "compensated"):
        light = acdf.EnvironmentLight(world, strategy=strategy)
        incomplete = strategy == "compensated"
        np.testing.assert_allclose(probabilities_of_cascade(light.cascade_arrays(incomplete), 8, 16),
                                   light.pixel_probabilities(incomplete), rtol=1e-5, atol=1e-7)
    assert acdf.EnvironmentLight(world, strategy="alias").cascade_arrays() is None
    # An alias light's tables: each gives every cell what its slots hand it (acceptance to the slot's own
    # cell, the rest to its alias), the cell's stored probability; a pixel's is its row's times its column's.
    alias = acdf.EnvironmentLight(world, strategy="alias")
    arrays = alias.alias_arrays()
    for table, tables, slots in ((arrays["rows"], 1, 8), (arrays["columns"], 8, 16)):
        acceptance = table["acceptance"].astype(F64).reshape(tables, slots)
        law = np.zeros((tables, slots))
        for t in range(tables):
            np.add.at(law[t], np.arange(slots), acceptance[t] / slots)
            np.add.at(law[t], table["alias"].reshape(tables, slots)[t], (1 - acceptance[t]) / slots)
        np.testing.assert_allclose(law, table["probability"].reshape(tables, slots), rtol=1e-5, atol=1e-7)
    pixels = arrays["rows"]["probability"].astype(F64)[:, None] * arrays["columns"]["probability"].reshape(8, 16)
    np.testing.assert_array_equal(pixels, alias.pixel_probabilities())
    # A hierarchical light's pyramid: its pixels' masses are their probabilities, and each node's mass
    # on a level is the float sum of its four children's below.
    hierarchical = acdf.EnvironmentLight(world, strategy="hierarchical")
    levels = hierarchical.hierarchical_arrays()
    assert [level["parent_columns"] for level in levels] == [8, 4, 2, 1]
    portal_arrays_give_the_lights_density(world)

    def nodes(level):
        """A level's blocks as its (padded) grid of masses, and the sums of each block, per node above."""
        blocks = level["blocks"].reshape(-1, level["parent_columns"], 2, 2)
        grid = blocks.transpose(0, 2, 1, 3).reshape(2 * blocks.shape[0], -1)
        return grid, blocks.astype(F64).sum((2, 3)).astype(F32)

    np.testing.assert_array_equal(nodes(levels[0])[0], hierarchical.pixel_probabilities())
    for below, level in zip(levels, levels[1:]):
        sums = nodes(below)[1]
        np.testing.assert_array_equal(nodes(level)[0][:sums.shape[0], :sums.shape[1]], sums)
    assert alias.hierarchical_arrays() is None and hierarchical.alias_arrays() is None
    # A local light's tables: its normal cell's block probabilities times each block's pixel ones
    # are the probabilities of its pdf at that normal.
    normal = np.array([0.3, 0.8, 0.5])
    for strategy in ("local", "local-compensated"):
        local = acdf.EnvironmentLight(world, strategy=strategy, normal_rows=2, normal_columns=4, block_size=4)
        arrays = local.local_arrays()
        assert (arrays["normal_rows"], arrays["normal_columns"], arrays["block_height"], arrays["block_width"]) == (
            2, 4, 4, 4)
        theta, phi = np.arctan2(np.hypot(normal[0], normal[2]), normal[1]), np.arctan2(normal[0], -normal[2])
        cell = int(theta / np.pi * 2) * 4 + int(np.mod(phi, 2 * np.pi) / (2 * np.pi) * 4)
        blocks = probabilities_of_cascade(arrays["blocks"], 2, 4, cell)
        p = np.zeros((8, 16))
        for b, distribution in enumerate(arrays["pixel_distributions"]):
            r, c = divmod(b, 4)
            p[4 * r:4 * r + 4, 4 * c:4 * c + 4] = blocks[r, c] * probabilities_of_cascade(arrays["pixels"], 4, 4,
                                                                                          distribution)
        theta = np.repeat((np.arange(8) + 0.5) * np.pi / 8, 16)
        phi = np.tile((np.arange(16) + 0.5) * np.pi / 8, 8)
        centres = np.stack([np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)], 1)
        pdf = local.pdf(centres, normal=normal, allow_incomplete_pdf=strategy == "local-compensated")
        np.testing.assert_allclose(p, pdf.reshape(8, 16) * solid_angle[:, None], rtol=1e-5, atol=1e-7)
    assert acdf.EnvironmentLight(world, strategy="adaptive").local_arrays() is None
    # A conditioned cascade whose slices 1-3 share one distribution (scaled copies of one slice).
    shape = values[None] * np.array([1.0, 2.0, 3.0, 4.0], dtype=F32)[:, None, None]
    shape[0] = values[::-1]
    grouped = acdf.Cascade(shape, conditioning_dims=1, slice_grouping_tolerance=0.01)
    assert grouped.distinct_slices == 2
    np.testing.assert_array_equal(grouped.distributions, [0, 1, 1, 1])
    for s in range(4):
        np.testing.assert_allclose(probabilities_of_cascade(grouped.arrays(), 12, 10, grouped.distributions[s]),
                                   grouped.cell_probabilities(s), rtol=1e-5, atol=1e-7)
    vertices, cdf = acdf.AdaptiveCdf1D(values[0]).breakpoints
    assert vertices[0] == 0 and vertices[-1] == 10 and np.all(np.diff(vertices) > 0) and np.all(np.diff(cdf) > 0)


NOT_NUMBERS = [np.array([[0.1, 0.2]], dtype=np.complex128), np.array([[True, False]]), np.array([["a", "b"]]),
               np.array([[object(), None]]), [[0.1], [0.2, 0.3]], "0.5"]


@pytest.mark.parametrize("bad", NOT_NUMBERS, ids=["complex", "bool", "text", "object", "ragged", "str"])
def test_what_is_not_numbers_is_refused_naming_the_argument(bad):
    light = acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((4, 8, 3), F32)))
    with pytest.raises(ValueError, match=r"^u: expected real numbers of shape \(n, 2\), got"):
        light.sample(bad)
    with pytest.raises(ValueError, match=r"^dirs: expected real numbers of shape \(n, 3\), got"):
        light.pdf(bad)
    sampler = acdf.GgxBrdfSampler(acdf.AnalyticBrdf.preset("gold"))
    with pytest.raises(ValueError, match=r"^wo: expected real numbers"):
        sampler.sample(bad, np.zeros((1, 2)))
    with pytest.raises(ValueError, match=r"^values: expected real numbers"):
        acdf.Cascade(bad)
    with pytest.raises(ValueError, match=r"^x: expected real numbers of shape \(n,\)"):
        acdf.PiecewiseConstant1D(np.ones(4)).pdf(bad)


def test_wrong_shapes_are_refused_naming_the_argument_and_the_shape():
    light = acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((4, 8, 3), F32)))
    with pytest.raises(ValueError, match=r"^u: expected shape \(n, 2\), got \(4, 2, 1\)"):
        light.sample(np.zeros((4, 2, 1)))
    with pytest.raises(ValueError, match=r"^u: expected shape \(n, 2\), got \(2,\)"):
        light.sample(np.zeros(2))
    with pytest.raises(ValueError, match=r"^dirs: expected shape \(n, 3\), got \(3, 2\)"):
        light.eval(np.ones((3, 2)))
    sampler = acdf.GgxBrdfSampler(acdf.AnalyticBrdf.preset("gold"))
    with pytest.raises(ValueError, match=r"^u: expected shape \(4, 2\), one row per sample, got \(1, 2\)"):
        sampler.sample(np.tile([0.0, 0.0, 1.0], (4, 1)), np.zeros((1, 2)))
    with pytest.raises(ValueError, match=r"^condition: expected shape \(1,\), got \(2,\)"):
        acdf.Cascade(np.ones((3, 4), F32), conditioning_dims=1).slice_of(np.zeros(2))
    with pytest.raises(ValueError, match=r"^condition: the cascade has no conditioning axes"):
        acdf.Cascade(np.ones((3, 4), F32)).sample(np.zeros((2, 2)), np.zeros((2, 1)))


def map_power(rgb):
    """The integral of a lat-long map over the sphere, per channel: each pixel times its solid angle."""
    rows, columns = rgb.shape[:2]
    edges = np.cos(np.arange(rows + 1) * np.pi / rows)
    solid_angle = (edges[:-1] - edges[1:]) * 2 * np.pi / columns
    return np.einsum("r,rcx->x", solid_angle, rgb.astype(F64))


STRATEGIES = ["uniform-sphere", "uniform", "alias", "adaptive", "compensated", "hierarchical", "local"]


def assert_power(light, rgb, n, seed, tests):
    """The mean of L / pdf over n samples is the map's power (z-test at alpha 0.01, Sidak over
    `tests` tests): every row's pdf must belong to its own direction and radiance."""
    u = np.random.default_rng(seed).random((n, 2))
    _, radiance, pdf = light.sample(u)
    assert np.all(pdf > 0) and np.all(np.isfinite(pdf)), light.strategy
    estimate = radiance.astype(F64) / pdf[:, None]
    mean, stderr = estimate.mean(0), estimate.std(0, ddof=1) / np.sqrt(n)
    bound = norm.ppf(1 - acdf.sidak_alpha(0.01, tests) / 2)
    z = (mean - map_power(rgb)) / stderr
    assert np.all(np.abs(z) < bound), f"{light.strategy}: z = {z}, means {mean}, power {map_power(rgb)}"


def test_mean_of_radiance_over_pdf_is_the_maps_power(rng):
    rgb = (0.2 + rng.random((32, 64, 3))).astype(F32)
    rgb[6:9, 40:44] = [400.0, 300.0, 150.0]
    world = acdf.EnvironmentMap(rgb)
    for seed, strategy in enumerate(STRATEGIES):
        assert_power(acdf.EnvironmentLight(world, strategy=strategy), rgb, 200_000, seed, 3 * len(STRATEGIES))


def test_a_real_map_answers_each_row(shared_map):
    """The report's case: the sunset map, three rows, each pdf its own direction's."""
    light = acdf.EnvironmentLight.load(shared_map, strategy="uniform")
    dirs, _, pdf = light.sample(np.array([[0.1, 0.9], [0.5, 0.5], [0.99, 0.01]]))
    np.testing.assert_array_equal(pdf, light.pdf(dirs))
    assert len(set(pdf.tolist())) == 3
    default = acdf.EnvironmentLight.load(shared_map)
    assert_power(default, default.map.rgb, 200_000, 7, 3)

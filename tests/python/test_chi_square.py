"""Independent chi-square tests, written with numpy and scipy: the module's samplers against
their own pdf(), integrated over cells of the sphere here, not by acdf.

Each test draws 1e6 samples, bins them, pools the cells to an expected count >= 5 and rejects at
alpha = 0.01 with the Sidak correction over the tests of this file.
"""
import numpy as np
import pytest
from scipy import stats

import acdf

SAMPLES = 1_000_000
TESTS_IN_FILE = 4
ALPHA = 1.0 - (1.0 - 0.01) ** (1.0 / TESTS_IN_FILE)


def pooled_chi_square(observed, expected, min_expected=5.0):
    """Pearson's statistic after pooling the smallest cells (in order of expected count)."""
    order = np.argsort(expected)
    observed, expected = observed[order], expected[order]
    pools_o, pools_e, o, e = [], [], 0.0, 0.0
    for ob, ex in zip(observed, expected):
        o += ob
        e += ex
        if e >= min_expected:
            pools_o.append(o)
            pools_e.append(e)
            o = e = 0.0
    if e > 0 or o > 0:  # the remainder joins the last pool
        pools_o[-1] += o
        pools_e[-1] += e
    pools_o, pools_e = np.array(pools_o), np.array(pools_e)
    statistic = float(np.sum((pools_o - pools_e) ** 2 / pools_e))
    return statistic, len(pools_e) - 1


def assert_fits(observed, probabilities, what):
    assert abs(probabilities.sum() - 1.0) < 1e-3, f"{what}: the pdf integrates to {probabilities.sum()}"
    statistic, dof = pooled_chi_square(observed.astype(float), probabilities * observed.sum())
    pvalue = stats.chi2.sf(statistic, dof)
    assert pvalue > ALPHA, f"{what}: chi2 = {statistic:.1f}, dof = {dof}, p = {pvalue:.3g}"


def sky(width, height):
    """A generated sky with a small bright sun, (height, width, 3)."""
    theta = (np.arange(height) + 0.5) / height * np.pi
    phi = (np.arange(width) + 0.5) / width * 2 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    d = np.stack([np.sin(t) * np.sin(p), np.cos(t), np.sin(t) * np.cos(p)], axis=-1)
    sun = np.array([0.6, 0.3, 0.74])
    sun /= np.linalg.norm(sun)
    lum = 0.2 + np.maximum(d[..., 1], 0) + 3000.0 * (d @ sun > np.cos(0.05))
    return np.repeat(lum[..., None], 3, axis=2).astype(np.float32) * np.array([1.0, 0.9, 0.7], np.float32)


@pytest.mark.parametrize("strategy", ["adaptive", "hierarchical", "local"])
def test_environment_light(strategy, rng):
    """Global strategies without a normal; local at a tilted normal (the surface's, world frame)."""
    width, height = 96, 48
    light = acdf.EnvironmentLight(acdf.EnvironmentMap(sky(width, height)), strategy=strategy, epsilon=1e-3,
                                  block_size=4)
    normal = np.array([0.3, 0.8, 0.5]) if strategy == "local" else None
    u = rng.random((SAMPLES, 2), dtype=np.float32)
    dirs, radiance, pdf = light.sample(u, normal=normal)
    assert np.all(np.isfinite(pdf)) and np.all(pdf > 0)
    np.testing.assert_allclose(np.linalg.norm(dirs, axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(light.pdf(dirs, normal=normal), pdf, rtol=1e-6)
    if normal is not None:  # the cosine bound: no sample far below the normal's horizon
        assert np.mean(dirs @ (normal / np.linalg.norm(normal)) < -0.3) < 1e-3
    # Cells: the map's own pixels (the pdf is constant on each, so pdf x solid angle is exact).
    # Direction to pixel, independently of acdf: OpenEXR's LatLong layout,
    # w(theta, phi) = (sin theta sin phi, cos theta, -sin theta cos phi).
    theta = np.arccos(np.clip(dirs[:, 1], -1, 1))
    phi = np.mod(np.arctan2(dirs[:, 0], -dirs[:, 2]), 2 * np.pi)
    row = np.minimum((theta / np.pi * height).astype(int), height - 1)
    col = np.minimum((phi / (2 * np.pi) * width).astype(int), width - 1)
    observed = np.bincount(row * width + col, minlength=width * height)
    theta_c = (np.arange(height) + 0.5) / height * np.pi
    phi_c = (np.arange(width) + 0.5) / width * 2 * np.pi
    t, p = np.meshgrid(theta_c, phi_c, indexing="ij")
    centres = np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], axis=-1).reshape(-1, 3)
    edges = np.arange(height + 1) / height * np.pi
    solid_angle = np.repeat((np.cos(edges[:-1]) - np.cos(edges[1:])) * 2 * np.pi / width, width)
    assert_fits(observed, light.pdf(centres, normal=normal) * solid_angle, strategy)


def test_tabulated_brdf_sampler(rng):
    """The adaptive half-vector table of the gold preset at theta_o = 40 degrees."""
    sampler = acdf.TabulatedBrdfSampler(acdf.AnalyticBrdf.preset("gold"), layout="isotropic")
    wo = np.array([np.sin(0.7), 0.0, np.cos(0.7)])
    wi, weight, pdf = sampler.sample(wo, rng.random((SAMPLES, 2), dtype=np.float32))
    assert np.all(np.isfinite(pdf)) and np.all(pdf > 0)
    consistent = np.isclose(sampler.pdf(wo, wi), pdf, rtol=1e-4)
    assert np.mean(~consistent) < 1e-4, "pdf(sample) differs from the returned pdf (beyond cell edges)"
    # Cells on the sphere, equal in (cos theta, phi); expected probabilities by midpoint quadrature
    # on 16 x 16 points per cell (the density is piecewise constant in the half vector, so a
    # finer rule only moves the few cells that straddle its edges).
    rows, cols, q = 20, 40, 16
    z = np.clip(wi[:, 2], -1, 1)
    phi = np.mod(np.arctan2(wi[:, 1], wi[:, 0]), 2 * np.pi)
    r = np.minimum(((1 - z) / 2 * rows).astype(int), rows - 1)
    c = np.minimum((phi / (2 * np.pi) * cols).astype(int), cols - 1)
    observed = np.bincount(r * cols + c, minlength=rows * cols)
    zs = 1 - 2 * (np.arange(rows * q) + 0.5) / (rows * q)
    ps = (np.arange(cols * q) + 0.5) / (cols * q) * 2 * np.pi
    zz, pp = np.meshgrid(zs, ps, indexing="ij")
    s = np.sqrt(1 - zz**2)
    points = np.stack([s * np.cos(pp), s * np.sin(pp), zz], axis=-1).reshape(-1, 3)
    density = sampler.pdf(wo, points).reshape(rows, q, cols, q)
    probabilities = density.sum(axis=(1, 3)) * (4 * np.pi / (rows * q * cols * q))
    assert_fits(observed, probabilities.reshape(-1), "adaptive-iso gold")

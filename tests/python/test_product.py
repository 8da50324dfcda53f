"""ProductSampler: direct light by resampled sampling of f L cos at batches of shading points."""
import numpy as np
import pytest

import acdf

ALBEDO = 0.5


def lambertian():
    return acdf.CosineBrdfSampler(acdf.LambertianBrdf([ALBEDO] * 3))


def constant_light(strategy="adaptive", radiance=1.0):
    return acdf.EnvironmentLight(acdf.EnvironmentMap(np.full((16, 32, 3), radiance, np.float32)), strategy=strategy)


def shading_points(n, rng):
    normal = rng.normal(size=(n, 3))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    wo = rng.normal(size=(n, 3))
    wo /= np.linalg.norm(wo, axis=1, keepdims=True)
    wo *= np.sign(np.sum(wo * normal, axis=1))[:, None]  # above the surface
    return wo, normal


@pytest.mark.parametrize("strategy", ["adaptive", "compensated", "local"])
@pytest.mark.parametrize("candidates,bsdf_fraction", [(1, 0.5), (8, 0.5), (4, 0.0), (4, 1.0)])
def test_the_estimate_is_unbiased_in_a_furnace(rng, strategy, candidates, bsdf_fraction):
    # Under a constant radiance 1 a Lambertian surface reflects its albedo: E[estimate] = 0.5.
    if strategy == "compensated" and bsdf_fraction == 0.0:
        pytest.skip("a compensated light is incomplete: b = 0 needs the complete table")
    sampler = acdf.ProductSampler(constant_light(strategy), lambertian(), candidates, bsdf_fraction)
    wo, normal = shading_points(20000, rng)
    wi, estimate, pdf = sampler.sample(wo, normal, seed=7)
    assert np.all(np.isfinite(estimate)) and np.all(estimate >= 0)
    mean, stderr = estimate.mean(axis=0), estimate.std(axis=0) / np.sqrt(len(estimate))
    assert np.all(np.abs(mean - ALBEDO) <= 4.5 * stderr + 1e-6), (mean, stderr)
    kept = pdf > 0
    assert np.all(np.sum(wi[kept] * normal[kept], axis=1) > 0)


def test_one_candidate_is_mixture_sampling(rng):
    # With M = 1 the estimate is f L cos / q at the kept direction, and q is the mixture's pdf.
    light = constant_light(radiance=2.0)
    sampler = acdf.ProductSampler(light, lambertian(), candidates=1, bsdf_fraction=0.3)
    wo, normal = shading_points(2000, rng)
    wi, estimate, pdf = sampler.sample(wo, normal, seed=3)
    kept = pdf > 0
    assert kept.mean() > 0.6  # light candidates below the horizon weigh 0
    np.testing.assert_allclose(sampler.mixture_pdf(wo[kept], normal[kept], wi[kept]), pdf[kept], rtol=1e-12)
    cos = np.sum(wi[kept] * normal[kept], axis=1)
    expected = ALBEDO / np.pi * 2.0 * cos / pdf[kept]
    np.testing.assert_allclose(estimate[kept], np.repeat(expected[:, None], 3, axis=1), rtol=1e-5)


def test_rows_are_deterministic_whatever_the_batch(rng):
    sampler = acdf.ProductSampler(constant_light(), lambertian())
    wo, normal = shading_points(10000, rng)  # above 8192 rows: the batch runs on several threads
    whole = sampler.sample(wo, normal, seed=11)
    part = sampler.sample(wo[:10], normal[:10], seed=11)
    for a, b in zip(whole, part):
        np.testing.assert_array_equal(a[:10], b)
    assert not np.array_equal(sampler.sample(wo[:10], normal[:10], seed=12)[0], part[0])


def test_a_black_map_gives_nothing(rng):
    sampler = acdf.ProductSampler(constant_light(radiance=0.0), lambertian())
    wo, normal = shading_points(100, rng)
    wi, estimate, pdf = sampler.sample(wo, normal)
    assert np.all(estimate == 0) and np.all(pdf == 0) and np.all(wi == 0)


def test_bad_arguments_raise_value_errors():
    light = constant_light()
    with pytest.raises(ValueError, match="candidates"):
        acdf.ProductSampler(light, lambertian(), candidates=0)
    with pytest.raises(ValueError, match="bsdf_fraction"):
        acdf.ProductSampler(light, lambertian(), bsdf_fraction=1.5)
    sampler = acdf.ProductSampler(light, lambertian())
    with pytest.raises(ValueError, match="normal"):
        sampler.sample(np.ones((3, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="wo and normal"):
        sampler.sample(np.ones((3, 3)), np.ones((4, 3)))

"""The module returns what the C++ libraries return, bit for bit, on fixed inputs."""
import numpy as np

import acdf


def assert_bits_equal(got, want):
    got = np.ascontiguousarray(got)
    assert got.dtype == want.dtype
    assert got.size == want.size
    assert np.array_equal(got.reshape(-1).view(np.uint8), want.view(np.uint8))


def test_1d_tables(reference):
    f = reference.f32("f1d")
    u = reference.f32("u1d")
    tables = {
        "pc": acdf.PiecewiseConstant1D(f, -1.0, 3.0),
        "ad": acdf.AdaptiveCdf1D(f, -1.0, 3.0, epsilon=1e-3),
        "al": acdf.AliasTable1D(f, -1.0, 3.0),
    }
    for name, table in tables.items():
        x, pdf = table.sample(u)
        assert_bits_equal(x, reference.f32(name + "_x"))
        assert_bits_equal(pdf, reference.f32(name + "_pdf"))
        if name != "al":
            assert_bits_equal(table.invert(x), reference.f32(name + "_invert"))


def test_cascades(reference):
    u = reference.f32("c_u").reshape(-1, 2)
    c2 = acdf.Cascade(reference.f32("c2_values").reshape(48, 40),
                      axes=[(0.0, 3.14159265), (0.0, 6.28318531)], epsilon=1e-3)
    x, pdf = c2.sample(u)
    assert_bits_equal(x, reference.f32("c2_x"))
    assert_bits_equal(c2.pdf(x), reference.f32("c2_pdf"))
    assert_bits_equal(pdf, reference.f32("c2_pdf"))
    assert_bits_equal(c2.invert(x), reference.f32("c2_invert"))

    c3 = acdf.Cascade(reference.f32("c3_values").reshape(6, 16, 24), conditioning_dims=1,
                      methods=["uniform", "adaptive"], epsilon=5e-3)
    condition = reference.f32("c3_condition").reshape(-1, 1)
    x, pdf = c3.sample(u, condition)
    assert_bits_equal(x, reference.f32("c3_x"))
    assert_bits_equal(pdf, reference.f32("c3_pdf"))
    assert_bits_equal(c3.invert(x, condition), reference.f32("c3_invert"))
    assert [c2.bytes, c3.bytes] == reference.f64("c_bytes").tolist()


def test_environment_light(reference):
    light = acdf.EnvironmentLight.load(reference.path("sky.exr"), rotation=30.0, scale=2.0)
    dirs, radiance, pdf = light.sample(reference.f32("env_u").reshape(-1, 2))
    assert_bits_equal(dirs, reference.f64("env_dirs"))
    assert_bits_equal(radiance, reference.f32("env_radiance"))
    assert_bits_equal(pdf, reference.f64("env_pdf"))
    assert_bits_equal(light.pdf(dirs), reference.f64("env_pdf_at"))


def test_tabulated_merl_sampler(reference):
    model = acdf.MerlBrdf.load(reference.path("gold.binary"))
    sampler = acdf.TabulatedBrdfSampler(model, layout="isotropic", theta_out=16,
                                        theta_half=64, phi_half=16)
    assert sampler.bytes == reference.f64("brdf_bytes")[0]
    wo = reference.f64("brdf_wo").reshape(-1, 3)
    wi, weight, pdf = sampler.sample(wo, reference.f32("brdf_u").reshape(-1, 2))
    assert_bits_equal(wi, reference.f64("brdf_wi"))
    assert_bits_equal(weight, reference.f32("brdf_weight"))
    assert_bits_equal(pdf, reference.f64("brdf_pdf"))
    assert_bits_equal(sampler.pdf(wo, wi), reference.f64("brdf_pdf_at"))
    assert_bits_equal(model.eval(wo, wi), reference.f32("brdf_eval"))

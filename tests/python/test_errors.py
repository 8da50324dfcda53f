"""Every bad input raises the documented exception, with a message naming the problem."""
import os

import numpy as np
import pytest

import acdf


def test_missing_and_malformed_files(tmp_path):
    missing = str(tmp_path / "missing.exr")
    with pytest.raises(acdf.FileError, match="missing.exr"):
        acdf.EnvironmentLight.load(missing)
    assert issubclass(acdf.FileError, OSError)
    truncated = tmp_path / "truncated.binary"
    truncated.write_bytes(b"\x5a\x00\x00\x00\x5a\x00\x00\x00\xb4\x00\x00\x00" + b"\x00" * 100)
    with pytest.raises(OSError, match="truncated.binary"):
        acdf.MerlBrdf.load(str(truncated))
    not_an_image = tmp_path / "notes.exr"
    not_an_image.write_text("not an image")
    with pytest.raises(acdf.FileError, match="notes.exr"):
        acdf.EnvironmentMap.load(str(not_an_image))
    not_rgl = tmp_path / "plain.bsdf"
    not_rgl.write_bytes(b"tensor_file\x00" + b"\x01" * 7)
    with pytest.raises(acdf.FileError, match="plain.bsdf"):
        acdf.RglBrdf.load(str(not_rgl))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -1.0])
def test_bad_values(bad):
    values = np.ones((8, 4), np.float32)
    values[3, 2] = bad
    with pytest.raises(ValueError):
        acdf.Cascade(values)
    with pytest.raises(ValueError):
        acdf.PiecewiseConstant1D(values[3])
    with pytest.raises(ValueError):
        acdf.AdaptiveCdf1D(values[3])
    with pytest.raises(ValueError):
        acdf.AliasTable1D(values[3])
    rgb = np.ones((4, 8, 3), np.float32)
    rgb[1, 2, 0] = bad
    if not bad < 0:  # a negative radiance is clamped to 0 (counted), as when a file is read
        with pytest.raises(ValueError):
            acdf.EnvironmentMap(rgb)


def test_bad_shapes_and_options():
    c = acdf.Cascade(np.ones((8, 4), np.float32))
    with pytest.raises(ValueError, match=r"u: expected shape \(n, 2\), got \(5, 3\)"):
        c.sample(np.zeros((5, 3), np.float32))
    with pytest.raises(ValueError, match="condition"):
        c.sample(np.zeros((5, 2), np.float32), np.zeros((5, 1), np.float32))
    with pytest.raises(ValueError, match="axes"):
        acdf.Cascade(np.ones((8, 4), np.float32), axes=[(0.0, 1.0)])
    with pytest.raises(ValueError, match="dimension method"):
        acdf.Cascade(np.ones((8, 4), np.float32), methods=["adaptive", "dense"])
    with pytest.raises(ValueError, match="epsilon"):
        acdf.Cascade(np.ones((8, 4), np.float32), epsilon=-1.0)
    with pytest.raises(ValueError, match="conditioning"):
        acdf.Cascade(np.ones((8, 4), np.float32), conditioning_dims=2)
    with pytest.raises(ValueError, match="simplifier"):
        acdf.SimplifyOptions(method="dp")
    with pytest.raises(ValueError, match="weight"):
        acdf.SimplifyOptions(weight_bound=0.5)
    light = acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((4, 8, 3), np.float32)))
    with pytest.raises(ValueError, match="strategy|sampling"):
        acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((4, 8, 3), np.float32)), strategy="importance")
    with pytest.raises(ValueError, match="scale"):
        acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((4, 8, 3), np.float32)), scale=-1.0)
    with pytest.raises(ValueError, match="rgb"):
        acdf.EnvironmentMap(np.ones((4, 8), np.float32))
    with pytest.raises(ValueError, match="dirs: row 1"):
        light.pdf(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 0.0]]))
    with pytest.raises(ValueError, match="dirs: row 0"):
        light.eval(np.array([[np.nan, 1.0, 0.0]]))
    with pytest.raises(ValueError, match="normal: row 0"):
        light.sample(np.zeros((2, 2), np.float32), normal=np.zeros(3))
    with pytest.raises(ValueError, match="normal and the samples"):
        light.pdf(np.ones((3, 3)), normal=np.ones((2, 3)))
    with pytest.raises(ValueError, match="block_size"):
        acdf.EnvironmentLight(acdf.EnvironmentMap(np.ones((4, 8, 3), np.float32)), strategy="local", block_size=0)
    sampler = acdf.CosineBrdfSampler(acdf.LambertianBrdf([0.5, 0.5, 0.5]))
    with pytest.raises(ValueError, match="row counts differ"):
        sampler.pdf(np.tile([0.0, 0.0, 1.0], (3, 1)), np.tile([0.0, 0.0, 1.0], (4, 1)))
    with pytest.raises(ValueError, match="layout"):
        acdf.TabulatedBrdfSampler(acdf.AnalyticBrdf.preset("gold"), layout="iso")
    gold = acdf.AnalyticBrdf.preset("gold")
    with pytest.raises(TypeError, match="unknown table option 'theta_half_cells'.*theta_half"):
        acdf.TabulatedBrdfSampler(gold, theta_half_cells=64)
    with pytest.raises(TypeError, match="theta_half must be a count, got float"):
        acdf.TabulatedBrdfSampler(gold, theta_half=64.0)
    with pytest.raises(TypeError, match="mirror must be a boolean, got int"):
        acdf.TabulatedBrdfSampler(gold, layout="isotropic", mirror=1)
    with pytest.raises(ValueError, match="phi_half must be even"):
        acdf.TabulatedBrdfSampler(gold, layout="isotropic", phi_half=7)
    with pytest.raises(ValueError, match="theta_out must be a whole number"):
        acdf.TabulatedBrdfSampler(gold, theta_out=-4)
    with pytest.raises(ValueError, match="preset"):
        acdf.AnalyticBrdf.preset("unobtainium")
    with pytest.raises(ValueError, match="interpolation"):
        acdf.MerlBrdf.load("whatever.binary", interpolation="cubic")

"""Irradiance at +y from an environment map, E = ∫ L(ω) max(0, ω_y) dω, estimated with acdf's
adaptive light table and with cosine-weighted hemisphere sampling (the C++ sample_environment).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/quickstart.py MAP.exr [SAMPLES]
"""
import sys

import numpy as np

import acdf

n = int(sys.argv[2]) if len(sys.argv) > 2 else 100_000
light = acdf.EnvironmentLight.load(sys.argv[1], strategy="adaptive")
rng = np.random.default_rng(1)
luminance = np.array([0.2126, 0.7152, 0.0722])

dirs, radiance, pdf = light.sample(rng.random((n, 2), dtype=np.float32))
with_light = radiance @ luminance * np.maximum(dirs[:, 1], 0) / pdf

u = rng.random((n, 2))  # cosine-weighted about +y: pdf = cos θ / π, so L cos θ / pdf = π L
r, phi = np.sqrt(u[:, 0]), 2 * np.pi * u[:, 1]
w = np.stack([r * np.cos(phi), np.sqrt(1 - u[:, 0]), r * np.sin(phi)], axis=1)
with_cosine = np.pi * (light.eval(w) @ luminance)

print(f"{sys.argv[1]}: {light.map.width} x {light.map.height}, adaptive table of {light.bytes} bytes")
for name, f in [("light table", with_light), ("cosine hemisphere", with_cosine)]:
    print(f"  {name:<17} {f.mean():.6g} +- {f.std() / np.sqrt(n):.2g}")

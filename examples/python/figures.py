"""The paper's two pictures of an adaptive CDF, from real data, as PNG:

1. a 1D CDF (the luminance of one row of an environment map, through the sun) with the
   breakpoints Douglas-Peucker keeps, over the full table's CDF;
2. the environment map with the adaptive table's intervals drawn over it: the row intervals of
   the marginal and, inside each, the column intervals of its conditional.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/figures.py MAP.exr OUT_DIR [--epsilon E]
"""
import argparse
import io
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from PIL import Image  # noqa: E402  (matplotlib's own dependency)

import acdf  # noqa: E402


def save_png(fig, path):
    """A 256-colour PNG: a photograph under thin lines, a third of the size of a true-colour one."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    Image.open(buffer).convert("RGB").quantize(colors=256).save(path, optimize=True)


def tone_map(rgb):
    """Reinhard on luminance, then sRGB-ish gamma: enough to see sky and sun."""
    lum = rgb @ np.array([0.2126, 0.7152, 0.0722])
    scale = 1.0 / (1.0 + lum / np.percentile(lum, 99))
    return np.clip((rgb * scale[..., None]) ** (1 / 2.2), 0, 1)


def cdf_figure(environment, epsilon, path):
    power = environment.pixel_power()
    row = int(np.argmax(power.max(axis=1)))  # the row of the brightest pixel
    f = power[row].astype(np.float32)
    table = acdf.AdaptiveCdf1D(f, epsilon=epsilon)
    full = np.concatenate([[0.0], np.cumsum(f, dtype=np.float64) / f.sum(dtype=np.float64)])
    vertices, cdf = table.breakpoints
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    x = np.arange(len(full)) / (len(full) - 1)
    ax.plot(x, full, color="0.6", lw=3, label=f"uniform table ({len(f)} cells)")
    ax.plot(vertices / len(f), cdf, "o-", color="C3", ms=4, lw=1.2,
            label=f"adaptive, ε = {epsilon:g} ({table.points} points)")
    ax.set_xlabel("φ / 2π")
    ax.set_ylabel("CDF")
    ax.set_title(f"Row {row} of the map: luminance × solid angle, Douglas–Peucker breakpoints")
    ax.legend(loc="lower right")
    fig.tight_layout()
    save_png(fig, path)
    return table.points, len(f) + 1


def intervals_figure(environment, epsilon, path):
    # The adaptive light's table is this cascade: the map's luminance × solid angle per pixel.
    power = environment.pixel_power().astype(np.float32)
    table = acdf.Cascade(power, epsilon=epsilon)
    uniform = acdf.Cascade(power, methods=["uniform", "uniform"])
    rows = table.breakpoints(0)[0]
    columns = table.breakpoints(1)
    h, w = environment.height, environment.width
    fig, ax = plt.subplots(figsize=(10, 5.4), dpi=100)
    ax.imshow(tone_map(environment.rgb), extent=(0, w, h, 0), interpolation="nearest")
    ax.hlines(rows, 0, w, color="white", lw=0.6)
    for j in range(len(rows) - 1):
        ax.vlines(columns[j][1:-1], rows[j], rows[j + 1], color="C1", lw=0.5)
    boxes = sum(len(c) - 1 for c in columns)
    ax.set_title(f"Adaptive intervals, ε = {epsilon:g}: {len(rows) - 1} row intervals, {boxes} boxes, "
                 f"{table.bytes} bytes (uniform table: {uniform.bytes} bytes)")
    ax.set_axis_off()
    fig.tight_layout()
    save_png(fig, path)
    return boxes, table.bytes


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("map")
    parser.add_argument("out_dir")
    parser.add_argument("--epsilon", type=float, default=2e-3)
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    environment = acdf.EnvironmentMap.load(args.map)
    kept, cells = cdf_figure(environment, args.epsilon, os.path.join(args.out_dir, "cdf_breakpoints.png"))
    boxes, size = intervals_figure(environment, args.epsilon, os.path.join(args.out_dir, "envmap_intervals.png"))
    print(f"cdf_breakpoints.png: {kept} of {cells} points kept")
    print(f"envmap_intervals.png: {boxes} boxes, {size} bytes")


if __name__ == "__main__":
    main()

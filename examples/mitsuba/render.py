"""Renders a Mitsuba 3 scene lit by acdf_envmap with a sphere of acdf_measured on a diffuse floor.

    PYTHONPATH=build/python .venv/bin/python examples/mitsuba/render.py MAP.exr MATERIAL.bsdf out.exr \
        [--variant llvm_ad_rgb] [--spp 64] [--size 320x240] [--strategy compensated] [--sampling adaptive]

MATERIAL is a MERL .binary or an RGL .bsdf file (`acdf rgl-gen --preset gold -o gold.bsdf` writes
one). The scene is a Python dict passed to mi.load_dict; the image is written by Mitsuba.
"""
import argparse

import mitsuba as mi


def scene(envmap, material, strategy, sampling, width, height):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 8},
        "sensor": {
            "type": "perspective",
            "fov": 35,
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 1.5, 5], target=[0, 0.6, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": width, "height": height},
        },
        "light": {"type": "acdf_envmap", "filename": envmap, "strategy": strategy,
                  "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 90)},
        "ball": {"type": "sphere", "center": [0, 1, 0], "radius": 1,
                 "bsdf": {"type": "acdf_measured", "filename": material, "sampling": sampling}},
        "floor": {"type": "rectangle", "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.4}},
                  "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(6)},
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("envmap")
    parser.add_argument("material")
    parser.add_argument("output")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--size", default="320x240", help="the image's width x height in pixels")
    parser.add_argument("--strategy", default="compensated",
                        help="acdf_envmap's strategy (compensated: the lowest error under path, docs/performance.md)")
    parser.add_argument("--sampling", default="adaptive", help="acdf_measured's sampling")
    args = parser.parse_args()
    try:
        width, height = (int(v) for v in args.size.split("x"))
    except ValueError:
        parser.error(f"--size: expected WIDTHxHEIGHT, got {args.size!r}")

    mi.set_variant(args.variant)
    import acdf.mitsuba

    acdf.mitsuba.register()
    image = mi.render(mi.load_dict(scene(args.envmap, args.material, args.strategy, args.sampling, width, height)), spp=args.spp)
    mi.util.write_bitmap(args.output, image)
    print(f"{args.output}: {args.variant}, {args.spp} spp")


if __name__ == "__main__":
    main()

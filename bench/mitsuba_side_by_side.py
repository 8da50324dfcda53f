"""Mitsuba's envmap against acdf_envmap in the same Mitsuba scene: relMSE at equal spp, table bytes,
render time per spp (llvm_ad_rgb).

    PYTHONPATH=build/python .venv/bin/python bench/mitsuba_side_by_side.py MAP.exr... [--spp 16] [--seeds 4]

Each emitter is judged against its own reference (the same emitter at --reference-spp), since
envmap interpolates the map bilinearly and acdf_envmap takes the nearest pixel. relMSE is the
mean over pixels and channels of (I - R)^2 / (R^2 + 1e-2); its mean over seeds and, because
the glossy sphere's fireflies make it heavy-tailed, its median. The scene: a
diffuse floor and a rough gold sphere (GGX, Mitsuba's roughconductor), MIS path tracing, depth 3;
the map is not seen directly. Times are wall clock of mi.render after one warm-up render,
including acdf_envmap's Python overhead.
"""
import argparse
import time

import mitsuba as mi
import numpy as np


def scene(emitter, res):
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {"type": "perspective", "fov": 40,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 4, 4], target=[0, 0.5, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent"}},
        "ball": {"type": "sphere", "center": [0, 1, 0], "radius": 1,
                 "bsdf": {"type": "roughconductor", "material": "Au", "alpha": 0.1}},
        "floor": {"type": "rectangle", "bsdf": {"type": "diffuse"},
                  "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(20)},
        "light": emitter,
    })


def render(s, spp, seed):
    return np.asarray(mi.render(s, spp=spp, seed=seed), dtype=np.float64)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("maps", nargs="+")
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--reference-spp", type=int, default=2048)
    parser.add_argument("--res", type=int, default=96)
    args = parser.parse_args()
    mi.set_variant("llvm_ad_rgb")
    import acdf
    import acdf.mitsuba

    acdf.mitsuba.register()
    print(f"mitsuba {mi.__version__}, {args.res}x{args.res}, {args.spp} spp x {args.seeds} seeds, "
          f"references at {args.reference_spp} spp")
    print("map | emitter | relMSE mean | relMSE median over seeds | table bytes | ms per spp")
    for path in args.maps:
        emitters = {"envmap": {"type": "envmap", "filename": path}}
        for strategy in ("uniform", "adaptive", "compensated"):
            emitters[f"acdf_envmap {strategy}"] = {"type": "acdf_envmap", "filename": path, "strategy": strategy}
        for name, emitter in emitters.items():
            s = scene(emitter, args.res)
            reference = render(s, args.reference_spp, 1000)
            render(s, args.spp, 999)  # warm-up: kernels compiled and cached
            errors, seconds = [], 0.0
            for seed in range(args.seeds):
                t = time.perf_counter()
                image = render(s, args.spp, seed)
                seconds += time.perf_counter() - t
                errors.append(np.mean((image - reference) ** 2 / (reference**2 + 1e-2)))
            if name == "envmap":
                table = "n/a"  # Mitsuba does not report its Hierarchical2D's size
            else:
                light = acdf.EnvironmentLight.load(path, strategy=emitter["strategy"])
                table = str(light.bytes)
            ms = 1000 * seconds / (args.seeds * args.spp)
            print(f"{path.split('/')[-1]} | {name} | {np.mean(errors):.5f} | {np.median(errors):.5f} | {table} | {ms:.2f}",
                  flush=True)


if __name__ == "__main__":
    main()

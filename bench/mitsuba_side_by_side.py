"""Mitsuba 3's envmap and measured against acdf_envmap and acdf_measured in the same Mitsuba scenes
and the same `path` integrator (llvm_ad_rgb): image means, relMSE at equal spp, time per spp,
efficiency at equal time, table bytes.

    PYTHONPATH=build/python .venv/bin/python bench/mitsuba_side_by_side.py \\
        --maps MAP.exr... --rgl FILE.bsdf... [--spp 16] [--seeds 16] [--reference-spp 1024] [--res 256] \\
        [--timing-renders 7]

Environment lights: a diffuse floor and a rough gold sphere (Mitsuba's roughconductor, GGX
alpha 0.1), depth 3, the map not seen directly. Each emitter is judged against its own reference
(the same emitter at --reference-spp): envmap interpolates the map bilinearly, acdf_envmap takes
the nearest pixel, so their images differ slightly where the map varies within a pixel.
Measured materials: a sphere of the material on a diffuse floor under Mitsuba's envmap of
--bsdf-map, depth 3; every BSDF is judged against Mitsuba's measured at --reference-spp, since
acdf_measured evaluates the file as measured does (tests/python/test_mitsuba.py).

Per row: relMSE = mean over pixels and channels of (I - R)^2 / (R^2 + 1e-2) of one --spp image,
its mean over seeds with the standard error, and its median (the glossy sphere's fireflies make it
heavy-tailed); the largest |z| of the image means against Mitsuba's plugin, over the frame and
4 x 4 blocks per channel, with the Sidak bound at alpha 0.01 (means and variances from the seeds'
images); table bytes (acdf's C++ table's, and of the drjit arrays a plugin samples in drjit);
wall time per spp of the median mi.render after a warm-up render (kernels compiled and cached;
with --timing-renders N, the fastest of N renders interleaved with the map's or file's other rows);
efficiency at equal time against the Mitsuba plugin of the block, (relMSE x time per spp) of
Mitsuba's over the row's: above 1, the row reaches a given error sooner. Every row renders with
drjit's symbolic loops and calls on, as a user's render does: acdf's plugins sample in drjit.
"""
import argparse
import time

import mitsuba as mi
import numpy as np
from scipy.stats import norm

BLOCKS = 4


def envmap_scene(emitter, res):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": sensor([0, 4, 4], [0, 0.5, 0], res),
        "ball": {"type": "sphere", "center": [0, 1, 0], "radius": 1,
                 "bsdf": {"type": "roughconductor", "material": "Au", "alpha": 0.1}},
        "floor": floor(),
        "light": emitter,
    }


def material_scene(bsdf, light_map, res):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": sensor([0, 2.5, 3.5], [0, 0.8, 0], res),
        "ball": {"type": "sphere", "center": [0, 1, 0], "radius": 1, "bsdf": bsdf},
        "floor": floor(),
        "light": {"type": "envmap", "filename": light_map},
    }


def sensor(origin, target, res):
    return {"type": "perspective", "fov": 40,
            "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=target, up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
            "sampler": {"type": "independent"}}


def floor():
    return {"type": "rectangle", "bsdf": {"type": "diffuse"},
            "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale(20)}


def interleaved_ms_per_spp(scenes, args):
    """ms per spp of each scene after measure()'s warm-up: the fastest of --timing-renders renders at
    --spp, the scenes taking turns so that load from other work on a shared machine falls on all of
    them alike."""
    best = [float("inf")] * len(scenes)
    for turn in range(args.timing_renders):
        for i, scene in enumerate(scenes):
            start = time.perf_counter()
            render(scene, args.spp, 2000 + turn)
            best[i] = min(best[i], time.perf_counter() - start)
    return [f"{1000.0 * seconds / args.spp:.2f}" for seconds in best]


def render(scene, spp, seed):
    return np.asarray(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)


def rel_mse(image, reference):
    return float(np.mean((image - reference) ** 2 / (reference**2 + 1e-2)))


def region_means(images):
    """Per seed, the frame's mean and the BLOCKS x BLOCKS blocks' means, per channel: (seeds, regions*3)."""
    seeds, h, w, c = images.shape
    blocks = images[:, : h - h % BLOCKS, : w - w % BLOCKS].reshape(seeds, BLOCKS, h // BLOCKS, BLOCKS, w // BLOCKS, c)
    return np.concatenate([images.mean((1, 2)), blocks.mean((2, 4)).reshape(seeds, -1)], axis=1)


def max_z(images, baseline):
    """The largest |z| of the region means against the baseline's (Welch, over seeds), its Sidak
    bound, and the channel it is in."""
    a, b = region_means(images), region_means(baseline)
    se = np.sqrt(a.var(0, ddof=1) / len(a) + b.var(0, ddof=1) / len(b))
    z = np.abs(a.mean(0) - b.mean(0)) / np.maximum(se, 1e-300)
    tests = a.shape[1]
    return float(z.max()), float(norm.ppf(1 - (1 - (1 - 0.01) ** (1 / tests)) / 2)), "RGB"[int(z.argmax()) % 3]


def measure(scene, reference, args):
    render(scene, args.spp, 999)  # warm-up: kernels compiled and cached
    images, seconds = [], []
    for seed in range(args.seeds):
        start = time.perf_counter()
        images.append(render(scene, args.spp, seed))
        seconds.append(time.perf_counter() - start)
    errors = np.array([rel_mse(image, reference) for image in images])
    # The median render: a spike of load on a shared machine moves one render, not the figure.
    ms_per_spp = 1000.0 * float(np.median(seconds)) / args.spp
    return np.stack(images), errors, f"{ms_per_spp:.2f}"


def report(source, name, errors, z, table, ms, baseline):
    """One row; baseline: (mean relMSE, ms per spp) of the block's Mitsuba plugin (None for that row)."""
    mean, se = errors.mean(), errors.std(ddof=1) / np.sqrt(len(errors))
    z = "-" if z is None else f"{z[0]:.2f} {z[2]} (bound {z[1]:.2f})"
    efficiency = "1" if baseline is None else f"{baseline[0] * baseline[1] / (mean * float(ms)):.2f}"
    print(f"{source} | {name} | {mean:.5f} ± {se:.5f} | {np.median(errors):.5f} | {z} "
          f"| {table} | {ms} | {efficiency}", flush=True)
    return mean, float(ms)


def hierarchical_bytes(path):
    """Mitsuba's envmap warp (Hierarchical2D over the map padded to powers of two), estimated from
    its structure: float levels summing to 4/3 of the finest. Mitsuba does not report it."""
    bitmap = mi.Bitmap(path)
    w, h = bitmap.size()
    finest = (1 << int(np.ceil(np.log2(w)))) * (1 << int(np.ceil(np.log2(h))))
    return f"~{int(4 * finest * 4 / 3)}"


def report_block(source, rows, scenes, args):
    """Reports one map's or file's rows, the first Mitsuba's own plugin (each other row's efficiency is
    against it); with --timing-renders the rows take the fastest of their scenes' interleaved renders
    as their time."""
    if args.timing_renders:
        rows = [row[:4] + (ms,) for row, ms in zip(rows, interleaved_ms_per_spp(scenes, args))]
    baseline = None
    for name, errors, z, table, ms in rows:
        row = report(source, name, errors, z, table, ms, baseline)
        baseline = baseline or row


def plugin_parameters(row):
    """'compensated' or 'adaptive:epsilon=5e-4,...': the strategy and the plugin's table options."""
    strategy, _, options = row.partition(":")
    parameters = {"strategy": strategy}
    for option in filter(None, options.split(",")):
        name, _, value = option.partition("=")
        parameters[name] = float(value) if "." in value or "e" in value else int(value)
    return parameters


def compare_envmaps(args, acdf):
    print(f"\n## envmap vs acdf_envmap: {args.res}x{args.res}, {args.spp} spp x {args.seeds} seeds, "
          f"references at {args.reference_spp} spp")
    print("map | emitter | relMSE mean ± se | median | max |z| of means vs envmap | table bytes | ms/spp "
          "| efficiency vs envmap")
    for path in args.maps:
        source = path.split("/")[-1]
        theirs = mi.load_dict(envmap_scene({"type": "envmap", "filename": path}, args.res))
        reference = render(theirs, args.reference_spp, 1000)
        baseline, errors, ms = measure(theirs, reference, args)
        rows = [("envmap", errors, None, hierarchical_bytes(path), ms)]
        scenes = [theirs]  # each row's, timed interleaved
        for strategy in args.strategies:
            plugin = {"type": "acdf_envmap", "filename": path, **plugin_parameters(strategy)}
            scene = mi.load_dict(envmap_scene(plugin, args.res))
            emitter = scene.emitters()[0]
            reference = render(scene, args.reference_spp, 1000)
            images, errors, ms = measure(scene, reference, args)
            rows.append((f"acdf_envmap {strategy}", errors, max_z(images, baseline), emitter.bytes, ms))
            scenes.append(scene)
        report_block(source, rows, scenes, args)


def compare_materials(args, acdf):
    print(f"\n## measured vs acdf_measured under {args.bsdf_map.split('/')[-1]}: {args.res}x{args.res}, "
          f"{args.spp} spp x {args.seeds} seeds, all against measured at {args.reference_spp} spp")
    print("file | bsdf | relMSE mean ± se | median | max |z| of means vs measured | table bytes | ms/spp "
          "| efficiency vs measured")
    for path in args.rgl:
        source = path.split("/")[-1]
        theirs = mi.load_dict(material_scene({"type": "measured", "filename": path}, args.bsdf_map, args.res))
        reference = render(theirs, args.reference_spp, 1000)
        baseline, errors, ms = measure(theirs, reference, args)
        warps = acdf.RglBrdfSampler(acdf.RglBrdf.load(path)).bytes
        rows = [("measured", errors, None, f"{warps} (its warps)", ms)]
        scenes = [theirs]  # each row's, timed interleaved
        for sampling in args.samplings:
            bsdf = {"type": "acdf_measured", "filename": path, "sampling": sampling}
            scene = mi.load_dict(material_scene(bsdf, args.bsdf_map, args.res))
            plugin = next(s.bsdf() for s in scene.shapes() if "Acdf" in str(s.bsdf()))
            images, errors, ms = measure(scene, reference, args)
            table = f"{plugin.bytes} (1/{warps / plugin.bytes:.1f})" if plugin.bytes else "0"
            if plugin.table is not None:  # the drjit copy the plugin samples (cosine sampling has none)
                table += f"; in drjit {plugin.table.bytes} (1/{warps / plugin.table.bytes:.1f})"
            rows.append((f"acdf_measured {sampling}", errors, max_z(images, baseline), table, ms))
            scenes.append(scene)
        report_block(source, rows, scenes, args)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", nargs="*", default=[])
    parser.add_argument("--strategies", nargs="+", default=["adaptive", "compensated"],
                        help="acdf_envmap rows: a strategy, or strategy:option=value,... with the plugin's table "
                        "options (e.g. adaptive:epsilon=5e-4)")
    parser.add_argument("--rgl", nargs="*", default=[])
    parser.add_argument("--samplings", nargs="+", default=["adaptive", "uniform", "rgl"])
    parser.add_argument("--bsdf-map", help="the envmap the measured materials are lit by")
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--reference-spp", type=int, default=1024)
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--timing-renders", type=int, default=0,
                        help="time each row as the fastest of this many renders at --spp, "
                        "interleaved with its map's or file's other rows (0: the median of the seeds' renders)")
    args = parser.parse_args()
    if args.rgl and not args.bsdf_map:
        parser.error("--rgl needs --bsdf-map")
    mi.set_variant("llvm_ad_rgb")
    import acdf
    import acdf.mitsuba

    acdf.mitsuba.register()
    print(f"mitsuba {mi.__version__}, acdf {acdf.__version__}")
    if args.maps:
        compare_envmaps(args, acdf)
    if args.rgl:
        compare_materials(args, acdf)


if __name__ == "__main__":
    main()

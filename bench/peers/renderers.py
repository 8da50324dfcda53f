"""The renderers of the comparison, each rendering one scene file at given (spp, seed) pairs.

Each renderer runs in its own process (`python bench/peers/renderers.py RENDERER ...`): bpy and Mitsuba
each bring their own LLVM, and a fresh process keeps one renderer's warm caches from another's timing.
The process renders a warm-up image at each sample count (not reported: table cache, JIT, first touch), then
every requested image, and saves them with their wall-clock seconds around the render call.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scene_conversion  # noqa: E402 (the directory is not a package)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ACDF_PROGRAM = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))

# The exit status of a renderer process refusing a scene (its one line on stderr)
UNSUPPORTED_EXIT = 3

# Row name -> what it renders with; the order of the report's rows.
RENDERERS = {
    "acdf": "acdf render, the scene's strategies (the defaults: Sobol, compensated map table, balance MIS)",
    "cycles": "Cycles 5.0.1, CPU, its defaults",
    "cycles-guiding": "Cycles 5.0.1 with path guiding (use_guiding, use_surface_guiding)",
    "mitsuba-independent": "Mitsuba 3.9.1 llvm_ad_rgb, path, independent sampler",
    "mitsuba-multijitter": "Mitsuba 3.9.1 llvm_ad_rgb, path, multijitter sampler",
    "mitsuba-multijitter-acdf": "the same with the map sampled by acdf's plugin (acdf_envmap, compensated: "
                                "acdf render's default table, traced into Mitsuba's kernels)",
}


def read_exr_with_mitsuba(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path), dtype=np.float64)[:, :, :3]


class AcdfRenderer:
    def __init__(self, scene, threads, workdir):
        self.threads, self.workdir = threads, workdir
        # the scene as read (absolute paths, the resolution asked for), so it renders from anywhere
        self.scene_path = os.path.join(workdir, scene.name + ".json")
        with open(self.scene_path, "w") as f:
            json.dump(scene.data, f)

    def render(self, spp, seed):
        output = os.path.join(self.workdir, "acdf.exr")
        command = [ACDF_PROGRAM, "render", self.scene_path, "-o", output, "--no-png", "--spp", str(spp),
                   "--seed", str(seed), "--threads", str(self.threads)]
        start = time.perf_counter()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        seconds = time.perf_counter() - start
        return read_exr_with_mitsuba(output), seconds


class CyclesRenderer:
    def __init__(self, scene, threads, workdir, guiding):
        self.blender = scene_conversion.build_blender_scene(scene, threads, guiding)
        self.blender.render.filepath = self.output = os.path.join(workdir, "cycles.exr")

    def render(self, spp, seed):
        import bpy
        self.blender.cycles.samples, self.blender.cycles.seed = spp, seed
        start = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        seconds = time.perf_counter() - start
        image = bpy.data.images.load(self.output)
        width, height = image.size
        pixels = np.array(image.pixels[:], dtype=np.float64).reshape(height, width, image.channels)
        bpy.data.images.remove(image)
        return pixels[::-1, :, :3], seconds  # Blender's rows run bottom-up


class MitsubaRenderer:
    def __init__(self, scene, threads, sampler, acdf_map):
        import drjit as dr
        import mitsuba as mi
        mi.set_variant("llvm_ad_rgb")
        dr.set_thread_count(threads)
        if acdf_map:
            import acdf.mitsuba
            acdf.mitsuba.register()  # the map's tables in drjit: no Python per wavefront
        scene_dict = scene_conversion.mitsuba_scene_dict(scene, sampler, 1, acdf_map)
        self.scene = scene_conversion.load_mitsuba_scene(scene_dict)

    def render(self, spp, seed):
        import drjit as dr
        import mitsuba as mi
        start = time.perf_counter()
        image = mi.render(self.scene, spp=spp, seed=seed)
        dr.eval(image)
        dr.sync_thread()
        seconds = time.perf_counter() - start
        return np.array(image, dtype=np.float64), seconds


def peer_of(name):
    """The renderer a row's name refers to in refusals: "Cycles", "Mitsuba 3", or None for acdf."""
    return {"cycles": "Cycles", "mitsuba": "Mitsuba 3"}.get(name.split("-")[0])


def make_renderer(name, scene, threads, workdir):
    """The renderer of a row; raises scene_conversion.Unsupported for a scene it cannot express."""
    if name == "acdf":
        return AcdfRenderer(scene, threads, workdir)
    if name.startswith("cycles"):
        return CyclesRenderer(scene, threads, workdir, guiding=name == "cycles-guiding")
    if name.startswith("mitsuba"):
        return MitsubaRenderer(scene, threads, name.split("-")[1], acdf_map=name.endswith("-acdf"))
    raise ValueError(f"unknown renderer {name!r} (one of {', '.join(RENDERERS)})")


def render_all(name, scene_path, spp_counts, seeds, threads, resolution=None):
    """{"images": array [len(spp_counts), len(seeds), H, W, 3], "seconds": same shape without H, W, 3}."""
    scene = scene_conversion.read_scene(scene_path, resolution)
    with tempfile.TemporaryDirectory(prefix="peers-") as workdir:
        renderer = make_renderer(name, scene, threads, workdir)
        for spp in spp_counts:  # warm-up renders, at every count: Mitsuba compiles a kernel per sample count
            renderer.render(spp, seed=10_000)
        images, seconds = [], []
        for spp in spp_counts:
            rendered = [renderer.render(spp, seed) for seed in seeds]
            images.append([image for image, _ in rendered])
            seconds.append([s for _, s in rendered])
    return {"images": np.array(images), "seconds": np.array(seconds)}


def run_in_subprocess(name, scene_path, spp_counts, seeds, threads, resolution=None):
    """render_all in a fresh process; raises scene_conversion.Unsupported with the process's reason."""
    with tempfile.TemporaryDirectory(prefix="peers-") as directory:
        output = os.path.join(directory, "result.npz")
        command = [sys.executable, os.path.abspath(__file__), name, scene_path, "--spp", ",".join(map(str, spp_counts)),
                   "--seeds", ",".join(map(str, seeds)), "--threads", str(threads), "-o", output]
        if resolution:
            command += ["--resolution", "{}x{}".format(*resolution)]
        process = subprocess.run(command, capture_output=True, text=True)
        if process.returncode == UNSUPPORTED_EXIT:
            raise scene_conversion.Unsupported(process.stderr.strip().splitlines()[-1])
        if process.returncode != 0:
            raise RuntimeError(f"{name} on {scene_path} failed:\n{process.stdout[-2000:]}\n{process.stderr[-4000:]}")
        with np.load(output) as result:
            return {key: result[key] for key in result.files}


def parse_resolution(text):
    width, height = text.lower().split("x")
    return int(width), int(height)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("renderer", choices=list(RENDERERS))
    parser.add_argument("scene")
    parser.add_argument("--spp", required=True, help="comma-separated sample counts")
    parser.add_argument("--seeds", required=True, help="comma-separated seeds")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--resolution", type=parse_resolution, help="WIDTHxHEIGHT instead of the scene's")
    parser.add_argument("-o", "--output", required=True, help=".npz with images and seconds")
    args = parser.parse_args()
    try:
        result = render_all(args.renderer, args.scene, [int(s) for s in args.spp.split(",")],
                            [int(s) for s in args.seeds.split(",")], args.threads, args.resolution)
    except scene_conversion.Unsupported as e:
        print(e, file=sys.stderr)
        sys.exit(UNSUPPORTED_EXIT)
    np.savez(args.output, **result)


if __name__ == "__main__":
    main()

"""acdf against Cycles 5 and Mitsuba 3 at equal time, on acdf scene files (`make bench-peers`).

    .venv-peers/bin/python bench/peers/bench_peers.py [SCENE.json ...] [--seeds 4] [--spp 16,64]
        [--resolution 256x192] [--threads 2] [--renderers acdf,cycles,...] [--out bench/results/peers]

Every renderer renders each scene with K seeds at two sample counts (2 threads each, in its own process,
after a warm-up render). Per row: the image mean over pixels and channels with its standard error over the
seeds, its z-score against acdf's; the relative variance per sample, the mean over pixels and channels of
the variance across seeds x spp / (R^2 + 0.01), R acdf's mean image, at the larger count; the seconds per
sample, the marginal wall-clock cost between the two counts (so start-up, scene loading, BVH and table
builds cancel); efficiency = 1 / (relative variance per sample x seconds per sample). A scene a peer cannot
express is skipped for that peer with the reason (scene_conversion.Unsupported); acdf is skipped where no
peer renders. Writes report.json, table.md and efficiency.png into --out (--from-report: only the last two,
from a saved report.json).
"""
import argparse
import glob
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import efficiency  # noqa: E402
import renderers  # noqa: E402
import scene_conversion  # noqa: E402

DEFAULT_SCENES = sorted(glob.glob(os.path.join(renderers.ROOT, "scenes", "*.json"))
                        + glob.glob(os.path.join(renderers.ROOT, "bench", "peers", "scenes", "*.json")))


def relative_path(path):
    return os.path.relpath(path, renderers.ROOT)


def measure_scene(scene_path, names, spp_counts, seeds, threads, resolution):
    """{"rows": {renderer: figures}, "skipped": {renderer: reason}} for one scene."""
    skipped, results = {}, {}
    scene = scene_conversion.read_scene(scene_path)
    for name in names:
        if renderers.peer_of(name):
            try:
                scene_conversion.check_peer_can_render(scene, renderers.peer_of(name))
            except scene_conversion.Unsupported as e:
                skipped[name] = str(e)
    if all(name in skipped or name == "acdf" for name in names):
        return {"rows": {}, "skipped": dict(skipped, acdf="no peer renders this scene")}
    for name in names:
        if name in skipped:
            continue
        print(f"  {name} ...", end="", flush=True)
        start = time.perf_counter()
        results[name] = renderers.run_in_subprocess(name, scene_path, spp_counts, seeds, threads, resolution)
        print(f" {time.perf_counter() - start:.0f} s", flush=True)
    return {"rows": figures(results, spp_counts), "skipped": skipped}


def figures(results, spp_counts):
    """The report's numbers per renderer from its images and seconds (acdf's images are the reference)."""
    reference_images = results["acdf"]["images"][-1]
    reference = reference_images.mean(axis=0)
    rows = {}
    for name, result in results.items():
        images = result["images"][-1]
        mean, error = efficiency.mean_and_standard_error(images)
        relative_variance = efficiency.relative_variance_per_sample(images, spp_counts[-1], reference)
        seconds = efficiency.seconds_per_sample(result["seconds"], spp_counts)
        rows[name] = {
            "mean": mean, "mean_standard_error": error,
            "z_against_acdf": efficiency.mean_z(images, reference_images) if name != "acdf" else 0.0,
            "relative_variance_per_sample": relative_variance,
            "seconds_per_sample": seconds,
            "efficiency": efficiency.efficiency(relative_variance, seconds),
            "median_seconds": [float(np.median(s)) for s in result["seconds"]],
        }
    for row in rows.values():
        row["efficiency_vs_acdf"] = row["efficiency"] / rows["acdf"]["efficiency"]
    return rows


def markdown_table(report):
    lines = ["| scene | renderer | image mean ± s.e. | z vs acdf | rel. variance / spp | ms / spp | efficiency "
             "| ÷ acdf |", "|---|---|---|---|---|---|---|---|"]
    skipped = []
    for scene, entry in report["scenes"].items():
        for name, row in entry["rows"].items():
            lines.append(f"| {scene} | {name} | {row['mean']:.5f} ± {row['mean_standard_error']:.1g} "
                         f"| {row['z_against_acdf']:+.1f} | {row['relative_variance_per_sample']:.3g} "
                         f"| {1e3 * row['seconds_per_sample']:.3g} | {row['efficiency']:.3g} "
                         f"| {row['efficiency_vs_acdf']:.2f} |")
        skipped += [f"- {scene}, {name}: {reason}" for name, reason in entry["skipped"].items()]
    return "\n".join(lines + ([""] + ["Skipped:"] + skipped if skipped else [])) + "\n"


def plot(report, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = [scene for scene, entry in report["scenes"].items() if entry["rows"]]
    if not scenes:
        return
    names = [name for name in renderers.RENDERERS if any(name in report["scenes"][s]["rows"] for s in scenes)]
    figure, axes = plt.subplots(figsize=(1.6 + 1.8 * len(scenes), 3.6))
    width = 0.8 / len(names)
    for i, name in enumerate(names):
        values = [report["scenes"][s]["rows"].get(name, {}).get("efficiency", math.nan) for s in scenes]
        axes.bar(np.arange(len(scenes)) + (i - (len(names) - 1) / 2) * width, values, width, label=name)
    axes.set_xticks(np.arange(len(scenes)), scenes)
    axes.set_yscale("log")
    axes.set_ylabel("1 / (rel. variance × seconds), per spp")
    axes.set_title(f"equal-time efficiency, {report['resolution']}, {report['seeds']} seeds, "
                   f"{report['threads']} threads", fontsize=9)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenes", nargs="*", default=DEFAULT_SCENES)
    parser.add_argument("--seeds", type=int, default=4, help="K seeded renders per sample count")
    parser.add_argument("--spp", default="16,64", help="the two sample counts")
    parser.add_argument("--resolution", type=renderers.parse_resolution, default=(256, 192),
                        help="WIDTHxHEIGHT for every scene")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--renderers", default=",".join(renderers.RENDERERS))
    parser.add_argument("--out", default=os.path.join(renderers.ROOT, "bench", "results", "peers"))
    parser.add_argument("--from-report", metavar="REPORT.json", help="render nothing: the table and plot of a run")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.from_report:
        with open(args.from_report) as f:
            write_table_and_plot(json.load(f), args.out)
        return

    spp_counts = [int(s) for s in args.spp.split(",")]
    if len(spp_counts) != 2 or not spp_counts[0] < spp_counts[1]:
        parser.error("--spp takes two increasing counts, e.g. 16,64")
    names = args.renderers.split(",")
    if "acdf" not in names:
        parser.error("--renderers must include acdf (the reference of every row)")
    seeds = list(range(1, args.seeds + 1))

    report = {"command": " ".join(sys.argv), "resolution": "{}x{}".format(*args.resolution), "seeds": args.seeds,
              "spp": spp_counts, "threads": args.threads, "renderers": {n: renderers.RENDERERS[n] for n in names},
              "scenes": {}}
    for scene_path in args.scenes:
        name = os.path.splitext(relative_path(scene_path))[0].replace("scenes/", "")
        print(f"{relative_path(scene_path)}:", flush=True)
        report["scenes"][name] = measure_scene(scene_path, names, spp_counts, seeds, args.threads, args.resolution)
        for renderer, reason in report["scenes"][name]["skipped"].items():
            print(f"  {renderer} skipped: {reason}")
        with open(os.path.join(args.out, "report.json"), "w") as f:  # after every scene: a partial run is kept
            json.dump(report, f, indent=1)
    write_table_and_plot(report, args.out)


def write_table_and_plot(report, directory):
    with open(os.path.join(directory, "table.md"), "w") as f:
        f.write(markdown_table(report))
    plot(report, os.path.join(directory, "efficiency.png"))
    print(markdown_table(report))


if __name__ == "__main__":
    main()

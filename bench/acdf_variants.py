"""acdf render of one scene under several command-line variants, side by side: K seeded renders of each,
then per variant the relative variance per sample (as make bench-peers computes it, against the mean of
every variant's renders), the median seconds per image and CPU seconds per image, the image mean with its
standard error, and the --json keys a variant reports about guiding.

    .venv/bin/python bench/acdf_variants.py scenes/room.json --spp 64 --seeds 4 \\
        --variant "--guiding off" --variant "--guiding light" --variant "--guiding auto"

With --program given more than once, every variant runs with each acdf program (two builds of the
project side by side, on the same seeds), and a row names its program:

    .venv/bin/python bench/acdf_variants.py scenes/room.json --variant "" \\
        --program /tmp/acdf-before --program build/bin/acdf

Reads the EXRs with Mitsuba's Bitmap (the project's .venv has it). A benchmark, not a test.
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "peers"))
import efficiency  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ACDF_PROGRAM = os.environ.get("ACDF_PROGRAM", os.path.join(ROOT, "build", "bin", "acdf"))


def read_exr(path):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path), dtype=np.float64)[:, :, :3]


def render(program, scene, variant, spp, seed, threads, output):
    command = [program, "render", scene, "-o", output, "--no-png", "--spp", str(spp), "--seed", str(seed),
               "--threads", str(threads), "--json"] + variant.split()
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = subprocess.run(command, check=True, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return read_exr(output), seconds, cpu, json.loads(result.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--variant", action="append", required=True, help="extra acdf render arguments")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--program", action="append",
                        help=f"an acdf program to run every variant with (default: {ACDF_PROGRAM})")
    args = parser.parse_args()
    programs = args.program or [ACDF_PROGRAM]
    if args.seeds < 2:
        parser.error("--seeds must be at least 2")

    rows = {}
    with tempfile.TemporaryDirectory() as workdir:
        output = os.path.join(workdir, "image.exr")
        # Seeds outermost, so load that changes during the run falls on every variant alike.
        runs = {(program, variant): [] for program in programs for variant in args.variant}
        for k in range(args.seeds):
            for program, variant in runs:
                runs[program, variant].append(render(program, args.scene, variant, args.spp, 1000 + k, args.threads,
                                                     output))
        for (program, variant), results in runs.items():
            label = f"{program}: `{variant}`" if len(programs) > 1 else f"`{variant}`"
            rows[label] = (np.array([r[0] for r in results]), [r[1] for r in results], [r[2] for r in results],
                           results[-1][3])
    reference = np.mean([images.mean(axis=0) for images, *_ in rows.values()], axis=0)
    print(f"{args.scene}: {args.spp} spp x {args.seeds} seeds, {args.threads} threads, "
          f"load average {os.getloadavg()[0]:.1f}")
    print("| variant | relative variance per sample | s per image (median) | CPU s per image (median) | image mean "
          "| guided | auto's gain |")
    print("|---|---|---|---|---|---|---|")
    for variant, (images, seconds, cpu, report) in rows.items():
        relative_variance = efficiency.relative_variance_per_sample(images, args.spp, reference)
        mean, error = efficiency.mean_and_standard_error(images)
        gain = report.get("guiding_gain")
        print(f"| {variant} | {relative_variance:.4g} | {statistics.median(seconds):.2f} | "
              f"{statistics.median(cpu):.2f} | {mean:.5f} ± {error:.1g} | {report.get('guided', '')} | "
              f"{'' if gain is None else f'{gain:.2f}'} |")


if __name__ == "__main__":
    main()

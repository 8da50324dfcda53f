#!/usr/bin/env python3
"""Regenerates the tables of docs/paper-reproduction.md: the paper's Table 1 beside our figures
for the same three materials (4D table and our isotropic one) and the rows of the three real
environment maps.

usage: bench/paper_reproduction.py [--acdf build/bin/acdf] [--materials build/demo]
                                   [--envmaps ../shared/data/envmaps] [--samples 4096]
                                   [--repeats 3] [--update docs/paper-reproduction.md]

Each command runs --repeats times. Variances, bytes and resolutions are deterministic (fixed seed)
and must agree between repeats; times are not, so each estimator's fastest repeat is used (the
least disturbed by other work on the machine). Without --update the tables go to stdout.
Environment-map rows are skipped, with a message, when the maps are absent (a user's clone).
"""

import argparse
import datetime
import json
import os
import subprocess
import sys

from doc_sections import machine, replace_sections, table

MATERIALS = [  # (our file name, the paper's name)
    ("nickel", "nickel"),
    ("blue-metallic-paint", "metallic-blue"),
    ("specular-blue-phenolic", "plastic"),
]
# The paper's Table 1: adaptive average resolution, compression, efficiency adaptive / uniform.
PAPER = {
    "nickel": ("32 × 16 × 30 × 10", "27 : 1", "0.985"),
    "blue-metallic-paint": ("32 × 16 × 30 × 12", "23 : 1", "0.836"),
    "specular-blue-phenolic": ("32 × 16 × 30 × 9", "30 : 1", "1.027"),
}
ENVMAPS = ["sunset_1024x512.exr", "forest_1024x512.exr", "stage_1000x500.exr"]
DETERMINISTIC = ("variance", "mean", "max_weight", "stratified_variance", "bytes")


def run_json(command):
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("paper_reproduction: %s failed (exit %d): %s" % (" ".join(command), result.returncode,
                                                                  result.stderr.strip()))
    return json.loads(result.stdout)


def fastest_of(command, repeats, estimators):
    """Runs command repeats times; returns the first report with each estimator's fastest
    ns_per_sample (and its efficiency recomputed), after checking the deterministic figures agree."""
    reports = [run_json(command) for _ in range(repeats)]
    best = reports[0]
    for name in estimators:
        for other in reports[1:]:
            for key in DETERMINISTIC:
                if key in best[name] and best[name][key] != other[name][key]:
                    sys.exit("paper_reproduction: %s: %s.%s differs between repeats (%r, %r)"
                             % (" ".join(command), name, key, best[name][key], other[name][key]))
        best[name]["ns_per_sample"] = min(r[name]["ns_per_sample"] for r in reports)
        best[name]["efficiency"] = 1e9 / (best[name]["variance"] * best[name]["ns_per_sample"])
    return best


def thousands(n):
    return "{:,}".format(int(n)).replace(",", " ")


def resolution(values):
    return " × ".join("%d" % v if float(v).is_integer() else "{:#.3g}".format(v) for v in values)


def g4(x):
    return ("%.4g" % x).replace("e-0", "e-")


def brdf_tables(args):
    ratios, absolute, iso = [], [], []
    for name, paper_name in MATERIALS:
        path = os.path.join(args.materials, name + ".binary")
        if not os.path.isfile(path):
            sys.exit("paper_reproduction: %s: no such file (generate it with `acdf merl-gen --nbrdf %s -o %s`,"
                     " or run `make demo-materials`)" % (path, name, path))
        command = [args.acdf, "brdf-stats", path, "--samples", str(args.samples), "--json"]
        estimators = ("cosine", "uniform", "adaptive")
        r = fastest_of(command, args.repeats, estimators)
        u, a, c = r["uniform"], r["adaptive"], r["cosine"]
        paper_res, paper_compression, paper_efficiency = PAPER[name]
        label = name if paper_name == name else "%s (%s)" % (paper_name, name)
        ratios.append((label, paper_res, paper_compression, paper_efficiency,
                       resolution(r["adaptive_avg_res"]), "%.1f : 1" % r["compression"],
                       "%.3f" % (a["variance"] / u["variance"]), "%.2f" % (a["efficiency"] / u["efficiency"])))
        absolute.append((name, thousands(u["bytes"]), thousands(a["bytes"]),
                         " / ".join(g4(x["variance"]) for x in (c, u, a)),
                         "%.1f / %.1f" % (u["max_weight"], a["max_weight"]),
                         "%.0f / %.0f" % (u["ns_per_sample"], a["ns_per_sample"])))

        ri = fastest_of(command + ["--table", "isotropic"], args.repeats, estimators)
        ui, ai = ri["uniform"], ri["adaptive"]
        iso.append((name, resolution(ri["adaptive_avg_res"]), "%.1f : 1" % ri["compression"],
                    "%s (%.0f : 1)" % (thousands(ai["bytes"]), u["bytes"] / ai["bytes"]),
                    "%s / %s" % (g4(ui["variance"]), g4(ai["variance"])), "%.3f" % (ai["variance"] / ui["variance"])))
        print("paper_reproduction: %s done" % name, file=sys.stderr)
    return (table(["material", "paper: adaptive avg res", "paper: compression",
                   "paper: efficiency adaptive ÷ uniform", "ours: adaptive avg res", "ours: compression",
                   "ours: variance adaptive ÷ uniform", "ours: efficiency adaptive ÷ uniform (timed)"], ratios),
            table(["material", "uniform bytes", "adaptive bytes", "variance cosine / uniform / adaptive",
                   "max weight uniform / adaptive", "ns/sample uniform / adaptive"], absolute),
            table(["material", "adaptive avg res", "compression", "adaptive bytes (÷ uniform 4D)",
                   "variance uniform / adaptive", "adaptive ÷ uniform variance"], iso))


def envmap_table(args):
    if not os.path.isdir(args.envmaps):
        print("paper_reproduction: %s absent: environment-map rows not regenerated" % args.envmaps, file=sys.stderr)
        return None
    rows = []
    for file in ENVMAPS:
        r = fastest_of([args.acdf, "envmap-stats", os.path.join(args.envmaps, file), "--json"], args.repeats,
                       ("uniform", "adaptive"))
        u, a = r["uniform"], r["adaptive"]
        name = file.rsplit(".", 1)[0].replace("_", " ").replace("x", "×")
        rows.append((name, thousands(r["uniform_bytes"]), thousands(r["adaptive_bytes"]),
                     "%.1f : 1" % r["compression"], "%.3f" % r["chi2_divergence"],
                     "%.3f / %.3f (%.3f)" % (u["variance"], a["variance"], a["variance"] / u["variance"]),
                     "%.3f / %.3f" % (u["stratified_variance"], a["stratified_variance"]),
                     "%.2f" % (a["efficiency"] / u["efficiency"])))
    return table(["map", "uniform bytes", "adaptive bytes", "compression", "χ²-divergence",
                  "variance uniform / adaptive (ratio)", "stratified variance uniform / adaptive",
                  "efficiency adaptive ÷ uniform (timed)"], rows)


def status(args):
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    return ("Generated %s at commit `%s` by `bench/paper_reproduction.py --samples %d --repeats %d` (run by `make "
            "bench`) on %s, load average %.1f when it finished. Variances, bytes and resolutions are "
            "deterministic; times, and so the timed efficiencies, are the fastest of the repeats."
            % (datetime.date.today().isoformat(), commit, args.samples, args.repeats, machine(), os.getloadavg()[0]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--acdf", default="build/bin/acdf")
    parser.add_argument("--materials", default="build/demo")
    parser.add_argument("--envmaps", default=os.path.join("..", "shared", "data", "envmaps"))
    parser.add_argument("--samples", type=int, default=4096)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--update", metavar="PAGE")
    args = parser.parse_args()
    if args.repeats < 1 or args.samples < 1:
        sys.exit("paper_reproduction: --samples and --repeats must be positive")

    sections = dict(zip(("table1-4d", "table1-4d-absolute", "table1-iso"), brdf_tables(args)))
    envmaps = envmap_table(args)
    if envmaps is not None:
        sections["envmaps"] = envmaps
    sections["status"] = status(args)
    if not args.update:
        for marker, body in sections.items():
            print("## %s\n\n%s\n" % (marker, body))
        return
    replace_sections(args.update, sections)
    print("paper_reproduction: updated %s" % args.update, file=sys.stderr)


if __name__ == "__main__":
    main()

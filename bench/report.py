#!/usr/bin/env python3
"""Turns the JSON of the Google Benchmark programs (bench/results/bench_*.json) into markdown:
the analysed tables of bench_sampling_1d and bench_sampling_2d, and for every other program a
table of each benchmark's time and counters.

usage: bench/report.py [--update DOC.md] [--command TEXT] [results.json ...]
       (default: bench/results/bench_*.json; without --update the markdown goes to stdout;
       with it, the part of DOC.md between <!-- make-bench: begin --> and <!-- make-bench: end -->
       is rewritten, with the run's date, machine, load average and the command)

Times are wall-clock (real_time) unless a column says CPU; for repeated benchmarks the median
repetition is used. Ratios vs uniform come from the same JSON, i.e. the same run; the
"interleaved" ratios come from the h2h* benchmarks, which time all samplers alternately under the
same machine noise.
"""

import argparse
import glob
import json
import os
import sys

from doc_sections import fmt_bytes, machine, replace_sections, table

UNIT_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def load_file(path):
    """The benchmarks of one JSON file by name (median aggregate of repeated ones) and its context."""
    runs = {}
    with open(path) as f:
        data = json.load(f)
    for b in data["benchmarks"]:
        # Drop the "/min_time:0.100/repeats:3/iterations:100" parts Google Benchmark appends.
        name = "/".join(p for p in b.get("run_name", b["name"]).split("/") if ":" not in p)
        if b.get("run_type") == "aggregate":
            if b.get("aggregate_name") != "median":
                continue
        elif name in runs and runs[name].get("run_type") == "aggregate":
            continue
        elif b.get("repetitions", 1) > 1:
            continue  # a single repetition; the median aggregate is used instead
        runs[name] = b
    return runs, data.get("context")


def load(paths):
    runs, context = {}, None
    for path in paths:
        file_runs, file_context = load_file(path)
        runs.update(file_runs)
        context = context or file_context
    return runs, context


def ns(b):
    """Wall-clock time of one iteration, in ns (builds: TBB runs on every core)."""
    return b["real_time"] * UNIT_NS[b.get("time_unit", "ns")]


def cpu_ns(b):
    """CPU time of the benchmark thread per iteration, in ns (single-threaded queries: robust to
    the process being descheduled on a shared machine)."""
    return b["cpu_time"] * UNIT_NS[b.get("time_unit", "ns")]


def g(x, digits=3):
    return f"{x:.{digits}g}"


def interleaved_table(runs, prefix, sizes, size_header):
    """The head-to-head counters (bench_util.h reportSamplersVsUniform) of each size, as a table."""
    rows = []
    for size in sizes:
        h = runs.get(f"{prefix}/{size}")
        if not h:
            continue
        rows.append([size] + [f"{h[f'{w}_ns_{m}']:.1f}" for w in ("sample", "pdf")
                              for m in ("uniform", "alias", "adaptive")] +
                    [f"{h['sample_alias_vs_uniform']:.2f}", f"{h['sample_adaptive_vs_uniform']:.2f}",
                     f"{h['pdf_alias_vs_uniform']:.2f}", f"{h['pdf_adaptive_vs_uniform']:.2f}"])
    return table([size_header, "sample uni", "sample alias", "sample adapt", "pdf uni", "pdf alias",
                  "pdf adapt", "sample alias÷uni", "sample adapt÷uni", "pdf alias÷uni",
                  "pdf adapt÷uni"], rows)


def report_1d(runs):
    sizes = sorted({int(n.split("/")[2]) for n in runs if n.startswith("build1d/")})
    if not sizes:
        return ""
    out = ["### 1D (bench_sampling_1d)", ""]
    rows = []
    for n in sizes:
        uni = runs.get(f"build1d/uniform/{n}")
        for m in ("uniform", "alias", "adaptive"):
            b, s, p = (runs.get(f"{w}1d/{m}/{n}") for w in ("build", "sample", "pdf"))
            if not (b and s and p):
                continue
            extra = ""
            if m == "adaptive":
                extra = f"{b['points']:.0f} pts, χ² {g(b['chi2'])}, max w {g(b['max_weight_ratio'])}"
            rows.append([n, m, f"{ns(b) / 1e3:.1f}", f"{ns(b) / ns(uni):.2f}" if uni else "",
                         f"{cpu_ns(s):.1f}", f"{cpu_ns(p):.1f}", fmt_bytes(b["bytes"]),
                         f"{b['bytes_vs_uniform']:.3g}", extra])
    out.append(table(["cells", "method", "build µs", "build ÷ uniform", "sample ns/op", "pdf ns/op",
                      "bytes", "bytes ÷ uniform", "adaptive: points, quality"], rows))
    out += ["", "Interleaved (h2h1d): median ns/op when the three run alternately in 4096-op chunks.", ""]
    out.append(interleaved_table(runs, "h2h1d", sizes, "cells"))
    return "\n".join(out) + "\n"


def report_2d(runs):
    sizes = []
    for n in runs:
        if n.startswith("build2d/") and n.split("/")[2] not in sizes:
            sizes.append(n.split("/")[2])
    sizes.sort(key=lambda s: int(s.split("x")[0]))
    if not sizes:
        return ""
    out = ["### 2D (bench_sampling_2d)", ""]
    rows = []
    for size in sizes:
        uni = runs.get(f"build2d/uniform/{size}")
        for m in ("uniform", "alias", "adaptive"):
            b, s, p = (runs.get(f"{w}2d/{m}/{size}") for w in ("build", "sample", "pdf"))
            if not (b and s and p):
                continue
            rows.append([size, m, f"{ns(b) / 1e6:.1f}", f"{b['process_cpu_ms']:.1f}",
                         f"{ns(b) / ns(uni):.2f}" if uni else "", fmt_bytes(b["peak_build_bytes"]), f"{cpu_ns(s):.1f}", f"{cpu_ns(p):.1f}",
                         fmt_bytes(b["bytes"]), f"{b['bytes_vs_uniform']:.3g}", g(b["chi2"]),
                         g(b["max_weight_ratio"])])
    out.append(table(["grid", "method", "build ms (wall)", "build CPU ms (all threads)",
                      "build ÷ uniform (wall)", "peak build RSS",
                      "sample ns/op", "pdf ns/op", "bytes", "bytes ÷ uniform", "χ² div",
                      "max p/q"], rows))
    out += ["", "Interleaved (h2h2d): median ns/op when the three run alternately in 8192-op chunks.", ""]
    out.append(interleaved_table(runs, "h2h2d", sizes, "grid"))
    opts = next((runs[n] for n in runs if n.startswith("simplify2d/")), None)
    params = f"ε = {opts['epsilon']:g}, weight bound ρ = {opts['weight_bound']:g}, " if opts else ""
    out += ["", f"Adaptive build per simplifier ({params}exact-mass conditionals):", ""]
    rows = []
    for size in sizes:
        for sim in ("dp-vertical", "dp-perpendicular", "greedy-vertical", "greedy-perpendicular",
                    "greedy-vertical-budget8"):
            b = runs.get(f"simplify2d/{sim}/{size}")
            if not b:
                continue
            rows.append([size, sim, f"{ns(b) / 1e6:.1f}", f"{b['process_cpu_ms']:.1f}",
                         fmt_bytes(b["peak_build_bytes"]),
                         fmt_bytes(b["bytes"]), f"{b['bytes_vs_uniform']:.3g}",
                         f"{b['avg_intervals_theta']:.0f}", f"{b['avg_intervals_phi']:.1f}",
                         g(b["chi2"]), g(b["max_weight_ratio"])])
    out.append(table(["grid", "simplifier", "build ms (wall)", "build CPU ms", "peak build RSS", "bytes", "bytes ÷ uniform",
                      "intervals θ", "avg intervals φ", "χ² div", "max p/q"], rows))
    rows = []
    for name in sorted(n for n in runs if n.startswith("build2d-rough/")):
        b = runs[name]
        _, method, size = name.split("/")
        rows.append([size, method, f"{ns(b) / 1e6:.1f}", f"{b['process_cpu_ms']:.1f}",
                     fmt_bytes(b["peak_build_bytes"]), fmt_bytes(b["bytes"]),
                     f"{b['bytes_vs_uniform']:.3g}", f"{b['avg_intervals_theta']:.0f}",
                     f"{b['avg_intervals_phi']:.0f}", g(b["chi2"]), g(b["max_weight_ratio"]),
                     g(b["unreachable_mass"])])
    if rows:
        out += ["", "Worst case for the simplifier: the rough (heavy-tailed noise) map:", ""]
        out.append(table(["grid", "method", "build ms (wall)", "build CPU ms (all threads)", "peak build RSS",
                          "bytes", "bytes ÷ uniform", "intervals θ", "avg intervals φ", "χ² div",
                          "max p/q", "unreachable mass"], rows))
    return "\n".join(out) + "\n"


# Fields of Google Benchmark's JSON that are not user counters.
STANDARD_FIELDS = {"name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
                   "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit",
                   "aggregate_name", "aggregate_unit", "label", "error_occurred", "error_message"}


def report_generic(program, runs):
    """Any program's benchmarks: wall and CPU time per iteration and its counters."""
    rows = []
    for name, b in runs.items():
        counters = ", ".join(f"{k} {g(v, 4)}" for k, v in b.items()
                             if k not in STANDARD_FIELDS and isinstance(v, (int, float)))
        rows.append([f"`{name}`", fmt_time(ns(b)), fmt_time(cpu_ns(b)), counters])
    return "\n".join([f"### {program}", "",
                       table(["benchmark", "wall time", "CPU time (benchmark thread)", "counters"], rows), ""])


def fmt_time(nanoseconds):
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if nanoseconds >= scale:
            return f"{nanoseconds / scale:.4g} {unit}"
    return f"{nanoseconds:.4g} ns"


def report(paths):
    """Markdown for every result file: the analysed 1D/2D tables, then one table per program."""
    out = []
    sampling = [p for p in paths if os.path.basename(p).startswith("bench_sampling_")]
    if sampling:
        runs, _ = load(sampling)
        out += [report_1d(runs), report_2d(runs)]
    for path in paths:
        if path in sampling:
            continue
        runs, _ = load_file(path)
        out.append(report_generic(os.path.basename(path)[:-len(".json")], runs))
    return "\n".join(part for part in out if part)


def run_line(paths, command):
    _, context = load_file(paths[0])
    context = context or {}
    load_avg = " / ".join(f"{x:.2f}" for x in context.get("load_avg", []))
    return (f"Run {context.get('date', '?')} on {machine()}; load average {load_avg or '?'} (1 / 5 / 15 min) when "
            f"`{os.path.basename(paths[0])}` started. Command: `{command}`.")


def main():
    parser = argparse.ArgumentParser(description="markdown tables from Google Benchmark JSON")
    parser.add_argument("results", nargs="*")
    parser.add_argument("--update", metavar="DOC")
    parser.add_argument("--command", default="make bench")
    args = parser.parse_args()
    paths = args.results or sorted(glob.glob(os.path.join(os.path.dirname(__file__), "results", "bench_*.json")))
    if not paths:
        sys.exit("report.py: no JSON results given or found in bench/results/")
    body = "\n".join([run_line(paths, args.command), "", report(paths)])
    if args.update:
        replace_sections(args.update, {"make-bench": "\n_Generated by `bench/report.py`; do not edit by hand._\n\n" + body})
    else:
        print(body)


if __name__ == "__main__":
    main()

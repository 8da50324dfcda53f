#!/usr/bin/python3
"""Batched Python sampling against the C++ benchmark, in the same run.

The map is the 4096 x 2048 "noon" sun and sky of bench_envmap (written by `acdf env-gen` with the
same generator, so both sides build the same adaptive table). The C++ figure is bench_envmap's
h2h/sunsky4096x2048 `sample_ns_adaptive` (median ns per EnvironmentLight::sample in a loop on one
thread). The Python figures are medians over rounds of EnvironmentLight.sample on
  - chunks of 4096 rows: below the module's parallel threshold, so one thread like the C++ loop,
    with the call's own overhead (conversion, output arrays) included;
  - one batch of 2^20 rows: oneTBB's threads, without the GIL (all cores).
The ratios are samples per second of Python over C++ (1.0: as fast as the C++ loop).

    bench/bench_python.py --build build [--json bench/results/python.json]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def cpp_sample_ns(bench):
    out = subprocess.run([bench, "--benchmark_filter=^h2h/sunsky4096x2048/", "--benchmark_format=json"],
                         check=True, capture_output=True, text=True).stdout
    (run,) = json.loads(out)["benchmarks"]
    return run["sample_ns_adaptive"]


def python_sample_ns(acdf, path, np):
    light = acdf.EnvironmentLight.load(path, strategy="adaptive")
    rng = np.random.default_rng(7)
    n, chunk = 1 << 20, 4096
    u = rng.random((n, 2), dtype=np.float32)
    light.sample(u[:chunk])  # warm-up
    chunked, batch = [], []
    for _ in range(5):
        t0 = time.perf_counter()
        for i in range(0, n, chunk):
            light.sample(u[i:i + chunk])
        chunked.append((time.perf_counter() - t0) * 1e9 / n)
        t0 = time.perf_counter()
        light.sample(u)
        batch.append((time.perf_counter() - t0) * 1e9 / n)
    return statistics.median(chunked), statistics.median(batch), light.bytes


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build", help="the build directory (bin/acdf, bin/bench_envmap, python/)")
    parser.add_argument("--json", help="write the figures here")
    args = parser.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import numpy as np

    import acdf

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "noon_4096x2048.exr")
        subprocess.run([os.path.join(args.build, "bin", "acdf"), "env-gen", "--preset", "noon", "--width", "4096",
                        "--height", "2048", "-o", path], check=True, capture_output=True)
        cpp = cpp_sample_ns(os.path.join(args.build, "bin", "bench_envmap"))
        chunked, batch, table_bytes = python_sample_ns(acdf, path, np)
    result = {
        "map": "env-gen --preset noon, 4096x2048",
        "table_bytes": table_bytes,
        "cpp_sample_ns": cpp,
        "python_chunk4096_sample_ns": chunked,
        "python_batch_sample_ns": batch,
        "python_chunk4096_vs_cpp": cpp / chunked,
        "python_batch_vs_cpp": cpp / batch,
        "cores": os.cpu_count(),
    }
    print(f"adaptive EnvironmentLight.sample, 4096x2048 noon ({table_bytes} bytes of tables):")
    print(f"  C++ loop (bench_envmap h2h)     {cpp:8.1f} ns/sample")
    print(f"  Python, chunks of 4096 rows     {chunked:8.1f} ns/sample  ({cpp / chunked:.2f}x the C++ rate)")
    print(f"  Python, one batch of 2^20 rows  {batch:8.1f} ns/sample  ({cpp / batch:.2f}x, {os.cpu_count()} cores)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()

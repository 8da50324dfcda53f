#!/usr/bin/python3
"""The BRDF compression frontier: bytes against variance, by quadrature, as epsilon varies.

For each material (the paper's nickel, blue-metallic-paint and plastic, i.e. specular-blue-phenolic,
tabulated from the bundled neural fits by `acdf merl-gen --nbrdf`; real MERL data is not bundled),
runs `acdf brdf-stats --quadrature --json` for the 4D and the isotropic layout at each epsilon and
prints every adaptive table's compression and variance against the uniform 4D table's (the paper's
table; its quadrature variance does not depend on epsilon), then the frontier: the largest
compression whose variance is at most --bound times the uniform 4D table's. Variances come from the
quadrature (deterministic; ratios between tables precise to 0.3%), not from sampling.

    bench/brdf_frontier.py --build build [--bound 1.05] [--epsilons 2.5e-5,5e-5,...] [--json OUT]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

MATERIALS = ["nickel", "blue-metallic-paint", "specular-blue-phenolic"]
EPSILONS = [2.5e-5, 5e-5, 1e-4, 2e-4, 4e-4, 8e-4, 1.6e-3]


def stats(acdf, path, layout, epsilon):
    out = subprocess.run([acdf, "brdf-stats", path, "--table", layout, "--chi2-epsilon", repr(epsilon), "--samples", "1",
                          "--quadrature", "--json"], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def frontier(acdf, path, epsilons):
    """Rows (layout, epsilon, bytes, compression vs uniform 4D, variance vs uniform 4D)."""
    rows, reference = [], None
    for layout in ["4d", "isotropic"]:
        for epsilon in epsilons:
            j = stats(acdf, path, layout, epsilon)
            if reference is None:  # the first run is a 4D one: its uniform table is the reference
                reference = (j["uniform_bytes"], j["uniform"]["quadrature"]["variance"])
            a = j["adaptive"]
            rows.append({"layout": layout, "epsilon": epsilon, "bytes": a["bytes"],
                         "compression": reference[0] / a["bytes"],
                         "variance_vs_uniform_4d": a["quadrature"]["variance"] / reference[1]})
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build", help="CMake build directory holding bin/acdf")
    parser.add_argument("--bound", type=float, default=1.05, help="variance bound, times the uniform 4D table's")
    parser.add_argument("--epsilons", default=",".join(map(repr, EPSILONS)), help="comma-separated epsilons")
    parser.add_argument("--materials", default=",".join(MATERIALS), help="comma-separated neural-fit materials")
    parser.add_argument("--json", help="also write every row to this file")
    args = parser.parse_args()
    acdf = os.path.join(args.build, "bin", "acdf")
    epsilons = [float(e) for e in args.epsilons.split(",")]

    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for material in args.materials.split(","):
            path = os.path.join(tmp, material + ".binary")
            subprocess.run([acdf, "merl-gen", "--nbrdf", material, "-o", path], check=True, capture_output=True)
            rows = frontier(acdf, path, epsilons)
            results[material] = rows
            print(f"{material}")
            print(f"  {'layout':10} {'epsilon':>9} {'bytes':>10} {'compression':>12} {'var / unif 4d':>14}")
            for r in rows:
                print(f"  {r['layout']:10} {r['epsilon']:9.3g} {r['bytes']:10d} {r['compression']:12.1f} "
                      f"{r['variance_vs_uniform_4d']:14.4f}")
            for layout in ["4d", "isotropic"]:
                within = [r for r in rows if r["layout"] == layout and r["variance_vs_uniform_4d"] <= args.bound]
                if within:
                    best = max(within, key=lambda r: r["compression"])
                    print(f"  frontier {layout}: {best['compression']:.1f} : 1 at {best['variance_vs_uniform_4d']:.4f}x "
                          f"(epsilon {best['epsilon']:.3g})")
                else:
                    print(f"  frontier {layout}: no epsilon within {args.bound}x")
            sys.stdout.flush()
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"bound": args.bound, "materials": results}, f, indent=2)


if __name__ == "__main__":
    main()

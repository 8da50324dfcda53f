"""examples/python runs as documented (on the reference run's generated sky)."""
import os
import re
import subprocess
import sys

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def run(script, *args):
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args], check=True,
                          capture_output=True, text=True).stdout


def test_quickstart_estimates_agree(reference):
    out = run("quickstart.py", reference.path("sky.exr"), "100000")
    estimates = [tuple(map(float, m)) for m in re.findall(r"([-+.eE0-9]+) \+- ([-+.eE0-9]+)", out)]
    (a, ea), (b, eb) = estimates
    assert a > 0 and (a - b) ** 2 <= 25 * (ea**2 + eb**2), out


def test_figures_are_written(reference, tmp_path):
    out = run("figures.py", reference.path("sky.exr"), str(tmp_path))
    for name in ["cdf_breakpoints.png", "envmap_intervals.png"]:
        with open(tmp_path / name, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n", name
    assert "points kept" in out and "boxes" in out

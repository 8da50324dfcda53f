#!/usr/bin/python3
"""Plots and markdown for the results of `acdf bench-error` (results.json).

usage: bench/error_report.py plot RESULTS.json OUT_DIR
         error_vs_time.png (log-log relMSE against render time, one curve per strategy
         combination with standard-error bars over the seeds, a panel per MIS mode and sample
         source; colour = BRDF strategy, line style and marker = environment strategy; in each
         panel the best curve at the largest budget and the adaptive and uniform tables' pair are
         drawn bold and named, the rest faint) and memory_vs_error.png (table memory against the
         relMSE of the largest budget, a panel per sample source), into OUT_DIR.
       bench/error_report.py docs RESULTS.json DOC.md IMAGE_DIR [--command TEXT]
         copies the plots and the adaptive-vs-uniform difference images next to RESULTS.json into
         IMAGE_DIR and rewrites the part of DOC.md between <!-- bench-error: begin --> and
         <!-- bench-error: end --> (appended when absent): the machine, the command, the settings,
         the table of every combination at the largest budget with its time to the target relMSE,
         and whether the run resolves a 10% difference. Idempotent.

Needs Debian's python3-matplotlib (scripts/install-deps) for `plot`; run it with /usr/bin/python3,
since a pyenv python may shadow it without matplotlib.
"""

import json
import os
import shutil
import sys

from doc_sections import fmt_bytes, machine, replace_sections, table

MIS_ORDER = ["power", "balance", "light-only", "bsdf-only", "product"]
ENV_ORDER = ["uniform-sphere", "uniform", "alias", "adaptive", "compensated", "hierarchical", "local"]
BSDF_COLOR = {"cosine": "tab:gray", "uniform": "tab:blue", "adaptive": "tab:red"}
# Line style and marker of each environment strategy: one curve told apart by two cues.
ENV_STYLE = {"uniform-sphere": (":", "x"), "uniform": ("--", "s"), "alias": ((0, (1, 1, 4, 1)), "v"),
             "adaptive": ("-", "o"), "compensated": ("-.", "^"), "hierarchical": ((0, (6, 2)), "D"),
             "local": ((0, (3, 1, 1, 1, 1, 1)), "P")}


def load(path):
    with open(path) as f:
        data = json.load(f)
    if not isinstance(data.get("rows"), list) or "settings" not in data:
        raise ValueError(f"{path}: not the results.json of acdf bench-error")
    return data


def lighting(row):
    """The MIS mode, or "product" for product direct lighting (which uses none)."""
    return "product" if row.get("direct", "mis") == "product" else row["mis"]


def strategy(row):
    return (row["bsdf_sampling"], row["env_sampling"], lighting(row), row["sampler"])


def by_strategy(rows):
    curves = {}
    for r in rows:
        curves.setdefault(strategy(r), []).append(r)
    for points in curves.values():
        points.sort(key=lambda r: r["budget"])
    return curves


def sort_key(s):
    bsdf, env, mis, sampler = s
    return (sampler, MIS_ORDER.index(mis) if mis in MIS_ORDER else 9, ENV_ORDER.index(env) if env in ENV_ORDER else 9,
            bsdf)


SAMPLERS = ("independent", "sobol")
# The paper's Table 2 pair of difference images, per sample source (bench-error's diff/ names).
PAPER_DIFFERENCES = tuple(f"{axis}-adaptive-vs-uniform_adaptive_power_{sampler}.png"
                          for sampler in SAMPLERS for axis in ("env", "bsdf"))
# The paper's comparison: adaptive tables on both axes against uniform tables on both.
PAPER_PAIR = (("adaptive", "adaptive"), ("uniform", "uniform"))


def highlighted(curves, panel):
    """The curves of a panel worth reading first: the lowest relMSE at the largest budget, and
    the adaptive and uniform tables' pair when the panel has them."""
    best = min(panel, key=lambda s: curves[s][-1]["relmse"])
    return {best} | {s for s in panel if (s[0], s[1]) in PAPER_PAIR}


def name_curve_ends(fig, ax, names, gap=9):
    """Writes each (x, y, text, colour) beside its point, moving a name up until it is `gap`
    points clear of the one below, so curves that end together stay readable."""
    fig.canvas.draw()  # fixes the axes' limits, so data converts to display points
    scale = fig.dpi / 72
    previous = None
    for x, y, text, color in sorted(names, key=lambda n: ax.transData.transform((n[0], n[1]))[1]):
        at = ax.transData.transform((x, y))[1] / scale
        shown = at if previous is None else max(at, previous + gap)
        ax.annotate(text, (x, y), xytext=(4, shown - at), textcoords="offset points", fontsize=7, va="center",
                    color=color, zorder=4)
        previous = shown


def plot(results, out_dir):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        sys.exit(f"error_report.py: matplotlib is missing ({e}); install python3-matplotlib "
                 "(scripts/install-deps) and run with /usr/bin/python3")
    data = load(results)
    rows = data["rows"]
    if not rows:
        sys.exit(f"error_report.py: {results} has no rows to plot")
    curves = by_strategy(rows)
    kind = data["settings"].get("budget_kind", "seconds")
    from matplotlib.lines import Line2D
    mises = sorted({s[2] for s in curves}, key=lambda m: MIS_ORDER.index(m) if m in MIS_ORDER else 9)
    samplers = sorted({s[3] for s in curves})
    seeds = data["settings"].get("seeds", 1)

    fig, axes = plt.subplots(len(samplers), len(mises), figsize=(5.2 * len(mises), 4.4 * len(samplers) + 0.5),
                             squeeze=False, sharey=True)
    for row, sampler in enumerate(samplers):
        for ax, mis in zip(axes[row], mises):
            panel = [s for s in curves if s[2] == mis and s[3] == sampler]
            if not panel:
                ax.set_visible(False)
                continue
            bold = highlighted(curves, panel)
            names = []
            for s in sorted(panel, key=sort_key):
                points = curves[s]
                xs = [p["seconds"] if kind == "seconds" else p["spp"] for p in points]
                ys = [p["relmse"] for p in points]
                # Bars of ± one standard error, the lower one kept above 0 for the log axis.
                se = [p.get("relmse_stderr", 0) for p in points]
                style, marker = ENV_STYLE.get(s[1], ("-", "o"))
                key = s in bold
                ax.errorbar(xs, ys, yerr=[[min(e, 0.95 * y) for e, y in zip(se, ys)], se], linestyle=style,
                            marker=marker, markersize=4.5 if key else 3, linewidth=2.2 if key else 0.8, capsize=2,
                            elinewidth=1.0 if key else 0.5, alpha=1.0 if key else 0.3, zorder=3 if key else 2,
                            color=BSDF_COLOR.get(s[0], "black"), markerfacecolor="none")
                if key:
                    names.append((xs[-1], ys[-1], f"{s[0]} × {s[1]}", BSDF_COLOR.get(s[0], "black")))
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.margins(x=0.25)  # room for the names at the curves' ends
            name_curve_ends(fig, ax, names)
            ax.set_title(f"MIS: {mis}, {sampler} samples" if len(samplers) > 1 else f"MIS: {mis}")
            ax.set_xlabel("render time (s)" if kind == "seconds" else "samples per pixel")
            ax.grid(True, which="both", alpha=0.3)
    shown = {s[0] for s in curves}, {s[1] for s in curves}
    bsdf_keys = [Line2D([], [], color=BSDF_COLOR[b], linewidth=2, label=b) for b in BSDF_COLOR if b in shown[0]]
    env_keys = [Line2D([], [], color="black", linestyle=ENV_STYLE[e][0], marker=ENV_STYLE[e][1], markersize=4,
                       markerfacecolor="none", label=e) for e in ENV_ORDER if e in shown[1]]
    first = axes[0][0]
    first.add_artist(first.legend(handles=bsdf_keys, title="BRDF sampling (colour)", fontsize=7, title_fontsize=7,
                                  loc="lower left"))
    axes[0][-1].legend(handles=env_keys, title="environment (line, marker)", fontsize=7, title_fontsize=7,
                       loc="upper right")
    for row in axes:
        row[0].set_ylabel(f"relMSE against the reference (mean ± s.e., {seeds} seed{'s' if seeds != 1 else ''})")
    fig.suptitle(f"{data['settings']['scene']}: error against {'time' if kind == 'seconds' else 'samples'}; bold "
                 "and named: each panel's best at the largest budget and the adaptive/uniform table pair\n"
                 f"{machine()}", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "error_vs_time.png"), dpi=90)
    plt.close(fig)

    # Colour = BRDF strategy and marker = environment strategy as in error_vs_time; fill = MIS; a
    # panel per sample source. Keyed by three small legends, not one entry per point.
    fills = {"power": "full", "balance": "bottom", "light-only": "left", "bsdf-only": "none", "product": "right"}
    samplers = sorted({s[3] for s in curves})
    fig, axes = plt.subplots(1, len(samplers), figsize=(5.6 * len(samplers), 4.8), squeeze=False, sharey=True)
    for ax, sampler in zip(axes[0], samplers):
        for s in sorted((s for s in curves if s[3] == sampler), key=sort_key):
            last = curves[s][-1]
            se = last.get("relmse_stderr", 0)
            ax.errorbar([max(last["table_bytes"], 1) / 2**20], [last["relmse"]],
                        yerr=[[min(se, 0.95 * last["relmse"])], [se]], color=BSDF_COLOR.get(s[0], "black"),
                        marker=ENV_STYLE.get(s[1], ("-", "o"))[1], linestyle="none", capsize=2,
                        fillstyle=fills.get(s[2], "full"))
        ax.set_xscale("symlog", linthresh=0.01)
        ax.set_yscale("log")
        ax.set_title(f"{sampler} samples", fontsize=9)
        ax.set_xlabel("table memory, BRDF + environment (MiB; 0 = no table)")
        ax.grid(True, which="both", alpha=0.3)
    shown = [{s[i] for s in curves} for i in range(3)]
    first = axes[0][0]
    first.set_ylabel(f"relMSE at the largest budget ({curves[next(iter(curves))][-1]['budget']:g} {kind})")
    keys = (([Line2D([], [], color=BSDF_COLOR[b], marker="o", linestyle="none", label=b)
              for b in BSDF_COLOR if b in shown[0]], "BRDF (colour)", 0.0),
            ([Line2D([], [], color="black", marker=ENV_STYLE[e][1], linestyle="none", fillstyle="none", label=e)
              for e in ENV_ORDER if e in shown[1]], "environment (marker)", 0.17),
            ([Line2D([], [], color="black", marker="o", linestyle="none", fillstyle=fills.get(m, "full"), label=m)
              for m in MIS_ORDER if m in shown[2]], "MIS or product (fill)", 0.38))
    # Side by side along the bottom of the first panel, below the table-less strategies' points.
    for handles, title, left in keys:
        first.add_artist(first.legend(handles=handles, title=title, fontsize=6, title_fontsize=6, loc="lower left",
                                      bbox_to_anchor=(left, 0.0)))
    fig.suptitle(f"{data['settings']['scene']}: table memory against error (bars ± one standard error)\n"
                 f"{machine()}", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "memory_vs_error.png"), dpi=90)
    plt.close(fig)


# The changes whose size a reader wants to trust: one axis changed, the rest fixed, power MIS.
CHANGES = tuple((f"{name} ({sampler})", ("adaptive", "adaptive", "power", sampler), (*b, "power", sampler))
                for sampler in SAMPLERS
                for name, b in (("BRDF table adaptive → uniform", ("uniform", "adaptive")),
                                ("env table adaptive → uniform", ("adaptive", "uniform")),
                                ("env table adaptive → compensated", ("adaptive", "compensated")),
                                ("env table adaptive → local", ("adaptive", "local")))) + \
          (("samples independent → Sobol", ("adaptive", "adaptive", "power", "independent"),
            ("adaptive", "adaptive", "power", "sobol")),)


def relative_change(a, b, key):
    """(b − a) / a of a row's mean `key` and its standard error: the rows' seeds are independent,
    so the ratio's relative errors add in quadrature."""
    ra, rb = a[key], b[key]
    ea, eb = a.get(key + "_stderr", 0) / ra, b.get(key + "_stderr", 0) / rb
    return rb / ra - 1, rb / ra * (ea * ea + eb * eb) ** 0.5


def resolution(data, kind):
    """Whether the run tells a 10% difference from noise: each change of CHANGES at each budget,
    relMSE and trimmed relMSE, as a relative change ± its standard error; 10% is resolved where
    that error is at most 5% (two standard errors)."""
    rows = {(strategy(r), r["budget"]): r for r in data["rows"]}
    budgets = sorted({r["budget"] for r in data["rows"]})
    lines = []
    for budget in budgets:
        for name, a, b in CHANGES:
            if (a, budget) not in rows or (b, budget) not in rows:
                continue
            cells = [f"{budget:g} {'s' if kind == 'seconds' else 'spp'}", name]
            resolved = []
            for key in ("relmse", "relmse_trimmed"):
                change, error = relative_change(rows[(a, budget)], rows[(b, budget)], key)
                cells.append(f"{100 * change:+.1f} % ± {100 * error:.1f} %")
                resolved.append("yes" if error <= 0.05 else "no")
            lines.append(cells + resolved)
    if not lines:
        return []
    seeds = data["settings"].get("seeds", 1)
    return ["", f"Does the run resolve 10 %? Each change below is (b − a) / a of the mean over {seeds} seeds, ± its "
            "standard error (the two rows' relative errors in quadrature); 10 % is resolved where that error is at "
            "most 5 %, two standard errors:", "",
            table(["budget", "change (power MIS)", "relMSE", "trimmed relMSE", "10 % resolved (relMSE)",
                   "10 % resolved (trimmed)"], lines)]


def markdown(data, results, image_dir, doc_dir, command):
    settings = data["settings"]
    kind = settings.get("budget_kind", "seconds")
    curves = by_strategy(data["rows"])
    budgets = sorted({r["budget"] for r in data["rows"]})
    ref = settings.get("reference", {})
    rel = lambda p: os.path.relpath(p, doc_dir)
    out = ["",
           "_Generated by `bench/error_report.py docs` from "
           f"`{os.path.relpath(results)}`; do not edit by hand._", "",
           f"- Machine: {machine()}.",
           f"- Command: `{command}`." if command else "- Command: not recorded.",
           f"- Scene `{settings['scene']}`; reference "
           + (f"`{ref['file']}`" if "file" in ref else f"{ref.get('spp', '?')} spp with the scene's own strategies "
              f"({ref.get('env_sampling', '?')} environment, {ref.get('mis', '?')} MIS)")
           + f", {ref.get('width', '?')}×{ref.get('height', '?')}.",
           f"- Budgets: {', '.join(f'{b:g}' for b in budgets)} ({kind}); {len(curves)} strategy combinations, "
           f"{len(data['rows'])} rows; {len(data.get('skipped', []))} combinations left out as identical by "
           "construction (listed in results.json).",
           f"- relMSE = {settings.get('relmse')}; RMSE = {settings.get('rmse')}.", ""]
    for name, title in (("error_vs_time.png", "Error against time"), ("memory_vs_error.png", "Table memory against error")):
        if os.path.exists(os.path.join(image_dir, name)):
            out += [f"![{title}]({rel(os.path.join(image_dir, name))})", ""]
    seeds = settings.get("seeds", 1)
    target = data.get("target_relmse")
    to_target = {strategy(c): c for c in data.get("curves", [])}
    out += [f"At the largest budget ({budgets[-1]:g} {kind}), best first; mean ± standard error over {seeds} "
            "seed(s); relMSE trimmed = relMSE without the 0.1% of pixels of largest error (firefly-robust); "
            "efficiency = 1 / (relMSE × time), its error by the delta method; time to "
            + (f"relMSE {target:.3g} ({data.get('target_relmse_rule', '')}): " if target else "the target: ")
            + "interpolated log-log between the budgets around it, or, marked *, extrapolated by relMSE ∝ 1/time "
            "from the nearest budget:", ""]
    header = ["BRDF", "environment", "MIS or product", "samples", "time (s)", "spp", "relMSE", "relMSE trimmed", "RMSE",
              "efficiency", "time to target (s)", "table memory", "table set-up (ms)"]

    def time_to_target(s):
        c = to_target.get(s)
        if not c or c.get("time_to_target") is None:
            return "n/a"
        mark = "*" if c.get("time_to_target_extrapolated") else ""
        return f"{c['time_to_target']:.3g} ± {c.get('time_to_target_stderr') or 0:.2g}{mark}"

    table_rows = []
    for s, points in curves.items():
        p = points[-1]
        eff = p.get("efficiency")
        if eff is None:
            eff = 1.0 / (p["relmse"] * p["seconds"]) if p["relmse"] > 0 and p["seconds"] > 0 else float("inf")
        pm = lambda key, value: f"{value:.3g} ± {p.get(key, 0):.2g}"
        table_rows.append((p["relmse"], [s[0], s[1], s[2], s[3], f"{p['seconds']:.2f}", p["spp"],
                                         pm("relmse_stderr", p["relmse"]),
                                         pm("relmse_trimmed_stderr", p.get("relmse_trimmed", p["relmse"])),
                                         f"{p['rmse']:.3g}", pm("efficiency_stderr", eff), time_to_target(s),
                                         fmt_bytes(p["table_bytes"]), f"{p['table_ms']:.0f}"]))
    table_rows.sort(key=lambda t: t[0])
    out.append(table(header, [r for _, r in table_rows]))
    out += resolution(data, kind)
    diffs = sorted(f for f in os.listdir(image_dir) if f in PAPER_DIFFERENCES)
    if diffs:
        out += ["", "Difference images at the largest budget, power MIS (red where the adaptive table's render "
                "differs from the uniform table's on one axis, the other axis adaptive, relative to the reference; "
                "full red at 50 %; all pairs are in the output directory's diff/):", ""]
        out += [f"![{d[:-4]}]({rel(os.path.join(image_dir, d))})" for d in diffs]
    out.append("")
    return "\n".join(out)


def docs(results, doc, image_dir, command):
    data = load(results)
    if not data["rows"]:
        sys.exit(f"error_report.py: {results} has no rows")
    src = os.path.dirname(os.path.abspath(results))
    os.makedirs(image_dir, exist_ok=True)
    for name in ("error_vs_time.png", "memory_vs_error.png"):
        if os.path.exists(os.path.join(src, name)):
            shutil.copyfile(os.path.join(src, name), os.path.join(image_dir, name))
    # The paper's Table 2 pair under power MIS: the adaptive table against the uniform one on one
    # axis, the other axis adaptive (two PNGs, to keep the docs small; DIR/diff has all).
    diff_dir = os.path.join(src, "diff")
    for name in PAPER_DIFFERENCES:
        if os.path.exists(os.path.join(diff_dir, name)):
            shutil.copyfile(os.path.join(diff_dir, name), os.path.join(image_dir, name))
    section = markdown(data, results, image_dir, os.path.dirname(os.path.abspath(doc)), command)
    replace_sections(doc, {"bench-error": section},
                     heading_if_absent={"bench-error": "## Error against time (`acdf bench-error`)"})


def main(argv):
    if len(argv) == 4 and argv[1] == "plot":
        plot(argv[2], argv[3])
    elif len(argv) in (5, 7) and argv[1] == "docs" and (len(argv) == 5 or argv[5] == "--command"):
        docs(argv[2], argv[3], argv[4], argv[6] if len(argv) == 7 else "")
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv)

#!/usr/bin/python3
"""How far crystal curves lie from a reference run's (issue 30's accuracy bounds):

    /usr/bin/python3 bench/curve_compare.py REFERENCE_DIR RUN_DIR [RUN_DIR ...] [--windows 0.05,0.25,0.5,1,1.5,2]

Each DIR is a `granulab run ... --out DIR` of crystal_compression. Printed per run, against the reference: its
steps, time per step and wall time (summary.json), the first yield (relative), the strain-weighted mean deviator over
each strain window (in %, relative; rate_bias.window_mean), top against bottom (the largest difference between a
window's mean top and mean bottom platen stress, over their mean), and the largest of the relative differences.
The bounds: every window, the first yield and top against bottom within 2 %.

Standard library only.
"""
import argparse
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rate_bias import window_mean  # noqa: E402


def load(folder):
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(folder, "curve.csv")) as f:
        rows = list(csv.DictReader(f))
    columns = {k: [float(r[k]) for r in rows] for k in ("strain", "deviator", "stress_top", "stress_bottom")}
    return summary, columns


def top_bottom(c, windows):
    """The largest |mean top - mean bottom| / mean of both over the windows (-)."""
    worst = 0.0
    for lo, hi in windows:
        top = window_mean(c["strain"], c["stress_top"], lo, hi)
        bottom = window_mean(c["strain"], c["stress_bottom"], lo, hi)
        if top is None or bottom is None:
            continue
        worst = max(worst, abs(top - bottom) / (0.5 * (top + bottom)))
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("reference")
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--windows", default="0.05,0.25,0.5,1,1.5,2", help="window edges in % strain")
    args = parser.parse_args()
    edges = [float(e) / 100 for e in args.windows.split(",")]
    windows = list(zip(edges[:-1], edges[1:]))
    ref_summary, ref = load(args.reference)
    ref_windows = [window_mean(ref["strain"], ref["deviator"], lo, hi) for lo, hi in windows]
    ref_yield = ref_summary["first_yield"].get("deviator", float("nan"))
    head = ["run", "steps", "ms / step", "wall (s)", "first yield"] + [
        "%g-%g %%" % (100 * lo, 100 * hi) for lo, hi in windows] + ["top - bottom", "largest"]
    print("| " + " | ".join(head) + " |")
    print("|" + " --- |" * len(head))
    for folder in [args.reference] + args.runs:
        s, c = load(folder)
        per_step = s.get("seconds_per_step")
        cells = [os.path.basename(os.path.normpath(folder)), "%d" % s["steps"],
                 "%.2f" % (1e3 * per_step) if per_step else "-", "%.0f" % (per_step * s["steps"]) if per_step else "-"]
        tb = top_bottom(c, windows)
        if folder == args.reference:
            cells += ["%.3f p0" % (ref_yield / s["spec"]["loading"]["confining_pressure"])] + [""] * len(windows)
            cells += ["%.2f %%" % (100 * tb), ""]
        else:
            diffs = [s["first_yield"].get("deviator", float("nan")) / ref_yield - 1]
            cells.append("%+.2f %%" % (100 * diffs[0]))
            for (lo, hi), r in zip(windows, ref_windows):
                m = window_mean(c["strain"], c["deviator"], lo, hi)
                if m is None or r is None:
                    cells.append("-")
                    continue
                diffs.append(m / r - 1)
                cells.append("%+.2f %%" % (100 * diffs[-1]))
            diffs.append(tb)
            cells += ["%.2f %%" % (100 * tb), "%.2f %%" % (100 * max(abs(d) for d in diffs))]
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

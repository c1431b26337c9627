#!/usr/bin/python3
"""Plot two_cube_sliding results against eq. 1 of the paper (Fig. 5b/5c).

usage: /usr/bin/python3 examples/plot_two_cube.py OUT_DIR [OUT_DIR ...] [-o figure.png]

Each OUT_DIR is what `granulab run SPEC --out OUT_DIR` wrote (curve.csv and summary.json).
Needs matplotlib (Debian: apt-get install python3-matplotlib).
"""
import argparse
import csv
import json
import os
import sys


def load(out_dir):
    with open(os.path.join(out_dir, "curve.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out_dir, "summary.json")) as f:
        summary = json.load(f)
    cols = {k: [float(r[k]) for r in rows] for k in rows[0]}
    return cols, summary


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("-o", "--output", default="two_cube.png")
    args = ap.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("matplotlib is missing: apt-get install python3-matplotlib, and run with /usr/bin/python3")

    fig, axes = plt.subplots(1, len(args.dirs), figsize=(5.2 * len(args.dirs), 4), squeeze=False)
    for ax, d in zip(axes[0], args.dirs):
        cols, s = load(d)
        f = s["spec"]["material"]["friction"]
        u = cols["slide_over_size"]
        ax.plot(u, cols["normal_over_p0"], color="tab:blue", lw=1.2, label="P/P0 (DEM)")
        ax.plot(u, cols["tangential_over_p0"], color="tab:red", lw=1.2, label="T/P0 (DEM)")
        ax.plot([0, 1], [1, 0], "--", color="tab:blue", lw=1, label="P/P0 = 1 - u/l (eq. 1)")
        ax.plot([0, 1], [f, 0], "--", color="tab:red", lw=1, label=f"T/P0 = f (1 - u/l), f = {f:g}")
        g = s["spec"]["grain"]
        ax.set_title(f"two cubes, N_e = {g['edge_spheres']}, kappa = {g['overlap']}, f = {f:g}")
        ax.set_xlabel("u / l")
        ax.set_ylabel("force / P0")
        ax.set_xlim(0, max(u))
        ax.axhline(0, color="0.6", lw=0.5)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(args.output)


if __name__ == "__main__":
    main()

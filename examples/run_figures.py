#!/usr/bin/python3
"""Run the example specs behind one of the paper's figures and plot their curves together.

usage: python3 examples/run_figures.py FIGURE [--max-strain S] [--out DIR] [--threads N] [--reuse]
       FIGURE: fig5 | fig7a | fig7c | fig10 | fig11 | all

Each spec runs with `build/granulab run` (sequentially; each uses all cores unless --threads) into
DIR/<spec name>/, then DIR/<figure>.csv gathers every curve (long format: spec,strain,...) and, when
matplotlib is available (Debian: python3-matplotlib, run with /usr/bin/python3), DIR/<figure>.png plots them.
--max-strain overrides loading.max_strain for a shorter run (the full 10 % takes about 30 min for the reference
crystal on 2 cores).
--reuse skips the specs whose DIR/<spec name>/summary.json already exists (gather and plot finished runs).
For crystal figures DIR/<figure>_summary.csv (also printed) lists per spec the first yield and the peak of
the deviator and of the total axial stress over p0, the peak of the curve smoothed over 0.5 % strain windows
and where it lies (softening starts after it), and each of them relative to the figure's first spec.
Standard library only, apart from the optional plot.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FIGURES = {
    "fig5": ["two_cube_f0", "two_cube_f03"],
    "fig7a": ["crystal_ref_p60", "fig7a_ne6", "fig7a_ne8"],
    "fig7c": ["crystal_ref_p60", "fig7c_p10", "fig7c_p30"],
    "fig10": ["crystal_ref_p60", "fig10_ko_centre", "fig10_ko_slip_plane", "fig10_ko_off_top", "fig10_ko_off_side"],
    "fig11": ["fig11_ar2", "fig11_ar1", "fig11_ar4"],
}


def run(name, out_dir, max_strain, threads, binary):
    with open(os.path.join(HERE, name + ".json")) as f:
        spec = json.load(f)
    if max_strain is not None and spec["experiment"] == "crystal_compression":
        spec["loading"]["max_strain"] = max_strain
        spec["output"]["snapshot_strains"] = [s for s in spec["output"].get("snapshot_strains", []) if s <= max_strain]
    target = os.path.join(out_dir, name)
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as tmp:
        json.dump(spec, tmp)
    cmd = [binary, "run", tmp.name, "--out", target] + (["--threads", str(threads)] if threads else [])
    print("running", name, "->", target, flush=True)
    try:
        subprocess.run(cmd, check=True)
    finally:
        os.unlink(tmp.name)
    return target


def summarise(results, out_dir, figure):
    """Strength measures per crystal spec and their ratios to the figure's first spec (the reference)."""
    rows = []
    for name, curve in results:
        if not curve or "deviator" not in curve[0]:
            return
        summary = json.load(open(os.path.join(out_dir, name, "summary.json")))
        p0 = summary["spec"]["loading"]["confining_pressure"]
        strain = [float(r["strain"]) for r in curve]
        dev = [float(r["deviator"]) / p0 for r in curve]
        # Smoothed: mean deviator over windows of 0.5 % strain (the curve's stick-slip drops average out).
        windows = {}
        for e, d in zip(strain, dev):
            windows.setdefault(int(e / 0.005), []).append((e, d))
        # Mean strain and deviator per window; a last window with fewer than 3 rows is left out.
        smooth = [(sum(e for e, _ in v) / len(v), sum(d for _, d in v) / len(v))
                  for _, v in sorted(windows.items()) if len(v) >= 3] or [(strain[-1], dev[-1])]
        smooth_strain, smooth_peak = max(smooth, key=lambda t: t[1])
        rows.append({
            "spec": name, "grains": summary["grains"], "p0": p0, "max_strain": strain[-1],
            "first_yield_dev": summary["first_yield"].get("deviator_over_p0", float("nan")),
            "first_yield_axial": summary["first_yield"].get("axial_over_p0", float("nan")),
            "first_yield_strain": summary["first_yield"].get("strain", float("nan")),
            "peak_dev": summary["peak"].get("deviator_over_p0", float("nan")), "peak_axial": summary["peak"].get("axial_over_p0", float("nan")),
            "peak_strain": summary["peak"].get("strain", float("nan")),
            "smoothed_peak_dev": smooth_peak, "smoothed_peak_strain": smooth_strain,
        })
    ref = rows[0]
    for r in rows:
        for key in ("first_yield_dev", "first_yield_axial", "peak_dev", "peak_axial", "smoothed_peak_dev"):
            r[key + "_ratio"] = r[key] / ref[key] if ref[key] else float("nan")
    path = os.path.join(out_dir, figure + "_summary.csv")
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print("%-22s %6s %9s | %-17s | %-17s | %-17s | %s" % ("spec", "grains", "to strain", "first yield dev/ax",
                                                     "peak dev/ax", "smoothed peak dev", "ratios to " + ref["spec"]))
    for r in rows:
        print("%-22s %6d %8.2f%% | %5.2f %5.2f %5.2f%% | %5.2f %5.2f %5.2f%% | %5.2f at %5.2f%% | %.2f %.2f %.2f" % (
            r["spec"], r["grains"], 100 * r["max_strain"], r["first_yield_dev"], r["first_yield_axial"],
            100 * r["first_yield_strain"], r["peak_dev"], r["peak_axial"], 100 * r["peak_strain"],
            r["smoothed_peak_dev"], 100 * r["smoothed_peak_strain"], r["first_yield_dev_ratio"], r["peak_dev_ratio"],
            r["smoothed_peak_dev_ratio"]))
    print("summary:", path)


def read_curve(directory):
    with open(os.path.join(directory, "curve.csv")) as f:
        return list(csv.DictReader(f))


def plot(figure, results, out_dir):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: curves are in", os.path.join(out_dir, figure + ".csv"))
        return
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for name, rows in results:
        if "strain" in rows[0]:
            p0 = json.load(open(os.path.join(out_dir, name, "summary.json")))["spec"]["loading"]["confining_pressure"]
            x = [100 * float(r["strain"]) for r in rows]
            ax.plot(x, [float(r["deviator"]) / p0 for r in rows], lw=1.2, label=name)
            ax.set_xlabel("strain (%)")
            ax.set_ylabel("deviator / p0")
        else:
            x = [float(r["slide_over_size"]) for r in rows]
            ax.plot(x, [float(r["normal_over_p0"]) for r in rows], lw=1.2, label=name + " P/P0")
            ax.plot(x, [float(r["tangential_over_p0"]) for r in rows], lw=1.2, label=name + " T/P0")
            ax.set_xlabel("u / l")
            ax.set_ylabel("force / P0")
    ax.set_title(figure)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out_dir, figure + ".png")
    fig.savefig(path, dpi=110)
    print("plot:", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("figure", choices=sorted(FIGURES) + ["all"])
    ap.add_argument("--max-strain", type=float)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "figures"))
    ap.add_argument("--threads", type=int)
    ap.add_argument("--reuse", action="store_true", help="do not rerun specs with a summary.json in DIR")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "granulab"))
    args = ap.parse_args()
    if not os.path.exists(args.binary):
        sys.exit("no granulab binary at %s: run `make run` or `make test` first" % args.binary)
    for figure in sorted(FIGURES) if args.figure == "all" else [args.figure]:
        results = []
        for name in FIGURES[figure]:
            directory = os.path.join(args.out, name)
            if not (args.reuse and os.path.exists(os.path.join(directory, "summary.json"))):
                directory = run(name, args.out, args.max_strain, args.threads, args.binary)
            results.append((name, read_curve(directory)))
        with open(os.path.join(args.out, figure + ".csv"), "w", newline="") as f:
            writer = csv.writer(f)
            header = list(results[0][1][0].keys())
            writer.writerow(["spec"] + header)
            for name, rows in results:
                for r in rows:
                    writer.writerow([name] + [r.get(k, "") for k in header])
        plot(figure, results, args.out)
        summarise(results, args.out, figure)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Strength against the loading axis, for every lattice (docs/results.md, "Lattices and loading axes").

usage: /usr/bin/python3 examples/lattice_axes.py [--out DIR] [--threads N] [--max-strain S] [--width W]
                                                 [--reuse] [--only NAME ...] [--estimates-only]

Runs one crystal_compression per case with `build/granulab run` (N_e = 4, kappa = 0.75, p0 = 30 kPa,
f = 0.35, R = p0/E), each a box about W x W x 2W (W in cubic cells a, default 4: aspect
ratio 2), then prints a markdown table (first yield, peak, apparent modulus; the box as built) and writes
DIR/lattice_axes.csv and, with matplotlib (Debian: python3-matplotlib), DIR/lattice_axes.png, the curves.
The apparent modulus is the summary's: the secant of the deviator between 10 % and 40 % of the first yield (of the
largest deviator for a crystal that does not yield), over strain.
Grain counts per direction come from the lattice's periods (the same rules as the engine's sample cut,
docs/model.md "Lattices and loading axes"): x the repeat along the lateral direction, y the spacing of the
site planes normal to y (HCP's A and B planes halve it), z the grain volume over the two.
Every case also gets the rigid-grain yield estimate (`granulab estimate --json`, docs/model.md "Yield estimate"):
a second table sets it against the first yield measured (sigma1 = deviator + p0). --estimates-only prints the
estimates alone, in about a second, without running anything (and with the measured values of DIR's runs if any).
Standard library only, apart from the optional plot.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# name, lattice, axis, lateral (lab x). FCC along its main axes and the paper's; the others along theirs.
CASES = [
    ("fcc_001", "fcc", [0, 0, 1], [1, 1, 0]),
    ("fcc_110", "fcc", [1, 1, 0], [0, 0, 1]),
    ("fcc_111", "fcc", [1, 1, 1], [1, -1, 0]),
    ("fcc_-1-12", "fcc", [-1, -1, 2], [1, -1, 0]),
    ("fcc_123", "fcc", [1, 2, 3], [1, 1, -1]),
    ("sc_001", "sc", [0, 0, 1], [1, 0, 0]),
    ("sc_110", "sc", [1, 1, 0], [0, 0, 1]),
    ("sc_111", "sc", [1, 1, 1], [1, -1, 0]),
    ("bcc_001", "bcc", [0, 0, 1], [1, 0, 0]),
    ("bcc_110", "bcc", [1, 1, 0], [0, 0, 1]),
    ("bcc_111", "bcc", [1, 1, 1], [1, -1, 0]),
    ("hcp_0001", "hcp", [0, 0, 1], [1, 0, 0]),
    ("hcp_2-1-10", "hcp", [1, 0, 0], [0, 0, 1]),
    ("hcp_01-10", "hcp", [1, 2, 0], [0, 0, 1]),
]


def mat_vec(m, v):
    return [sum(m[i][j] * v[j] for j in range(3)) for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def norm(a):
    return math.sqrt(dot(a, a))


def solve(m, v):
    """m^-1 v for a 3x3 m (Cramer)."""
    def det(a):
        return (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
                + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    d = det(m)
    out = []
    for k in range(3):
        mk = [[v[i] if j == k else m[i][j] for j in range(3)] for i in range(3)]
        out.append(det(mk) / d)
    return out


def cell(lattice):
    """Primitive translations (rows of the returned list are the matrix rows), basis, site volume; a = 1."""
    if lattice == "sc":
        p, basis = [[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 0, 0]]
    elif lattice == "fcc":
        p, basis = [[0, 0.5, 0.5], [0.5, 0, 0.5], [0.5, 0.5, 0]], [[0, 0, 0]]
    elif lattice == "bcc":
        p, basis = [[-0.5, 0.5, 0.5], [0.5, -0.5, 0.5], [0.5, 0.5, -0.5]], [[0, 0, 0]]
    else:
        d = 1 / math.sqrt(2)
        c = math.sqrt(8 / 3) * d
        p = [[d, -d / 2, 0], [0, d * math.sqrt(3) / 2, 0], [0, 0, c]]
        basis = [[0, 0, 0], mat_vec(p, [2 / 3, 1 / 3, 0.5])]
    m = p
    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    volume = abs(det) / len(basis)
    return p, basis, volume


def direction(lattice, uvw):
    if lattice != "hcp":
        return [float(x) for x in uvw]
    p, _, _ = cell("hcp")
    return mat_vec(p, uvw)


def integral(v):
    return all(abs(x - round(x)) < 1e-9 for x in v)


def periods(lattice, axis, lateral):
    p, basis, volume = cell(lattice)
    g = math.gcd(math.gcd(abs(lateral[0]), abs(lateral[1])), abs(lateral[2])) or 1
    v = direction(lattice, [x // g for x in lateral])
    wx = norm(v) / 2 if integral(solve(p, [x / 2 for x in v])) else norm(v)
    z = direction(lattice, axis)
    z = [x / norm(z) for x in z]
    x = [c / norm(v) for c in v]
    y = cross(z, x)
    c = [dot([p[0][k], p[1][k], p[2][k]], y) for k in range(3)]  # primitive translations . y
    top = max(abs(t) for t in c)
    wy = next(top / q for q in range(1, 2001) if integral([t * q / top for t in c]))
    offsets = sorted((dot(b, y) / wy + 1e-12) % 1 for b in basis)
    if len(offsets) > 1 and min(offsets[-1], 1 - offsets[-1]) > 1e-7:
        wy /= 2
    return wx, wy, volume / (wx * wy)


def spec(name, lattice, axis, lateral, width, max_strain):
    wx, wy, wz = periods(lattice, axis, lateral)
    gx, ly, rz = max(1, round(width / wx)), max(1, round(width / wy)), max(2, round(2 * width / wz))
    return {
        "experiment": "crystal_compression",
        "label": "%s along %s: N_e 4, p0 30 kPa, f 0.35, AR 2" % (lattice, axis),
        "grain": {"size": 0.01, "edge_spheres": 4, "overlap": 0.75},
        "material": {"youngs_modulus": 3e9, "density": 1200, "friction": 0.35},
        "crystal": {"lattice": lattice, "grains_x": gx, "layers_y": ly, "rows_z": rz},
        "loading": {"axis": axis, "lateral": lateral, "confining_pressure": 30e3, "max_strain": max_strain,
                    "rate_number": 30e3 / 3e9},  # p0/E, as the results were measured
        "output": {"curve_points": 200, "snapshot_strains": []},
    }


def read_curve(directory):
    with open(os.path.join(directory, "curve.csv")) as f:
        return list(csv.DictReader(f))


def measures(directory):
    summary = json.load(open(os.path.join(directory, "summary.json")))
    curve = read_curve(directory)
    p0 = summary["spec"]["loading"]["confining_pressure"]
    crystal = summary["spec"]["crystal"]
    width = math.sqrt(summary["cross_section"])
    first, peak, modulus = summary["first_yield"], summary["peak"], summary["apparent_modulus"]
    highest = max(float(r["deviator"]) for r in curve)
    highest_strain = next(float(r["strain"]) for r in curve if float(r["deviator"]) == highest)
    return {
        "grains": summary["grains"], "box": "%d x %d x %d" % (crystal["grains_x"], crystal["layers_y"], crystal["rows_z"]),
        "aspect": summary["initial_length"] / width,
        # A first yield or peak the curve never fell after is none (the summary says why), never its last row.
        "first_yield": first.get("deviator_over_p0"), "first_yield_strain": first.get("strain"),
        "first_yield_reason": first.get("reason"),
        "peak": peak["deviator_over_p0"] if peak["found"] else highest / p0,
        "peak_strain": peak["strain"] if peak["found"] else highest_strain,
        # The summary's apparent modulus: the secant between 10 % and 40 % of the first yield (or of the largest
        # deviator when there is none), docs/model.md.
        "modulus_over_p0": modulus["over_p0"] if modulus["found"] else float("nan"),
        "seconds": summary.get("wall_seconds", float("nan")),
        "steps": summary.get("steps", 0), "spheres": summary.get("spheres", 0), "curve": curve, "p0": p0,
    }


def plot(results, out_dir):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: the curves are in", os.path.join(out_dir, "lattice_axes.csv"))
        return
    fig, axes = plt.subplots(1, 4, figsize=(14, 4), sharey=True)
    panels = {"fcc": 0, "sc": 1, "bcc": 2, "hcp": 3}
    for name, m in results:
        ax = axes[panels[name.split("_")[0]]]
        rows = [r for r in m["curve"] if float(r["deviator"]) > 0]
        ax.plot([100 * float(r["strain"]) for r in rows], [float(r["deviator"]) / m["p0"] for r in rows],
                lw=1.1, label=name.split("_", 1)[1])
    for lattice, k in panels.items():
        axes[k].set_title(lattice)
        axes[k].set_xlabel("axial strain (%)")
        axes[k].legend(fontsize=8, title="axis")
    axes[0].set_ylabel("deviator / p0 (log scale)")
    axes[0].set_yscale("log")  # shared: the locked axes carry 100x what the sliding ones do
    axes[0].set_ylim(0.1, 2000)
    fig.suptitle("N_e = 4, p0 = 30 kPa, f = 0.35, aspect ratio 2, rate p0/E")
    fig.tight_layout()
    path = os.path.join(out_dir, "lattice_axes.png")
    fig.savefig(path, dpi=100)
    print("plot:", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "var", "lattice_axes"))
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--max-strain", type=float, default=0.03)
    ap.add_argument("--width", type=float, default=4.0, help="box width in cubic cells a")
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--estimates-only", action="store_true", help="the rigid-grain estimates, no runs")
    ap.add_argument("--granulab", default=os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    results, estimates = [], []
    for name, lattice, axis, lateral in CASES:
        if args.only and name not in args.only:
            continue
        target = os.path.join(args.out, name)
        estimates.append((name, estimate(args.granulab, spec(name, lattice, axis, lateral, args.width, args.max_strain)),
                          measures(target) if os.path.exists(os.path.join(target, "summary.json")) else None))
        if args.estimates_only:
            continue
        if not (args.reuse and os.path.exists(os.path.join(target, "summary.json"))):
            with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as tmp:
                json.dump(spec(name, lattice, axis, lateral, args.width, args.max_strain), tmp)
            cmd = [args.granulab, "run", tmp.name, "--out", target, "--quiet"]
            if args.threads:
                cmd += ["--threads", str(args.threads)]
            print("running", name, flush=True)
            subprocess.run(cmd, check=True)
            os.unlink(tmp.name)
        results.append((name, measures(target)))
    print_estimates(estimates)
    if args.estimates_only:
        return 0
    estimates = [(name, e, dict(results).get(name)) for name, e, _ in estimates]
    with open(os.path.join(args.out, "lattice_axes.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "strain", "deviator_over_p0"])
        for name, m in results:
            for r in m["curve"]:
                w.writerow([name, r["strain"], float(r["deviator"]) / m["p0"]])
    print("| case | box (x, y, z) | grains | AR | first yield σ_d/p0 (strain %) | highest σ_d/p0 (strain %) | "
          "apparent modulus / p0 | time (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, m in results:
        last = float(m["curve"][-1]["strain"])
        first = ("none to %.0f %%" % (100 * last) if m["first_yield"] is None else
                 "%.2f (%.3f)" % (m["first_yield"], 100 * m["first_yield_strain"]))
        print("| %s | %s | %d | %.2f | %s | %.2f (%.2f) | %.0f | %.0f |" % (
            name, m["box"], m["grains"], m["aspect"], first, m["peak"], 100 * m["peak_strain"], m["modulus_over_p0"],
            m["seconds"]))
    print()
    print_estimates(estimates)
    plot(results, args.out)


def estimate(granulab, one):
    """The spec's rigid-grain yield estimate, from `granulab estimate --json`."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as tmp:
        json.dump(one, tmp)
    try:
        out = subprocess.run([granulab, "estimate", tmp.name, "--json"], check=True, capture_output=True, text=True)
    finally:
        os.unlink(tmp.name)
    return json.loads(out.stdout)["yield_estimate"]


def print_estimates(rows):
    print("| case | rigid-grain estimate σ1/p0 | plane, slip direction | dilation | measured first yield σ1/p0 | "
          "measured / estimate |")
    print("| --- | --- | --- | --- | --- | --- |")
    for name, e, m in rows:
        measured, ratio = "-", "-"
        if m:
            last = float(m["curve"][-1]["strain"])
            if m["first_yield"] is not None:
                measured = "%.2f" % (m["first_yield"] + 1)
                if e["found"]:
                    ratio = "%.2f" % ((m["first_yield"] + 1) / e["axial_over_p0"])
            else:
                measured = "none to %.0f %%" % (100 * last)
        if e["found"]:
            print("| %s | %.2f | %s %s | %.1f° | %s | %s |" % (name, e["axial_over_p0"], e["plane"], e["direction"],
                                                               e["dilation_angle"], measured, ratio))
        else:
            print("| %s | locked | - | - | %s | - |" % (name, measured))


if __name__ == "__main__":
    sys.exit(main())

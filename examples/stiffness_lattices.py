#!/usr/bin/python3
"""The elastic tensors of the four crystals, and the paper's "too stiff" (docs/results.md, "Elastic tensors").

usage: /usr/bin/python3 examples/stiffness_lattices.py [--out DIR] [--threads N] [--width W] [--reuse]
                                                       [--only lattices|imperfect|paper]

Runs crystal_stiffness with `build/granulab run` (kappa = 0.75, f = 0.35) and prints three markdown tables:
- lattices: SC, FCC, BCC and HCP along their cube (HCP: c) axes, N_e = 4, p0 = 30 kPa, boxes about W cubic cells a
  on a side (default 5): the relaxed and affine C11, C12, C44 (HCP: its five), against the face-spring prediction,
  Zener's ratio, and Young's modulus along each axis of the compression table in docs/results.md ("Lattices and
  loading axes", the same N_e, p0 and f) against that table's apparent modulus;
- imperfect: the paper's crystal (off axis, 6 x 6 x 6 grains), N_e = 4, 60 kPa, perfect and with smaller or tilted
  grains, Young's modulus along its axis against the apparent modulus of the compression runs in README.md
  ("Imperfect grains", the same crystal, N_e, p0 and seed);
- paper: the paper's crystal at N_e = 6, 8 and 10 (the paper's model), 60 kPa, the same box.
Standard library only.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from lattice_axes import periods  # noqa: E402

LATTICES = [("sc", [0, 0, 1], [1, 0, 0]), ("fcc", [0, 0, 1], [1, 0, 0]), ("bcc", [0, 0, 1], [1, 0, 0]),
            ("hcp", [0, 0, 1], [1, 0, 0])]
# docs/results.md, "Lattices and loading axes" (2026-12-03, commit 7f3c157): N_e 4, 30 kPa, f 0.35, the secant of the
# deviator between 10 % and 40 % of the first yield (or of the highest), over p0. Axes in the lattice's own indices
# (HCP three-index, of a1, a2, c).
APPARENT = {"fcc": [([0, 0, 1], 7092), ([1, 1, 0], 16055), ([1, 1, 1], 9188), ([-1, -1, 2], 9365), ([1, 2, 3], 5762)],
            "sc": [([0, 0, 1], 88890), ([1, 1, 0], 22733), ([1, 1, 1], 9305)],
            "bcc": [([0, 0, 1], 11443), ([1, 1, 0], 12659), ([1, 1, 1], 7611)],
            "hcp": [([0, 0, 1], 8249), ([1, 0, 0], 20244), ([1, 2, 0], 10967)]}
# README.md, "Imperfect grains": the paper's crystal at N_e 4, 60 kPa, seed 1, secant to 0.05 % (MPa).
IMPERFECT = [("perfect", 0, 0, 342), ("σ_s = 0.1 %", 0.001, 0, 139), ("σ_s = 0.2 %", 0.002, 0, 85),
             ("σ_s = 0.5 %", 0.005, 0, 41), ("σ_s = 1 %", 0.01, 0, 25), ("σ_r = 0.25°", 0, 0.25, 78),
             ("σ_r = 0.5°", 0, 0.5, 39), ("σ_r = 1°", 0, 1.0, 18)]


def base(lattice, edge_spheres, p0):
    return {"experiment": "crystal_stiffness", "grain": {"size": 0.01, "edge_spheres": edge_spheres, "overlap": 0.75},
            "material": {"youngs_modulus": 3e9, "density": 1200, "friction": 0.35},
            "crystal": {"lattice": lattice}, "loading": {"confining_pressure": p0}}


def lattice_spec(lattice, axis, lateral, width):
    wx, wy, wz = periods(lattice, axis, lateral)
    s = base(lattice, 4, 30e3)
    s["label"] = "%s elastic tensor: N_e 4, p0 30 kPa" % lattice
    s["crystal"].update(grains_x=max(3, round(width / wx)), layers_y=max(3, round(width / wy)),
                        rows_z=max(3, round(width / wz)))
    s["loading"].update(axis=axis, lateral=lateral)
    return s


def run(granulab, spec, target, threads, reuse):
    if reuse and os.path.exists(os.path.join(target, "summary.json")):
        return json.load(open(os.path.join(target, "summary.json")))
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as tmp:
        json.dump(spec, tmp)
    cmd = [granulab, "run", tmp.name, "--out", target, "--quiet"] + (["--threads", str(threads)] if threads else [])
    done = subprocess.run(cmd, capture_output=True, text=True)
    os.unlink(tmp.name)
    if done.returncode != 0:
        raise RuntimeError(done.stderr)
    return json.load(open(os.path.join(target, "summary.json")))


def direction(lattice, uvw):
    """[u v w] as a crystal-frame vector (HCP: a1 = (1, 0, 0), a2 = (-1/2, sqrt3/2, 0), c = sqrt(8/3) D)."""
    if lattice != "hcp":
        return [float(x) for x in uvw]
    c = math.sqrt(8 / 3)
    return [uvw[0] - uvw[1] / 2, uvw[1] * math.sqrt(3) / 2, uvw[2] * c]


def young(c, d):
    """1 / (d d : C^-1 : d d), C 6 x 6 Voigt with engineering shears (Gauss-Jordan on [C | sigma])."""
    n = math.sqrt(sum(x * x for x in d))
    d = [x / n for x in d]
    sigma = [d[0] * d[0], d[1] * d[1], d[2] * d[2], d[1] * d[2], d[0] * d[2], d[0] * d[1]]
    m = [list(row) + [s] for row, s in zip(c, sigma)]
    for i in range(6):
        p = max(range(i, 6), key=lambda r: abs(m[r][i]))
        m[i], m[p] = m[p], m[i]
        for r in range(6):
            if r != i:
                f = m[r][i] / m[i][i]
                m[r] = [a - f * b for a, b in zip(m[r], m[i])]
    e = [m[i][6] / m[i][i] for i in range(6)]
    along = e[0] * d[0] ** 2 + e[1] * d[1] ** 2 + e[2] * d[2] ** 2 + e[3] * d[1] * d[2] + e[4] * d[0] * d[2] + \
        e[5] * d[0] * d[1]
    return 1 / along


def lattices(args):
    print("| lattice | box, grains (interior) | relaxed C11, C12, C44 (GPa) | affine / prediction, C11 | "
          "relaxed / affine | Zener | cubic spread | nonlinearity | time (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    tensors = {}
    for lattice, axis, lateral in LATTICES:
        s = run(args.granulab, lattice_spec(lattice, axis, lateral, args.width), os.path.join(args.out, lattice),
                args.threads, args.reuse)
        tensors[lattice] = s
        c, a, p = s["stiffness"], s["affine_stiffness"], s["affine_prediction"]
        cr = s["spec"]["crystal"]
        if lattice == "hcp":
            names = [(0, 0), (0, 1), (0, 2), (2, 2), (3, 3), (5, 5)]
            entries = "C11 %.3f, C12 %.3f, C13 %.3f, C33 %.3f, C44 %.3f, C66 %.3f" % tuple(c[i][j] / 1e9 for i, j in names)
            ratios = ", ".join("%.4f" % (c[i][j] / a[i][j]) for i, j in names)
        else:
            entries = "%.3f, %.3f, %.3f" % (c[0][0] / 1e9, c[0][1] / 1e9, c[3][3] / 1e9)
            ratios = ", ".join("%.4f" % (c[i][j] / a[i][j]) if abs(a[i][j]) > 1e-3 * a[0][0] else "-"
                               for i, j in [(0, 0), (0, 1), (3, 3)])
        print("| %s | %d × %d × %d, %d (%d) | %s | %.5f | %s | %s | %s | %.2g | %.0f |" % (
            lattice, cr["grains_x"], cr["layers_y"], cr["rows_z"], s["grains"], s["interior_grains"], entries,
            a[0][0] / p[0][0], ratios,
            "%.3f" % s["zener_ratio"]["relaxed"] if "zener_ratio" in s else "-",
            "%.1e" % s["cubic_spread"]["relaxed"] if "cubic_spread" in s else "-",
            s["nonlinearity"]["relaxed"], s["wall_seconds"]), flush=True)
    print()
    print("| crystal, axis | Young's modulus from the tensor / p0 | apparent modulus of the compression / p0 | ratio |")
    print("| --- | --- | --- | --- |")
    for lattice, axes in APPARENT.items():
        s = tensors[lattice]
        p0 = s["spec"]["loading"]["confining_pressure"]
        for axis, apparent in axes:
            e = young(s["stiffness"], direction(lattice, axis)) / p0
            print("| %s %s | %.0f | %.0f | %.1f |" % (lattice, axis, e, apparent, e / apparent), flush=True)


def imperfect(args, cases, edge_spheres, folder, header=True):
    if header:
        print("| grains | N_e | E along [-1 -1 2], relaxed (MPa) | affine (MPa) | relaxed / affine | nonlinearity | "
              "apparent modulus of the compression (MPa) | tensor / apparent | time (s) |")
        print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, size, tilt, apparent in cases:
        s = base("fcc", edge_spheres, 60e3)
        s["label"] = "the paper's crystal, %s: N_e %d, 60 kPa" % (name, edge_spheres)
        s["imperfections"] = {"size_dispersion": size, "misorientation": tilt, "seed": 1}
        r = run(args.granulab, s, os.path.join(args.out, "%s_%s" % (folder, name.replace(" ", "_"))), args.threads,
                args.reuse)
        e, ea = r["along_axis"]["relaxed"] / 1e6, r["along_axis"]["affine"] / 1e6
        print("| %s | %d | %.0f | %.0f | %.3f | %.3f | %s | %s | %.0f |" % (
            name, edge_spheres, e, ea, e / ea, r["nonlinearity"]["relaxed"], "%d" % apparent if apparent else "-",
            "%.1f" % (e / apparent) if apparent else "-", r["wall_seconds"]), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "var", "stiffness_lattices"))
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--width", type=float, default=5.0, help="box size of the lattice runs in cubic cells a")
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--only", choices=["lattices", "imperfect", "paper"])
    ap.add_argument("--granulab", default=os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.only in (None, "lattices"):
        lattices(args)
        print()
    if args.only in (None, "imperfect"):
        imperfect(args, IMPERFECT, 4, "paper_ne4")
        print()
    if args.only in (None, "paper"):
        for edge_spheres in (6, 8, 10):
            imperfect(args, [("perfect", 0, 0, None)], edge_spheres, "paper_ne%d" % edge_spheres, edge_spheres == 6)


if __name__ == "__main__":
    sys.exit(main())

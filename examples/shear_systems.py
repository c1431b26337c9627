#!/usr/bin/python3
"""The slip law of one slip system at a time: crystal_shear on the main systems of every lattice (docs/results.md,
"Shear on one slip system").

usage: /usr/bin/python3 examples/shear_systems.py [--out DIR] [--threads N] [--max-shear-strain G] [--width W]
                                                  [--reuse] [--only NAME ...]

Runs one crystal_shear per system with `build/granulab run` (N_e = 4, kappa = 0.75, p0 = sigma_n = 30 kPa,
f = 0.35, the default rate p0/E), each slab about W x W across (W in cubic cells a, default 4) and about W thick
along the plane's normal (at least four layers), sheared to G (default 0.1). Prints a markdown table: the peak and
residual tau/sigma_n, the dilation angle at the peak, against the rigid-grain estimate (docs/model.md, "Yield
estimate"), and where the slip concentrated in the last snapshot. Grain counts per direction come from the lattice's
periods (examples/lattice_axes.py). Standard library only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from lattice_axes import periods  # noqa: E402

# name, lattice, plane (Miller), its normal as a lattice direction (the sample's axis), shear direction.
SYSTEMS = [
    ("sc (1 0 0) [0 1 0]", "sc", [1, 0, 0], [1, 0, 0], [0, 1, 0]),
    ("fcc (1 1 1) [-2 1 1]", "fcc", [1, 1, 1], [1, 1, 1], [-2, 1, 1]),
    ("fcc (1 1 1) [2 -1 -1]", "fcc", [1, 1, 1], [1, 1, 1], [2, -1, -1]),
    ("fcc (1 1 1) [1 -1 0]", "fcc", [1, 1, 1], [1, 1, 1], [1, -1, 0]),
    ("bcc (1 1 0) [1 -1 1]", "bcc", [1, 1, 0], [1, 1, 0], [1, -1, 1]),
    ("bcc (1 1 0) [0 0 1]", "bcc", [1, 1, 0], [1, 1, 0], [0, 0, 1]),
    ("bcc (1 1 2) [1 1 -1]", "bcc", [1, 1, 2], [1, 1, 2], [1, 1, -1]),
    ("bcc (1 1 2) [-1 -1 1]", "bcc", [1, 1, 2], [1, 1, 2], [-1, -1, 1]),
    # HCP's basal plane (0 0 0 1), its normal c; directions in three indices of a1, a2, c: [1 0 0] = [2 -1 -1 0],
    # [1 2 0] = [0 1 -1 0].
    ("hcp (0 0 0 1) [2 -1 -1 0]", "hcp", [0, 0, 1], [0, 0, 1], [1, 0, 0]),
    ("hcp (0 0 0 1) [-2 1 1 0]", "hcp", [0, 0, 1], [0, 0, 1], [-1, 0, 0]),
    ("hcp (0 0 0 1) [0 1 -1 0]", "hcp", [0, 0, 1], [0, 0, 1], [1, 2, 0]),
    ("hcp (0 0 0 1) [0 -1 1 0]", "hcp", [0, 0, 1], [0, 0, 1], [-1, -2, 0]),
]


def spec(name, lattice, plane, axis, direction, width, max_shear_strain):
    wx, wy, wz = periods(lattice, axis, direction)
    gx, ly, rz = max(1, round(width / wx)), max(1, round(width / wy)), max(1, round(width / wz))
    return {
        "experiment": "crystal_shear",
        "label": "%s: N_e 4, p0 30 kPa, f 0.35" % name,
        "grain": {"size": 0.01, "edge_spheres": 4, "overlap": 0.75},
        "material": {"youngs_modulus": 3e9, "density": 1200, "friction": 0.35},
        "crystal": {"lattice": lattice, "grains_x": gx, "layers_y": ly, "rows_z": rz},
        "loading": {"plane": plane, "direction": direction, "confining_pressure": 30e3,
                    "max_shear_strain": max_shear_strain},
        "output": {"curve_points": 200, "snapshot_strains": [max_shear_strain]},
    }


def run(granulab, one, target, threads):
    """Runs the spec into target; a slab too thin for three layers gets one more repeat along its normal."""
    for _ in range(4):
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as tmp:
            json.dump(one, tmp)
        cmd = [granulab, "run", tmp.name, "--out", target, "--quiet"] + (["--threads", str(threads)] if threads else [])
        done = subprocess.run(cmd, capture_output=True, text=True)
        os.unlink(tmp.name)
        if done.returncode == 0:
            return
        if "crystal.rows_z" not in done.stderr:
            raise RuntimeError(done.stderr)
        one["crystal"]["rows_z"] += 1
    raise RuntimeError("no slab of three layers")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(ROOT, "var", "shear_systems"))
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--max-shear-strain", type=float, default=0.1)
    ap.add_argument("--width", type=float, default=4.0, help="slab width and thickness in cubic cells a")
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--only", nargs="*")
    ap.add_argument("--granulab", default=os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    print("| system | slab (x, y, z), grains | peak τ/σn (γ %) | residual τ/σn | dilation at the peak | "
          "rigid-grain estimate τ/σn, uplift | peak / estimate | slip in the last snapshot | time (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for name, lattice, plane, axis, direction in SYSTEMS:
        if args.only and name not in args.only:
            continue
        target = os.path.join(args.out, name.replace(" ", "_").replace("(", "").replace(")", "").replace("[", "")
                              .replace("]", ""))
        if not (args.reuse and os.path.exists(os.path.join(target, "summary.json"))):
            run(args.granulab, spec(name, lattice, plane, axis, direction, args.width, args.max_shear_strain), target,
                args.threads)
        s = json.load(open(os.path.join(target, "summary.json")))
        c, e = s["spec"]["crystal"], s["yield_estimate"]
        estimate = "%.3f, %.1f°" % (e["shear_over_normal"], e["dilation_angle"]) if e["found"] else "locked"
        ratio = "%.2f" % s["peak"]["over_estimate"] if "over_estimate" in s["peak"] else "-"
        snaps = s.get("snapshots", [])
        slip = "-"
        if snaps and "sliding_plane" in snaps[-1]:
            p = snaps[-1]["sliding_plane"]
            slip = "gap %d of %d, %.0f %%" % (p["gap"], s["layers"] - 1, 100 * p["share"])
        print("| %s | %d x %d x %d, %d | %.3f (%.2f) | %.3f | %.1f° | %s | %s | %s | %.0f |" % (
            name, c["grains_x"], c["layers_y"], c["rows_z"], s["grains"], s["peak"].get("shear_over_normal", float("nan")),
            100 * s["peak"].get("shear_strain", float("nan")), s["residual"]["shear_over_normal"], s["dilation_angle"], estimate, ratio,
            slip, s["wall_seconds"]), flush=True)


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""granulab's confinements against LAMMPS with the paper's fixed forces, strain window by strain window.

    /usr/bin/python3 bench/fixed_force_compare.py [--grains 3,7,4] [--edge-spheres 4] [--rate 2e-5]
        [--max-strain 0.03] [--pressure 60000] [--variants vector,in_plane,cross_section]
        [--granulab fixed_forces,membrane,membrane:defaults] [--ranks 2] [--out out/fixed_force_compare]

The LAMMPS side (docs/results.md, "Fixed forces against LAMMPS"): build/bench/fixed_force_lammps writes the crystal
as granulab builds it (the lattice pre-strained by eps0, platens just touching the end rows) and the paper's
confinement: every surface grain a constant force -p0 x the vector area of its exposed faces, end grains
included, split between two antipodal spheres (no torque); this script writes the input: fix rigid/small on
one molecule per grain, pair gran/hooke/history and wall/gran/region hooke/history platens with granulab's
k_n, k_t, damping and friction, fix addforce from the per-sphere forces, the bottom platen fixed and the top
one moving down at R sqrt(E/rho) from the first step; the platens' forces every record. Its deviator is the
mean platen force over the lattice cross-section (the platens carry the deviator alone).
Variants of the LAMMPS set-up: vector (the set-up above), in_plane (the lateral faces' axial force
components dropped), cross_section (each end's axial forces scaled to p0 x the cross-section, as granulab's
fixed_forces loads them), both (in_plane and cross_section), bag (granulab's fixed_forces forces, the bag's
on the sample as built, at the grains' centres, the ends' p0 x cross-section shared by projected area).

The granulab side: `granulab run` on the same crystal, material, damping, p0 and rate, with
loading.confinement fixed_forces and membrane (the bag confines first, then the loading starts). A confinement
named `NAME:defaults` runs at granulab's own damping and integration instead of LAMMPS' (docs/model.md: damping
0.05, the quarter-step damping velocity, 0.3 t0): the bag confines the dense 6 x 14 x 4 block at those in 600
steps, and at LAMMPS' damping 0.1 and 0.2 t0 not at all (it was still confining, then came apart, after
197,600 steps). A granulab run that fails is reported and left out; the others go on.

Prints the mean deviator / p0 over the strain windows 0.1-0.5, 0.5-1, ..., 2.5-3 % (each curve resampled on a
uniform strain grid) and every curve's ratio to the first LAMMPS variant; writes windows.csv and each curve. Then
the time per step of each run (LAMMPS: its loop time; granulab: its run, set-up included) and how many times
faster each granulab run stepped than the first LAMMPS variant: the dense, confined case of issue 30 and 52 is
`--grains 6,14,4 --edge-spheres 10 --max-strain 0.003 --granulab face_forces,membrane:defaults` (bench/README.md).
Standard library only; LAMMPS (Debian's lmp, mpirun) is installed if missing (bench/lammps_compare.py).
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from lammps_compare import die, ensure_lammps, read_params, run_measured  # noqa: E402

BUILD = os.path.join(ROOT, os.environ.get("BUILD", "build"))
WINDOWS = [(0.001, 0.005), (0.005, 0.01), (0.01, 0.015), (0.015, 0.02), (0.02, 0.025), (0.025, 0.03)]
VARIANTS = {"vector": [], "in_plane": ["--lateral", "in_plane"], "cross_section": ["--ends", "cross_section"],
            "both": ["--lateral", "in_plane", "--ends", "cross_section"], "bag": ["--distribution", "bag"]}


def lammps_input(p, skin):
    """The input script for the files fixed_force_lammps wrote (run in their folder)."""
    reach = 2 * (float(p["bounding_radius"]) - float(p["diameter"]) / 2)
    wall_law = "hooke/history %s %s %s %s %s 1" % (p["kn"], p["kt"], p["gamma_n_wall"], p["gamma_t_wall"],
                                                   p["wall_friction"])
    every, steps = int(float(p["record_every"])), int(float(p["steps"]))
    return "\n".join([
        "# Written by bench/fixed_force_compare.py from the files of fixed_force_lammps.",
        "# Rigid clumps of overlapping spheres (one molecule per grain), Hookean contacts with shear history,",
        "# constant confining forces on the surface grains, two frictional platens, the top one moving down.",
        "units           si",
        "atom_style      sphere",
        "atom_modify     map array",
        "boundary        f f f",
        "comm_modify     vel yes cutoff %.9g" % (1.05 * reach + skin),
        "fix             grainid all property/atom mol ghost yes",
        "# per-sphere constant force: -p0 x the grain's exposed vector area, on two antipodal spheres",
        "fix             pushed all property/atom d_fx d_fy d_fz",
        "read_data       data.grains fix grainid NULL Molecules",
        "include         forces.lmp",
        "neighbor        %.9g bin" % skin,
        "neigh_modify    delay 0 every 1 check yes exclude molecule/intra all",
        "pair_style      gran/hooke/history %s %s %s %s %s 1" % (p["kn"], p["kt"], p["gamma_n_pair"],
                                                                p["gamma_t_pair"], p["friction"]),
        "pair_coeff      * *",
        "timestep        %s" % p["dt"],
        "fix             bodies all rigid/small molecule infile bodies.rigid",
        "compute         push all property/atom d_fx d_fy d_fz",
        "variable        fx atom c_push[1]",
        "variable        fy atom c_push[2]",
        "variable        fz atom c_push[3]",
        "fix             confine all addforce v_fx v_fy v_fz",
        "variable        top_shift equal -%s*elapsed*%s" % (p["top_speed"], p["dt"]),
        "region          zhi plane 0 0 %s 0 0 -1 side in units box move NULL NULL v_top_shift" % p["wall_zhi"],
        "region          zlo plane 0 0 %s 0 0 1 side in units box" % p["wall_zlo"],
        "fix             wall_zlo all wall/gran/region %s region zlo contacts" % wall_law,
        "fix             wall_zhi all wall/gran/region %s region zhi contacts" % wall_law,
        "# the platens' forces on the spheres along z (the platen feels the opposite)",
        "compute         f_zlo all reduce sum f_wall_zlo[4]",
        "compute         f_zhi all reduce sum f_wall_zhi[4]",
        "fix             out all ave/time %d 1 %d c_f_zlo c_f_zhi file platens.txt format \" %%.12g\"" % (every, every),
        "thermo_style    custom step",
        "thermo          %d" % max(1, steps // 10),
        "run             %d" % steps,
    ]) + "\n"


def run_lammps(variant, args, out):
    folder = os.path.join(out, "lammps_" + variant)
    cmd = [os.path.join(BUILD, "bench", "fixed_force_lammps"), "--out", folder, "--grains", args.grains,
           "--edge-spheres", str(args.edge_spheres), "--rate", str(args.rate), "--max-strain", str(1.02 * args.max_strain),
           "--pressure", str(args.pressure)] + VARIANTS[variant]
    os.makedirs(folder, exist_ok=True)
    run_measured(cmd, os.path.join(folder, "export.log"))
    p = read_params(os.path.join(folder, "params.txt"))
    with open(os.path.join(folder, "in.lmp"), "w") as f:
        f.write(lammps_input(p, 0.1 * float(p["diameter"])))
    lmp = ["lmp", "-in", "in.lmp", "-log", "log.lammps", "-screen", "none"]
    if args.ranks > 1 and shutil.which("mpirun"):
        lmp = ["mpirun"] + (["--allow-run-as-root"] if os.geteuid() == 0 else []) + ["-np", str(args.ranks)] + lmp
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        seconds, _ = run_measured(lmp, "stdout.txt", env=dict(os.environ, OMP_NUM_THREADS="1"))
    finally:
        os.chdir(cwd)
    length, area, speed, dt = (float(p[k]) for k in ("length", "cross_section", "top_speed", "dt"))
    curve = [(0.0, 0.0)]
    with open(os.path.join(folder, "platens.txt")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            step, f_bottom, f_top = (float(x) for x in line.split()[:3])
            # The platens push the crystal: bottom +z, top -z; their mean over the cross-section.
            curve.append((speed * dt * step / length, (f_bottom - f_top) / 2 / area))
    print("  %-26s %6.0f s  (%s)" % ("LAMMPS " + variant, seconds, folder))
    with open(os.path.join(folder, "log.lammps")) as f:
        loop = [line.split() for line in f if line.startswith("Loop time of")]
    # "Loop time of T on N procs for S steps with A atoms"
    STEP_SECONDS["LAMMPS " + variant] = float(loop[-1][3]) / float(loop[-1][8]) if loop else float("nan")
    return curve


# Seconds per step of each run, by curve name (run_lammps, run_granulab).
STEP_SECONDS = {}


def run_granulab(entry, args, out):
    """granulab's run of one --granulab entry, CONFINEMENT or CONFINEMENT:defaults; its curve, or None if it failed."""
    confinement, _, how = entry.partition(":")
    x, z, y = (int(v) for v in args.grains.split(","))
    spec = {"experiment": "crystal_compression",
            "grain": {"edge_spheres": args.edge_spheres, "overlap": 0.75},
            "material": {"friction": 0.35, "damping": 0.1},
            "crystal": {"grains_x": x, "rows_z": z, "layers_y": y},
            "loading": {"confining_pressure": args.pressure, "max_strain": args.max_strain,
                        "rate_number": args.rate, "confinement": confinement},
            "output": {"curve_points": 400, "snapshot_strains": []},
            # LAMMPS' velocity Verlet: the dashpots see the half-step velocity; the time step of fixed_force_lammps.
            "run": {"damping_velocity": "half_step", "time_step_factor": 0.2},
            "label": "fixed_force_compare: %s, %s" % (args.grains, entry)}
    if how == "defaults":
        del spec["material"]["damping"], spec["run"]
    name = "granulab " + entry
    folder = os.path.join(out, "granulab_" + entry.replace(":", "_"))
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "spec.json"), "w") as f:
        json.dump(spec, f, indent=1)
    try:
        seconds, _ = run_measured([os.path.join(BUILD, "granulab"), "run", os.path.join(folder, "spec.json"),
                                   "--out", os.path.join(folder, "run"), "--threads", str(args.ranks)],
                                  os.path.join(folder, "run.log"))
    except SystemExit as failed:  # run_measured printed the log's tail
        print("  %s failed, left out (%s)" % (name, failed), file=sys.stderr)
        return None
    with open(os.path.join(folder, "run", "curve.csv")) as f:
        curve = [(0.0, 0.0)] + [(float(r["strain"]), float(r["deviator"])) for r in csv.DictReader(f)]
    with open(os.path.join(folder, "run", "summary.json")) as f:
        summary = json.load(f)
    STEP_SECONDS[name] = summary["wall_seconds"] / max(1, summary["steps"])
    print("  %-26s %6.0f s  (%s; kernel %s)" % (name, seconds, folder, summary.get("kernel", "?")))
    return curve


def window_mean(curve, lo, hi, points=200):
    """Mean of the curve over strains [lo, hi], linearly interpolated on a uniform grid."""
    curve = sorted(curve)
    total, k = 0.0, 0
    for i in range(points + 1):
        e = lo + (hi - lo) * i / points
        while k + 1 < len(curve) and curve[k + 1][0] < e:
            k += 1
        if k + 1 >= len(curve):
            return float("nan")
        (e0, s0), (e1, s1) = curve[k], curve[k + 1]
        total += s0 + (s1 - s0) * (e - e0) / (e1 - e0) if e1 > e0 else s0
    return total / (points + 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grains", default="3,7,4", help="grains_x,rows_z,layers_y")
    ap.add_argument("--edge-spheres", type=int, default=4)
    ap.add_argument("--rate", type=float, default=2e-5)
    ap.add_argument("--max-strain", type=float, default=0.03)
    ap.add_argument("--pressure", type=float, default=60e3)
    ap.add_argument("--variants", default="vector", help="LAMMPS set-ups, comma-separated: " + ",".join(VARIANTS))
    ap.add_argument("--granulab", default="fixed_forces,membrane", help="granulab confinements (or none); NAME:defaults at granulab's own damping and integration")
    ap.add_argument("--ranks", type=int, default=2, help="LAMMPS MPI ranks and granulab threads")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "fixed_force_compare"))
    args = ap.parse_args()
    entries = [c for c in args.granulab.split(",") if c and c != "none"]
    for c in entries:
        if c.partition(":")[2] not in ("", "defaults"):
            die("--granulab %s: the only suffix is :defaults (granulab's own damping and integration)" % c)
    ensure_lammps()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    curves = []
    for v in args.variants.split(","):
        curves.append(("LAMMPS " + v, run_lammps(v, args, out)))
    for c in entries:
        curve = run_granulab(c, args, out)
        if curve is not None:
            curves.append(("granulab " + c, curve))
    windows = [w for w in WINDOWS if w[1] <= args.max_strain + 1e-12]
    if not windows and args.max_strain > WINDOWS[0][0]:  # a short run (the speed benchmark): one window to its end
        windows = [(WINDOWS[0][0], args.max_strain)]
    means = {name: [window_mean(curve, lo, hi) / args.pressure for lo, hi in windows] for name, curve in curves}
    base = curves[0][0]
    print("\n%s crystal, N_e = %d, p0 = %.0f kPa, R = %g: mean deviator / p0 per strain window (ratio to %s)"
          % (args.grains.replace(",", " x "), args.edge_spheres, args.pressure / 1e3, args.rate, base))
    print("| curve | " + " | ".join("%.2g-%.2g %%" % (100 * lo, 100 * hi) for lo, hi in windows) + " |")
    print("| --- |" + " --- |" * len(windows))
    for name, _ in curves:
        cells = ["%.2f" % m if name == base else "%.2f (%.2f)" % (m, m / b) for m, b in zip(means[name], means[base])]
        print("| %s | %s |" % (name, " | ".join(cells)))
    with open(os.path.join(out, "windows.csv"), "w") as f:
        f.write("curve," + ",".join("%g-%g" % w for w in windows) + "\n")
        for name, _ in curves:
            f.write(name + "," + ",".join("%.6g" % m for m in means[name]) + "\n")
    for name, curve in curves:
        with open(os.path.join(out, name.replace(" ", "_") + ".csv"), "w") as f:
            f.write("strain,deviator\n" + "".join("%.9g,%.9g\n" % row for row in curve))
    print("\ntime per step (%d ranks / threads): " % args.ranks +
          ", ".join("%s %.3g ms" % (name, 1e3 * STEP_SECONDS[name]) for name, _ in curves if name in STEP_SECONDS))
    for name in [name for name, _ in curves if name.startswith("granulab")]:
        if base in STEP_SECONDS:
            print("%s steps %.1fx faster than %s" % (name, STEP_SECONDS[base] / STEP_SECONDS[name], base))


if __name__ == "__main__":
    main()

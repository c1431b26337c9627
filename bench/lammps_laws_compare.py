#!/usr/bin/python3
"""granulab's interface laws against LAMMPS' pair_style granular: two cubes at rest, force against overlap (issue 29).

    /usr/bin/python3 bench/lammps_laws_compare.py [--laws hertz/material,dmt,jkr] [--gamma 5] [--points 600]
        [--from -2] [--to 4] [--pull-to -2.5] [--tolerance 0.01] [--threshold 1e-3] [--skin-breaks 4]
        [--out out/lammps_laws_compare]

The problem (build/bench/bench_interface_laws, see its header; tests/engine/validation/interface_laws_test.cpp):
two aligned cubes (GrainTemplate cube, edge 0.01 m, N_e = 4, kappa = 0.75, 56 spheres each, the 16 of each facing
layer aligned in pairs), E = 3e9 Pa, nu = 0.3, gamma (dmt, jkr) from --gamma. Cube 2 is held at rest at an overlap
delta of the facing layers; the sweep presses in from apart ("in") and pulls back out past JKR's break point ("out"),
in units of s = JKR's break depth a_c^2 / (3 R*) (at gamma = 5 when the law has none).

Per law this script
  1. runs bench_interface_laws --law L --gamma G --write-lammps DIR: our curve (CSV on stdout, kept as ours.csv), the
     spheres (DIR/data.grains: the same positions and diameter, one molecule per cube, cube 2 at delta = 0) and the
     constants (DIR/params.txt);
  2. writes DIR/in.laws: atom_style sphere, no time integration (nothing moves by itself), spheres of one cube
     excluded from each other (neigh_modify exclude molecule/intra), pair_style granular with
       pair_coeff * * <law> E 0 nu [gamma] damping velocity tangential linear_history k_t 0 mu
     (one atom type: `* *` avoids the Debian version's mixing of E* between types; damping is irrelevant at rest),
     neighbor skin = --skin-breaks x s (it must exceed the break distance: this LAMMPS version's pair cutoff adds
     its pull-off distance with the wrong sign, and a bonded pair beyond radsum + skin would be lost), comm_modify
     vel yes; then for every delta of our sweep, in order: displace_atoms cube2 by the change of -delta, `run 1`
     (the setup's force evaluation updates JKR's touch flags, which fix neigh/history keeps between runs), and the
     sum of fx over cube2's spheres (compute reduce) and the overlap of one aligned pair, measured from the atoms'
     positions, printed to DIR/lammps_rows.txt;
  3. compares the two curves point by point: the largest |F_lammps - F_ours| / |F_ours| over the points with
     |F_ours| > --threshold x max |F_ours|, the points where one code has a force and the other none, the overlap
     LAMMPS' atoms actually sit at against ours; dmt: the pull-off (most tensile force) and no force apart; jkr: the
     most tensile force, the snap at first touch, the last overlap held and the first one broken on the way out;
     each also against its closed form (n_c 4 pi gamma R*, n_c 3 pi gamma R*, -a_c^2/(3 R*)).
Writes DIR/ours.csv, DIR/lammps_rows.txt, DIR/curves.csv (delta, both forces) and prints a summary; exits 1 when a
difference exceeds --tolerance. Standard library only; needs Debian's /usr/bin/lmp (29 Sep 2021 update 2; installed
with apt-get if missing, as bench/lammps_compare.py does) and build/bench/bench_interface_laws
(cmake --build build --target bench_interface_laws). LAMMPS is a comparison tool only.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from lammps_compare import ensure_lammps, read_params  # noqa: E402

BUILD = os.path.join(ROOT, os.environ.get("BUILD", "build"))


def die(msg, code=2):
    print("lammps_laws_compare: " + msg, file=sys.stderr)
    sys.exit(code)


def read_ours(path):
    with open(path) as f:
        return [(r["phase"], float(r["delta_m"]), float(r["force_N"])) for r in csv.DictReader(f)]


def read_spheres(path):
    """{id: (molecule, x, y, z)} and the diameter from a data.grains file."""
    atoms, mols, section, diameter = {}, {}, None, None
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s:
                continue
            if s[0] in ("Atoms", "Molecules"):
                section = s[0]
                continue
            if section == "Atoms" and len(s) == 7:
                atoms[int(s[0])] = tuple(float(v) for v in s[4:7])
                diameter = float(s[2])
            elif section == "Molecules" and len(s) == 2:
                mols[int(s[0])] = int(s[1])
    return {i: (mols[i],) + atoms[i] for i in atoms}, diameter


def aligned_pair(spheres):
    """Ids of one facing sphere of cube 1 (largest x) and its aligned partner in cube 2 (smallest x, same y and z)."""
    c1 = max((v[1], i) for i, v in spheres.items() if v[0] == 1)[1]
    y, z = spheres[c1][2], spheres[c1][3]
    c2 = min((v[1], i) for i, v in spheres.items()
             if v[0] == 2 and abs(v[2] - y) < 1e-12 and abs(v[3] - z) < 1e-12)[1]
    return c1, c2


def law_coeff(p):
    """pair_coeff arguments of the law: E, damping eta_n0 = 0, nu [, gamma]; velocity damping; linear_history."""
    law = p["law"]
    normal = "%s %s 0 %s" % (law, p["youngs"], p["poisson"])
    if law in ("dmt", "jkr"):
        normal += " %s" % p["gamma"]
    return "%s damping velocity tangential linear_history %s 0 %s" % (normal, p["kt"], p["friction"])


def lammps_input(p, rows, ids, skin):
    lines = [
        "# Written by bench/lammps_laws_compare.py from the files of bench_interface_laws --write-lammps.",
        "# Two cubes of overlapping spheres (one molecule each) at rest; cube 2 is moved to each overlap of the",
        "# sweep and the force on it measured after one step without time integration.",
        "units           si",
        "atom_style      sphere",
        "atom_modify     map array sort 0 0",
        "boundary        f f f",
        "newton          on",
        "comm_modify     vel yes",
        "fix             grainid all property/atom mol ghost yes",
        "read_data       data.grains fix grainid NULL Molecules",
        "group           cube1 molecule 1",
        "group           cube2 molecule 2",
        "neighbor        %.17g bin" % skin,
        "neigh_modify    delay 0 every 1 check yes exclude molecule/intra all",
        "pair_style      granular",
        "pair_coeff      * * %s" % law_coeff(p),
        "compute         f2 cube2 reduce sum fx",
        "# overlap of one aligned pair (ids %d, %d) from the atoms' positions" % ids,
        "variable        overlap equal %s-(x[%d]-x[%d])" % (p["diameter"], ids[1], ids[0]),
        "thermo_style    custom step c_f2 v_overlap",
        "thermo_modify   format float %.17g",
        "thermo          1",
    ]
    current = 0.0  # data.grains holds cube 2 at delta = 0
    for k, (phase, delta, _) in enumerate(rows):
        lines += [
            "displace_atoms  cube2 move %.17g 0 0 units box" % (-(delta - current)),
            "run             1 post no",
            'print           "%s %d %.17g $(c_f2:%%.17g) $(v_overlap:%%.17g)" append lammps_rows.txt screen no'
            % (phase, k, delta),
        ]
        current = delta
    return "\n".join(lines) + "\n"


def read_lammps_rows(path):
    out = []
    with open(path) as f:
        for line in f:
            s = line.split()
            if len(s) == 5:
                out.append((s[0], float(s[2]), float(s[3]), float(s[4])))
    return out


def compare_law(law, args, out_root):
    bench = os.path.join(BUILD, "bench", "bench_interface_laws")
    if not os.access(bench, os.X_OK):
        die("%s not found: cmake --build build --target bench_interface_laws" % bench)
    d = os.path.join(out_root, law.replace("/", "_"))
    os.makedirs(d, exist_ok=True)
    rows_path = os.path.join(d, "lammps_rows.txt")
    if os.path.exists(rows_path):
        os.remove(rows_path)
    cmd = [bench, "--law", law, "--gamma", repr(args.gamma), "--points", str(args.points), "--from", repr(args.start),
           "--to", repr(args.to), "--pull-to", repr(args.pull_to), "--write-lammps", d]
    with open(os.path.join(d, "ours.csv"), "w") as f:
        subprocess.run(cmd, check=True, stdout=f)
    ours = read_ours(os.path.join(d, "ours.csv"))
    p = read_params(os.path.join(d, "params.txt"))
    spheres, diameter = read_spheres(os.path.join(d, "data.grains"))
    ids = aligned_pair(spheres)
    unit = float(p["unit"])
    skin = args.skin_breaks * unit
    with open(os.path.join(d, "in.laws"), "w") as f:
        f.write(lammps_input(p, ours, ids, skin))
    log = os.path.join(d, "lmp.out")
    with open(log, "w") as f:
        r = subprocess.run([args.lmp, "-in", "in.laws", "-log", "log.lammps", "-screen", "none"], cwd=d,
                           stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        die("lmp failed for %s (see %s and %s)" % (law, log, os.path.join(d, "log.lammps")))
    theirs = read_lammps_rows(rows_path)
    if len(theirs) != len(ours):
        die("%s: %d LAMMPS rows for %d of ours" % (law, len(theirs), len(ours)))

    with open(os.path.join(d, "curves.csv"), "w") as f:
        f.write("phase,delta_m,force_ours_N,force_lammps_N,overlap_lammps_m\n")
        for (ph, dl, fo), (_, _, fl, ol) in zip(ours, theirs):
            f.write("%s,%.17g,%.17g,%.17g,%.17g\n" % (ph, dl, fo, fl, ol))

    fmax = max(abs(fo) for _, _, fo in ours)
    worst, worst_at, tested, mismatch = 0.0, None, 0, []
    overlap_err = 0.0
    for (ph, dl, fo), (_, _, fl, ol) in zip(ours, theirs):
        overlap_err = max(overlap_err, abs(ol - dl))
        if (fo == 0) != (fl == 0):
            mismatch.append((ph, dl, fo, fl))
        if abs(fo) > args.threshold * fmax:
            rel = abs(fl - fo) / abs(fo)
            tested += 1
            if rel > worst:
                worst, worst_at = rel, (ph, dl, fo, fl)
    res = {"law": law, "points": len(ours), "tested": tested, "fmax": fmax, "worst": worst, "worst_at": worst_at,
           "mismatch": mismatch, "overlap_err": overlap_err, "unit": unit, "skin": skin, "dir": d}
    checks = []  # (name, ours, lammps, closed form or None)

    def phase_rows(name, src, fi):
        return [(r[1], r[fi]) for r in src if r[0] == name]

    if law in ("dmt", "jkr"):
        for name, fi_o, fi_l in (("in", 2, 2), ("out", 2, 2)):
            o = phase_rows(name, ours, fi_o)
            t = phase_rows(name, theirs, fi_l)
            checks.append(("most tensile (%s) N" % name, min(f for _, f in o), min(f for _, f in t),
                           -float(p["pulloff_%s_closed" % law])))
        if law == "jkr":
            o_in, t_in = phase_rows("in", ours, 2), phase_rows("in", theirs, 2)
            first_o = next((dl, f) for dl, f in o_in if f != 0)
            first_t = next((dl, f) for dl, f in t_in if f != 0)
            n_c = float(p["aligned_pairs"])
            snap_closed = -n_c * 8.0 / 3 * math.pi * float(p["gamma"]) * float(p["r_eff"])
            checks.append(("first touch delta m", first_o[0], first_t[0], 0.0))
            checks.append(("snap force at first touch N", first_o[1], first_t[1], snap_closed))
            o_out, t_out = phase_rows("out", ours, 2), phase_rows("out", theirs, 2)
            held_o = min(dl for dl, f in o_out if f != 0)
            held_t = min(dl for dl, f in t_out if f != 0)
            broken_o = max(dl for dl, f in o_out if f == 0 and dl < held_o + 1e-30)
            broken_t = max(dl for dl, f in t_out if f == 0 and dl < held_t + 1e-30)
            checks.append(("last held delta (out) m", held_o, held_t, -float(p["break_depth_jkr_closed"])))
            checks.append(("first broken delta (out) m", broken_o, broken_t, -float(p["break_depth_jkr_closed"])))
        if law == "dmt":
            apart_o = max(abs(f) for dl, f in ((r[1], r[2]) for r in ours) if dl < 0)
            apart_t = max(abs(f) for dl, f in ((r[1], r[2]) for r in theirs) if dl < 0)
            checks.append(("largest |F| apart N", apart_o, apart_t, 0.0))
    res["checks"] = checks
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--laws", default="hertz/material,dmt,jkr")
    ap.add_argument("--gamma", type=float, default=5.0, help="surface energy of dmt and jkr (J/m^2)")
    ap.add_argument("--points", type=int, default=600, help="points per phase of the sweep")
    ap.add_argument("--from", dest="start", type=float, default=-2.0, help="sweep start, in break depths s")
    ap.add_argument("--to", type=float, default=4.0, help="deepest overlap, in break depths s")
    ap.add_argument("--pull-to", type=float, default=-2.5, help="end of the pull-out, in break depths s")
    ap.add_argument("--tolerance", type=float, default=0.01)
    ap.add_argument("--threshold", type=float, default=1e-3, help="points tested: |F| > threshold x max |F|")
    ap.add_argument("--skin-breaks", type=float, default=4.0, help="LAMMPS skin in break depths s")
    ap.add_argument("--lmp", default="/usr/bin/lmp")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "lammps_laws_compare"))
    args = ap.parse_args()
    if not os.access(args.lmp, os.X_OK):
        ensure_lammps()
    out = os.path.abspath(args.out)
    ok = True
    for law in args.laws.split(","):
        r = compare_law(law, args, out)
        print("== %s (gamma %g J/m^2; %d points, s = %.6g m, LAMMPS skin %.6g m; files in %s)"
              % (law, args.gamma if law != "hertz/material" else 0, r["points"], r["unit"], r["skin"], r["dir"]))
        print("  point by point: largest relative difference %.3g over %d points with |F| > %g x %.6g N"
              % (r["worst"], r["tested"], args.threshold, r["fmax"]))
        if r["worst_at"]:
            ph, dl, fo, fl = r["worst_at"]
            print("    at %s delta %.6g m: ours %.10g N, LAMMPS %.10g N" % (ph, dl, fo, fl))
        print("  LAMMPS' atoms sit within %.3g m of our overlap (%.3g s)" % (r["overlap_err"], r["overlap_err"] / r["unit"]))
        print("  points where one code has a force and the other none: %d" % len(r["mismatch"]))
        for m in r["mismatch"][:10]:
            print("    %s delta %.10g m: ours %.10g N, LAMMPS %.10g N" % m)
        for name, o, t, closed in r["checks"]:
            rel = abs(t - o) / abs(o) if o != 0 else (0.0 if t == 0 else float("inf"))
            line = "  %-30s ours %.10g  LAMMPS %.10g  (rel. diff. %.3g)" % (name, o, t, rel)
            if closed is not None:
                line += "  closed form %.10g" % closed
            print(line)
        bad = r["worst"] > args.tolerance or r["mismatch"]
        for name, o, t, _ in r["checks"]:
            if "delta" in name:
                bad = bad or abs(t - o) > 1e-6 * r["unit"]
            elif o != 0:
                bad = bad or abs(t - o) / abs(o) > args.tolerance
        print("  %s" % ("FAIL" if bad else "ok: within %g" % args.tolerance))
        ok = ok and not bad
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()

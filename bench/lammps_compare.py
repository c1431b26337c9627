#!/usr/bin/python3
"""Side-by-side speed benchmark of granulab against LAMMPS on the same DEM problem (standard library only).

Problem (built by build/bench/bench_compare, see its header): a dense off-axis FCC block of rhombic
dodecahedra, N_e = 10, kappa = 0.75 (974 spheres per grain; 6 x 6 x 6 = 216 grains, 210,384 spheres by
default), pre-strain 1e-4, two fixed walls normal to +-x, a fixed bottom wall and a top wall moving down at
v = 1e-4 sqrt(E/rho); the same grain geometry, stiffness, friction, damping, time step and step count in
both codes.

What it does:
  1. installs LAMMPS from Debian (apt-get update; apt-get install -y lammps) if `lmp` is missing;
  2. runs bench_compare (1 and 2 threads): our timing and wall forces, and the LAMMPS data file, per-body
     file and parameters (--write-lammps);
  3. writes the LAMMPS input script itself (in.forces: with wall-force output; in.timing: without it);
  4. runs lmp on 1 rank with force output, then timing runs on 1 rank and, with mpirun, on 2 ranks;
  5. checks that the wall forces agree and prints sphere-steps/s, the ratio to LAMMPS on the same number
     of cores and the peak RSS.

Force agreement criterion (default): for every record where our top-wall force is at least 10 % of its
maximum over the run, |F_lammps - F_ours| / |F_ours| < 1 %. The same is reported (not enforced) for the
other walls. Why 1 % is a fair bar: the two codes integrate the same equations of motion with the same
constants, so the records agree to ~1e-5 at first and differ only by accumulated round-off and the
modelling details below, which are second order in the tiny per-step rotations and overlaps
(delta/d ~ 1e-3):
  * rigid-body integrator: LAMMPS' fix rigid/small (Richardson-iterated quaternion update) vs our
    velocity Verlet with the NO_SQUISH free-rotor splitting. The RD's inertia is isotropic, so the free
    rotation is exact in both; the schemes differ only in how the torque
    updates the orientation within a step, at O(dt^2).
  * shear history: LAMMPS adds v_t dt and then projects the spring onto the new tangent plane, shortening
    it by O(theta^2) (theta = the contact normal's rotation in one step, < 1e-5 here); we rotate it into
    the plane keeping its length, then add v_t dt.
  * contact point: LAMMPS evaluates the rotational part of the relative velocity and applies the
    tangential force at one radius from each sphere centre (so its two torques differ by delta x F_t), we
    at the mid-point of the overlap for both spheres (a lever-arm difference of delta/2 ~ 1e-4 d); on walls
    LAMMPS uses one radius from the centre, we the foot of the centre on the plane.
  * walls: the fixed ones are fix wall/gran xplane/zplane (default, --lmp-walls plane) or plane regions
    (--lmp-walls region; same forces, ~16 % slower LAMMPS steps); the moving top wall is a region moved by
    a displacement variable, its velocity taken from the finite difference of the displacement (exact at
    constant speed); LAMMPS uses m_eff = the rigid body's mass on walls, as we do.
  * both codes use the same time step; the neighbour rules differ (LAMMPS: everything again when an atom
    moved half the skin; ours: a grain pair again when its relative pose drifted a skin), and so do the
    skins (ours 0.03 d, the engine default; LAMMPS 0.1 d, its fastest of 0.05/0.1/0.2 d here); neither
    changes forces.
At 1e-3 relative per quantity and with the block's response smooth over 2000 steps these stay well below
1 %; where the force is small (< 10 % of its maximum, e.g. while a wall is about to lose contact) relative
differences are meaningless and are not tested.
The walls start v dt / 2 away from the outermost spheres (bench_compare): with a zero gap, the coplanar
outer spheres would start at round-off-level overlaps and the damping force c_n v of the moving wall would
switch on for a round-off-dependent subset of them (0.1-1 % discrepancies in the first records).

Usage: /usr/bin/python3 bench/lammps_compare.py [--steps 2000] [--record-every 20] [--grains 6]
           [--out out/lammps_compare] [--lmp-skin 0.1] [--lmp-walls plane|region] [--tolerance 0.01]
           [--threshold 0.1] [--repeat 1] [--no-mpi]
Timings on a shared machine are noisy (+-25 % seen here): use --repeat 2 or more before quoting a ratio.
Needs build/bench/bench_compare (run `make build` first). LAMMPS is a comparison tool only: nothing in
engine/, api/ or server/ depends on it and `make test` does not need it.
"""
import argparse
import csv
import os
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def die(msg, code=2):
    print("lammps_compare: " + msg, file=sys.stderr)
    sys.exit(code)


def ensure_lammps():
    if shutil.which("lmp"):
        return
    print("lmp not found: installing the Debian package lammps")
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(sudo + ["apt-get", "update"], check=True, env=env)
    subprocess.run(sudo + ["apt-get", "install", "-y", "lammps"], check=True, env=env)
    if not shutil.which("lmp"):
        die("apt-get install lammps did not provide lmp")


def run_measured(cmd, log_path, env=None):
    """Runs cmd with stdout+stderr to log_path; returns (wall seconds, peak RSS MiB of the largest process)."""
    with open(log_path, "w") as log:
        start = time.monotonic()
        p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env)
        _, status, usage = os.wait4(p.pid, 0)
        seconds = time.monotonic() - start
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        with open(log_path) as f:
            tail = f.read()[-3000:]
        die("command failed (%d): %s\n--- %s (tail) ---\n%s" % (p.returncode, " ".join(cmd), log_path, tail))
    return seconds, usage.ru_maxrss / 1024.0  # ru_maxrss in KiB on Linux


def read_params(path):
    params = {}
    with open(path) as f:
        for line in f:
            parts = line.split()
            if parts:
                params[parts[0]] = parts[1:] if len(parts) > 2 else parts[1]
    return params


def lammps_input(p, skin, with_forces, forces_file, walls="plane"):
    """The LAMMPS input script for the files written by bench_compare --write-lammps.

    walls = "region": all four walls are fix wall/gran/region on plane regions; "plane": the three fixed
    ones are fix wall/gran xplane/zplane (the same contact law, without the region machinery, which costs
    LAMMPS ~16 % of its step here), the moving top one stays a moving region."""
    f = float
    kn, kt, mu = p["kn"], p["kt"], p["friction"]
    dt, steps, every = p["dt"], int(f(p["steps"])), int(f(p["record_every"]))
    # Ghost cutoff for fix rigid/small: every atom of a body must be within it of the body's owning atom
    # (at most twice the largest sphere-centre offset).
    reach = 2 * (f(p["bounding_radius"]) - f(p["diameter"]) / 2)
    ghost_cut = 1.05 * reach + skin
    contacts = " contacts" if with_forces else ""
    wall_law = "hooke/history %s %s %s %s %s 1" % (kn, kt, p["gamma_n_wall"], p["gamma_t_wall"], mu)
    lines = [
        "# Written by bench/lammps_compare.py from the files of bench_compare --write-lammps.",
        "# Rigid clumps of overlapping spheres (one molecule per grain), Hookean contacts with shear history,",
        "# four frictional plane walls, the top one (a region) moving down at constant speed.",
        "units           si",
        "atom_style      sphere",
        "atom_modify     map array",
        "boundary        f f f",
        "comm_modify     vel yes cutoff %.9g" % ghost_cut,
        "# grain id of every sphere, read from the Molecules section of the data file",
        "fix             grainid all property/atom mol ghost yes",
        "read_data       data.grains fix grainid NULL Molecules",
        "neighbor        %.9g bin" % skin,
        "# spheres of one grain never interact",
        "neigh_modify    delay 0 every 1 check yes exclude molecule/intra all",
        "# F = k_n delta n - m_eff gamma_n v_n - (k_t xi + m_eff gamma_t v_t), |F_t| <= mu |F_n|; m_eff from the",
        "# rigid-body masses, so gamma = c / m_eff with our c_n = 2 zeta sqrt(k_n m_eff), c_t = c_n / 2 (dampflag 1)",
        "pair_style      gran/hooke/history %s %s %s %s %s 1" % (kn, kt, p["gamma_n_pair"], p["gamma_t_pair"], mu),
        "pair_coeff      * *",
        "timestep        %s" % dt,
        "# mass, centre of mass and inertia of each grain from the solid polyhedron (overlapping spheres would be wrong)",
        "fix             bodies all rigid/small molecule infile bodies.rigid",
        "# walls: the top one is a plane region whose normal points into the sample, moved by -v t",
        "variable        top_shift equal -%s*elapsed*%s" % (p["top_speed"], dt),
        "region          zhi plane 0 0 %s 0 0 -1 side in units box move NULL NULL v_top_shift" % p["wall_zhi"],
    ]
    if walls == "region":
        lines += [
            "region          xlo plane %s 0 0  1 0 0 side in units box" % p["wall_xlo"],
            "region          xhi plane %s 0 0 -1 0 0 side in units box" % p["wall_xhi"],
            "region          zlo plane 0 0 %s 0 0  1 side in units box" % p["wall_zlo"],
        ]
        for w in ("xlo", "xhi", "zlo"):
            lines.append("fix             wall_%s all wall/gran/region %s region %s%s" % (w, wall_law, w, contacts))
    else:
        lines += [
            "fix             wall_xlo all wall/gran %s xplane %s NULL%s" % (wall_law, p["wall_xlo"], contacts),
            "fix             wall_xhi all wall/gran %s xplane NULL %s%s" % (wall_law, p["wall_xhi"], contacts),
            "fix             wall_zlo all wall/gran %s zplane %s NULL%s" % (wall_law, p["wall_zlo"], contacts),
        ]
    lines.append("fix             wall_zhi all wall/gran/region %s region zhi%s" % (wall_law, contacts))
    if with_forces:
        # Column 2..4 of the per-atom contact array: the wall's force on the sphere (x, y, z).
        lines += [
            "compute         f_xlo all reduce sum f_wall_xlo[2]",
            "compute         f_xhi all reduce sum f_wall_xhi[2]",
            "compute         f_zlo all reduce sum f_wall_zlo[4]",
            "compute         f_zhi all reduce sum f_wall_zhi[4]",
            "fix             forces all ave/time %d 1 %d c_f_xlo c_f_xhi c_f_zlo c_f_zhi file %s format \" %%.12g\"" % (every, every, forces_file),
        ]
    lines += [
        "thermo_style    custom step",
        "thermo          %d" % max(steps, 1),
        "run             %d" % steps,
    ]
    return "\n".join(lines) + "\n"


def lammps_loop(log_path):
    """(loop seconds, procs, steps, atoms) from a LAMMPS log."""
    with open(log_path) as f:
        text = f.read()
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    if not m:
        die("no 'Loop time' line in " + log_path)
    return float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))


def read_ours(path):
    with open(path) as f:
        return {int(r["step"]): [float(r["f_xlo"]), float(r["f_xhi"]), float(r["f_zlo"]), float(r["f_zhi"])] for r in csv.DictReader(f)}


def read_lammps_forces(path):
    out = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            # LAMMPS reports the force on the spheres; the force on the wall is its opposite.
            out[int(v[0])] = [-float(x) for x in v[1:5]]
    return out


def compare(ours, theirs, threshold):
    """Per wall: (max relative difference over records with |F| >= threshold max|F|, records tested, max |F|)."""
    steps = sorted(set(ours) & set(theirs))
    result = []
    for w in range(4):
        fmax = max(abs(ours[s][w]) for s in steps)
        worst, n = 0.0, 0
        for s in steps:
            fo, fl = ours[s][w], theirs[s][w]
            if fmax > 0 and abs(fo) >= threshold * fmax:
                worst = max(worst, abs(fl - fo) / abs(fo))
                n += 1
        result.append((worst, n, fmax))
    return steps, result


def parse_result(stdout_path):
    with open(stdout_path) as f:
        for line in f:
            if line.startswith("RESULT "):
                return {k: v for k, v in (kv.split("=") for kv in line.split()[1:])}
    die("no RESULT line in " + stdout_path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--record-every", type=int, default=20)
    ap.add_argument("--grains", type=int, default=6, help="grains per side of the block (K^3 grains)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "lammps_compare"))
    ap.add_argument("--lmp-skin", type=float, default=0.1, help="LAMMPS neighbour skin in sphere diameters")
    ap.add_argument("--tolerance", type=float, default=0.01, help="max relative difference of the top-wall force")
    ap.add_argument("--threshold", type=float, default=0.1, help="records tested: |F| >= threshold x max |F|")
    ap.add_argument("--no-mpi", action="store_true", help="skip the 2-rank LAMMPS and 2-thread granulab runs")
    ap.add_argument("--repeat", type=int, default=1, help="timing runs per configuration; the fastest is reported")
    ap.add_argument("--lmp-walls", choices=["plane", "region"], default="plane",
                    help="LAMMPS fixed walls as fix wall/gran planes (faster) or as wall/gran/region regions")
    args = ap.parse_args()

    bench = os.path.join(ROOT, os.environ.get("BUILD", "build"), "bench", "bench_compare")
    if not os.access(bench, os.X_OK):
        die("%s not found: build it first with `make build` (or cmake --build build --target bench_compare)" % bench)
    ensure_lammps()
    mpirun = shutil.which("mpirun")
    two = not args.no_mpi
    ncpu = os.cpu_count() or 1

    out = os.path.abspath(args.out)
    lmp_dir = os.path.join(out, "lammps")
    os.makedirs(lmp_dir, exist_ok=True)
    load = os.getloadavg()[0]
    print("machine: %d CPUs, load average %.2f before the runs%s" % (ncpu, load,
          " (other work is running: timings on all cores are contended)" if load > 0.5 else ""))

    # 1. granulab: inputs for LAMMPS, forces and timing.
    common = ["--grains", str(args.grains), "--steps", str(args.steps), "--record-every", str(args.record_every)]
    rows = []  # (code, cores, sphere-steps/s, peak RSS MiB)
    ours_forces = {}
    for threads in ([1, 2] if two else [1]):
        forces = os.path.join(out, "granulab_forces_t%d.csv" % threads)
        best, best_rss = 0.0, 0.0
        for k in range(args.repeat):
            cmd = [bench, "--threads", str(threads), "--forces", forces] + common
            if threads == 1 and k == 0:
                cmd += ["--write-lammps", lmp_dir]
            log = os.path.join(out, "granulab_t%d.r%d.log" % (threads, k + 1))
            print("running:", " ".join(cmd))
            # Passive OpenMP waiting, as the granulab CLI sets it (spinning threads are slow on shared cores).
            env = dict(os.environ, OMP_NUM_THREADS=str(threads))
            env.setdefault("OMP_WAIT_POLICY", "passive")
            _, rss = run_measured(cmd, log, env=env)
            best = max(best, float(parse_result(log)["sphere_steps_per_s"]))
            best_rss = max(best_rss, rss)
        rows.append(("granulab", threads, best, best_rss))
        ours_forces[threads] = read_ours(forces)
    params = read_params(os.path.join(lmp_dir, "params.txt"))
    skin = args.lmp_skin * float(params["diameter"])

    # 2. LAMMPS input scripts.
    with open(os.path.join(lmp_dir, "in.forces"), "w") as f:
        f.write(lammps_input(params, skin, True, "lammps_forces.txt", args.lmp_walls))
    with open(os.path.join(lmp_dir, "in.timing"), "w") as f:
        f.write(lammps_input(params, skin, False, None, args.lmp_walls))

    # 3. LAMMPS runs (in lmp_dir: the input refers to its files by name).
    env = dict(os.environ, OMP_NUM_THREADS="1")
    os.chdir(lmp_dir)
    runs = [("forces", 1, 1, ["lmp", "-in", "in.forces", "-log", "log.forces", "-screen", "none"])]
    for k in range(args.repeat):
        runs.append(("timing", 1, k + 1, ["lmp", "-in", "in.timing", "-log", "log.timing.np1.r%d" % (k + 1), "-screen", "none"]))
    if two and mpirun:
        extra = ["--allow-run-as-root"] if os.geteuid() == 0 else []
        if ncpu < 2:
            extra.append("--oversubscribe")
        for k in range(args.repeat):
            runs.append(("timing", 2, k + 1, [mpirun] + extra + ["-np", "2", "lmp", "-in", "in.timing", "-log",
                                                               "log.timing.np2.r%d" % (k + 1), "-screen", "none"]))
    elif two:
        print("mpirun not found: no 2-rank LAMMPS run")
    lammps_rate, lammps_rss = {}, {}
    for kind, ranks, rep, cmd in runs:
        print("running:", " ".join(cmd))
        _, rss = run_measured(cmd, os.path.join(lmp_dir, "stdout.%s.np%d.r%d" % (kind, ranks, rep)), env=env)
        loop, procs, steps, atoms = lammps_loop(cmd[cmd.index("-log") + 1])
        rate = atoms * steps / loop
        if kind == "forces":
            forces_rate = rate
        else:
            lammps_rate[ranks] = max(lammps_rate.get(ranks, 0.0), rate)
            lammps_rss[ranks] = max(lammps_rss.get(ranks, 0.0), rss)
    for ranks in sorted(lammps_rate):
        rows.append(("LAMMPS", ranks, lammps_rate[ranks], lammps_rss[ranks]))

    # 4. Force agreement.
    theirs = read_lammps_forces(os.path.join(lmp_dir, "lammps_forces.txt"))
    steps, res = compare(ours_forces[1], theirs, args.threshold)
    names = ["xlo (side, fixed)", "xhi (side, fixed)", "zlo (bottom, fixed)", "zhi (top, moving)"]
    print("\nwall forces, %d common records (every %d steps, %d steps):" % (len(steps), args.record_every, args.steps))
    print("  %-20s %12s %10s %22s" % ("wall", "max |F| (N)", "records", "max rel. difference"))
    for name, (worst, n, fmax) in zip(names, res):
        print("  %-20s %12.4g %10d %21.3g%%" % (name, fmax, n, 100 * worst))
    top_worst = res[3][0]
    agree = top_worst < args.tolerance and res[3][1] > 0
    print("top-wall force agreement: max relative difference %.3g%% over the %d records with |F| >= %.0f%% of max -> %s "
          "(tolerance %.3g%%)" % (100 * top_worst, res[3][1], 100 * args.threshold, "PASS" if agree else "FAIL", 100 * args.tolerance))
    with open(os.path.join(out, "forces_side_by_side.csv"), "w") as f:
        f.write("step,ours_xlo,lmp_xlo,ours_xhi,lmp_xhi,ours_zlo,lmp_zlo,ours_zhi,lmp_zhi\n")
        for s in steps:
            f.write("%d,%s\n" % (s, ",".join("%.9g,%.9g" % (ours_forces[1][s][w], theirs[s][w]) for w in range(4))))
    if 2 in ours_forces:
        same = all(ours_forces[1][s] == ours_forces[2][s] for s in ours_forces[1])
        print("granulab 1 vs 2 threads: wall-force records %s" % ("bit-identical" if same else "DIFFER"))

    # 5. Speed table.
    print("\n%s spheres, %d steps; sphere-steps/s over the stepping only (LAMMPS: its 'Loop time'), best of %d" % (params["spheres"], args.steps, args.repeat))
    print("%-10s %14s %16s %20s %14s" % ("code", "ranks/threads", "sphere-steps/s", "ratio to LAMMPS", "peak RSS MiB"))
    for code, cores, rate, rss in rows:
        ratio = "%.2f" % (rate / lammps_rate[cores]) if cores in lammps_rate else "-"
        print("%-10s %14d %16.4g %20s %14.0f" % (code, cores, rate, ratio, rss))
    print("(LAMMPS run with wall-force output on 1 rank: %.4g sphere-steps/s; peak RSS of the 2-rank run is the "
          "largest single rank)" % forces_rate)
    with open(os.path.join(out, "speed.csv"), "w") as f:
        f.write("code,cores,sphere_steps_per_s,ratio_to_lammps,peak_rss_mib\n")
        for code, cores, rate, rss in rows:
            f.write("%s,%d,%.6g,%s,%.1f\n" % (code, cores, rate, "%.4f" % (rate / lammps_rate[cores]) if cores in lammps_rate else "", rss))
    print("files: %s" % out)
    return 0 if agree else 1


if __name__ == "__main__":
    sys.exit(main())

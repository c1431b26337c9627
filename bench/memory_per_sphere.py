#!/usr/bin/python3
"""Peak and steady memory of `granulab run` per sphere, for the admission estimate of granulabd's
--max-memory (server/budget). Runs the reference crystal's spec at several sizes, each in a fresh
process, samples /proc/PID/status while it builds the sample and starts confining, then stops it.

usage: bench/memory_per_sphere.py [build/granulab] [--seconds S] [--large]
Prints one line per size: spheres, peak (VmHWM) and steady (VmRSS) bytes, and bytes per sphere.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = next((a for a in sys.argv[1:] if not a.startswith("--")), os.path.join(ROOT, "build", "granulab"))
SECONDS = float(sys.argv[sys.argv.index("--seconds") + 1]) if "--seconds" in sys.argv else 20.0
# (grains_x, rows_z, layers_y, edge_spheres): the reference crystal (841,536 spheres) and around it.
# Many small grains weigh more per sphere (each grain is a rigid body with its own state): N_e = 3 too.
SIZES = [(4, 9, 3, 10), (8, 18, 3, 10), (8, 18, 6, 10), (16, 18, 6, 10), (16, 36, 6, 10),
         (20, 50, 10, 3), (40, 100, 10, 3), (40, 100, 20, 3)]

if "--large" in sys.argv:  # the largest crystal the spec allows: 1,000,000 grains, 50,000,000 spheres (~7 GB)
    SIZES = [(50, 400, 50, 3)]


def spheres_per_grain(base, ne, tmp):
    """From the engine itself: a 2 x 2 x 1 crystal run to the end, its summary's sphere count / 4."""
    spec = dict(base, crystal={"grains_x": 2, "rows_z": 2, "layers_y": 1},
                loading=dict(base["loading"], max_strain=1e-5, rate_number=1e-2),
                output={"curve_points": 1, "snapshot_strains": []})
    spec["grain"] = dict(base["grain"], edge_spheres=ne)
    path, out = os.path.join(tmp, "one.json"), os.path.join(tmp, "one")
    with open(path, "w") as f:
        json.dump(spec, f)
    subprocess.run([CLI, "run", path, "--out", out, "--threads", "1", "--quiet"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)["spheres"] // 4


def status_kib(pid, key):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


def main():
    with open(os.path.join(ROOT, "examples", "crystal_ref_p60.json")) as f:
        base = json.load(f)
    print("grains,spheres,peak_bytes,steady_bytes,peak_bytes_per_sphere,steady_bytes_per_sphere")
    with tempfile.TemporaryDirectory() as tmp:
        for gx, rz, ly, ne in SIZES:
            spec = dict(base, crystal={"grains_x": gx, "rows_z": rz, "layers_y": ly})
            spec["grain"] = dict(base["grain"], edge_spheres=ne)
            path = os.path.join(tmp, "spec.json")
            with open(path, "w") as f:
                json.dump(spec, f)
            proc = subprocess.Popen([CLI, "run", path, "--out", os.path.join(tmp, "out"), "--threads", "1"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            peak = steady = 0
            start = time.time()
            try:
                while time.time() - start < SECONDS and proc.poll() is None:
                    peak = max(peak, status_kib(proc.pid, "VmHWM"))
                    steady = status_kib(proc.pid, "VmRSS")
                    time.sleep(0.05)
            except FileNotFoundError:
                pass
            proc.kill()
            proc.communicate()
            spheres = gx * rz * ly * spheres_per_grain(base, ne, tmp)
            print(f"{gx * rz * ly},{spheres},{peak * 1024},{steady * 1024},{peak * 1024 / max(spheres, 1):.0f},"
                  f"{steady * 1024 / max(spheres, 1):.0f}", flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""What a checkpoint costs in memory and on disk, over size (bench/README.md, "Checkpoint memory").

    /usr/bin/python3 bench/checkpoint_memory.py [build/granulab] [--seconds S] [--sizes a,b,...]

For each crystal size, the reference crystal's spec (examples/crystal_ref_p60.json, made smaller or larger)
runs in a fresh `granulab run` process for S seconds from its start (default 90) and is then stopped:
once without checkpoints, once with `--checkpoint-seconds 1`, so that several checkpoints are written
(and the first is read back by a resumed third run, for the restore's peak). /proc/PID/status is sampled
every 20 ms: the peak (VmHWM) of each run, the largest checkpoint file and the resumed run's peak.
Prints one CSV line per size: spheres, checkpoint bytes and bytes per sphere, the three peaks and what
checkpoints add to the peak, in MB and as a fraction of the run's own.
Standard library only.
"""
import glob
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARGS = sys.argv[1:]
POSITIONAL = [a for i, a in enumerate(ARGS) if not a.startswith("--") and (i == 0 or not ARGS[i - 1].startswith("--"))]
CLI = POSITIONAL[0] if POSITIONAL else os.path.join(ROOT, "build", "granulab")
SECONDS = float(ARGS[ARGS.index("--seconds") + 1]) if "--seconds" in ARGS else 90.0
# (grains_x, rows_z, layers_y, edge_spheres): from 1e5 to 5e6 spheres at the reference's N_e = 10 (974 spheres
# a grain: 841,536 spheres / 864 grains), and the largest crystal the spec allows, 1,000,000 grains of N_e = 3
# (50 spheres each, 5e7 spheres; give it --seconds 300: it takes minutes to build).
SPHERES_PER_GRAIN = {10: 974, 3: 50}
SIZES = {"0.1M": (4, 9, 3, 10), "0.4M": (8, 18, 3, 10), "0.8M": (8, 18, 6, 10), "1.7M": (16, 18, 6, 10),
         "3.4M": (16, 36, 6, 10), "5.1M": (16, 36, 9, 10), "50M": (50, 400, 50, 3)}
CHOSEN = ARGS[ARGS.index("--sizes") + 1].split(",") if "--sizes" in ARGS else list(SIZES)[:-1]


def status_kib(pid, key):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def watch(argv, seconds, checkpoint_dir=None):
    """Runs argv for `seconds` from its start (or until it ends): (peak bytes, largest file in checkpoint_dir)."""
    log = tempfile.TemporaryFile()
    p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=log)
    peak, largest, started = 0, 0, time.time()
    try:
        while p.poll() is None and time.time() - started < seconds:
            peak = max(peak, status_kib(p.pid, "VmHWM") * 1024)
            if checkpoint_dir:
                for f in glob.glob(os.path.join(checkpoint_dir, "*")):
                    try:
                        largest = max(largest, os.path.getsize(f))
                    except OSError:
                        pass
            time.sleep(0.02)
        peak = max(peak, status_kib(p.pid, "VmHWM") * 1024)
    finally:
        if p.poll() is None:
            p.send_signal(signal.SIGKILL)
        p.wait()
    return peak, largest


def main():
    with open(os.path.join(ROOT, "examples", "crystal_ref_p60.json")) as f:
        base = json.load(f)
    print("size,spheres,checkpoint_bytes,checkpoint_bytes_per_sphere,peak_without_mb,peak_with_mb,"
          "peak_resumed_mb,added_mb,added_fraction")
    for name in CHOSEN:
        gx, rz, ly, ne = SIZES[name]
        spec = dict(base, crystal={"grains_x": gx, "rows_z": rz, "layers_y": ly})
        spec["grain"] = dict(base["grain"], edge_spheres=ne)
        spec["output"] = {"curve_points": 2, "snapshot_strains": []}
        tmp = tempfile.mkdtemp(prefix="granulab-ckmem-")
        try:
            path = os.path.join(tmp, "spec.json")
            with open(path, "w") as f:
                json.dump(spec, f)
            run = [CLI, "run", path, "--threads", "2", "--quiet"]
            without, _ = watch(run + ["--out", os.path.join(tmp, "a")], SECONDS)
            cdir = os.path.join(tmp, "ck")
            with_ck, largest = watch(run + ["--out", os.path.join(tmp, "b"), "--checkpoint-dir", cdir,
                                            "--checkpoint-seconds", "1"], SECONDS, cdir)
            # The last checkpoint read back: a resumed run, stopped soon after its restore.
            resumed, _ = watch(run + ["--out", os.path.join(tmp, "b"), "--checkpoint-dir", cdir,
                                      "--checkpoint-seconds", "0", "--resume"], min(SECONDS, 30))
            spheres = gx * rz * ly * SPHERES_PER_GRAIN[ne]
            added = max(with_ck, resumed) - without
            print(f"{name},{spheres},{largest},{largest / spheres:.0f},{without / 1e6:.0f},{with_ck / 1e6:.0f},"
                  f"{resumed / 1e6:.0f},{added / 1e6:.0f},{added / without:.3f}", flush=True)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The Python package (clients/python) as a researcher installs and uses it (issue 53, part 1).

pip installs it into a fresh virtual environment with no index at all (PIP_NO_INDEX=1: a download attempt fails
the install), then a script run by that environment's interpreter from an empty folder (so only the installed copy
can be imported) drives a real granulabd on loopback with its own SQLite file: jobs are Futures that complete
through concurrent.futures.as_completed, callbacks fire, granulab.wait shows progress, a cancelled job's Future is
cancelled and the server says so; a sweep's frame has a row per job with the varied value as a column, its
curves come in each job's natural units (p0, %) and SI (kPa), a snapshot's grains as a table, pictures as SVG.
Exits 77 (a skip, said to ctest) when this Python has no venv or pip.
"""

import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import package_env  # noqa: E402

SCRIPT = r'''
import concurrent.futures, json, sys, threading, time
import granulab

assert "/env/lib/" in granulab.__file__, granulab.__file__  # the installed copy, not the checkout's
client = granulab.Client(sys.argv[1], poll=0.1)
tiny = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3}, "loading": {"rate_number": 1e-3},
        "output": {"curve_points": 10}}
slow = dict(tiny, loading={"rate_number": 1e-8}, output={"curve_points": 1})

# Three jobs, as Futures: as_completed yields each once, with its final status and summary.
jobs = [client.submit(dict(tiny, label="p%d" % i)) for i in range(3)]
assert all(isinstance(j, concurrent.futures.Future) for j in jobs)
called = []
lock = threading.Lock()
for j in jobs:
    j.add_done_callback(lambda f: (lock.acquire(), called.append(f.id), lock.release()))
seen = []
for job in concurrent.futures.as_completed(jobs, timeout=60):
    st = job.result()
    assert st["status"] == "succeeded" and st["id"] == job.id, st
    assert st["summary"]["steps"] > 0, st["summary"]
    assert job.progress == 1.0 and "succeeded" in repr(job), repr(job)
    seen.append(job.id)
assert sorted(seen) == sorted(j.id for j in jobs), (seen, jobs)
time.sleep(0.2)
assert sorted(called) == sorted(seen), (called, seen)

# granulab.wait: one display for several jobs (a plain line per change here: stderr is not a terminal).
more = [client.submit(dict(tiny, label="q%d" % i)) for i in range(2)]
done = granulab.wait(more, timeout=60)
assert all(j.done() and j.result()["status"] == "succeeded" for j in done)

# A job of minutes, cancelled: its Future is cancelled and the server says cancelled.
long_job = client.submit(slow)
assert not long_job.done()
assert long_job.cancel() is True
assert long_job.cancelled()
try:
    long_job.result(timeout=1)
    raise AssertionError("a cancelled job gave a result")
except concurrent.futures.CancelledError:
    pass
for _ in range(100):
    if client.status(long_job)["status"] == "cancelled":
        break
    time.sleep(0.1)
assert client.status(long_job)["status"] == "cancelled", client.status(long_job)

# A job cancelled behind the Future's back (on the server) is seen as cancelled by the watcher.
other = client.submit(slow)
client.cancel(other.id)
try:
    other.result(timeout=30)
    raise AssertionError("a job cancelled on the server gave a result")
except concurrent.futures.CancelledError:
    pass

# A sweep over p0 of a small crystal: one row per job with the varied value as a plain column, and the curves in
# natural units, each job's stresses over its own p0 (the deviator in p0 = the SI deviator / p0, strain in %).
crystal = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
           "crystal": {"grains_x": 2, "rows_z": 3, "layers_y": 2},
           "loading": {"max_strain": 0.01, "rate_number": 1e-3}, "output": {"curve_points": 10}}
pressures = [20e3, 40e3]
sweep = client.submit_sweep(crystal, {"loading.confining_pressure": pressures}, label="package p0")
assert isinstance(sweep, granulab.Sweep) and len(sweep.jobs) == 2
sweep.wait(timeout=120, progress=False)
frame = sweep.frame()
assert len(frame) == 2, frame
assert sorted(frame["confining_pressure"]) == pressures, frame.columns
assert list(frame["status"]) == ["succeeded"] * 2, frame
assert "first_yield_found" in frame.columns and "peak_deviator_over_p0" in frame.columns, list(frame.columns)
natural = sweep.curves(units="natural")
si = sweep.curves(units="si")
assert natural.attrs["units"]["deviator"] == "p0" and natural.attrs["units"]["strain"] == "%", natural.attrs
for job in sweep.jobs:
    raw = job.frame()  # every column, stored (SI: Pa)
    p0 = frame.loc[frame["job"] == job.id, "confining_pressure"].iloc[0]
    mine = natural[natural["job"] == job.id]
    assert len(mine) == len(raw) > 3, (len(mine), len(raw))
    for a, b in zip(mine["deviator"], raw["deviator"]):
        assert abs(a - b / p0) <= 1e-12 * max(1.0, abs(b / p0)), (a, b, p0)
    for a, b in zip(mine["strain"], raw["strain"]):
        assert abs(a - 100 * b) <= 1e-12, (a, b)
    kpa = si[si["job"] == job.id]["deviator"]
    assert all(abs(a - b / 1e3) <= 1e-9 * max(1.0, abs(b)) for a, b in zip(kpa, raw["deviator"]))
    # A snapshot's grains, one row per grain, integer ids; the server's pictures as SVG.
    snap = job.snapshot_frame(1)
    raw_snapshot = client.snapshot(job, 1)
    assert len(snap) == len(raw_snapshot["grains"]["x"]) and str(snap["id"].dtype).startswith("int")
    # Grain indices are JSON integers in every section (issue 53: they were floats, 2.0).
    for section in ("interfaces", "contact_network"):
        pairs = raw_snapshot.get(section, {"a": [], "b": []})
        assert all(type(v) is int for v in pairs["a"] + pairs["b"]), (section, pairs["a"][:3])
    assert len(raw_snapshot["interfaces"]["a"]) > 0
    assert "<svg" in job.curve_svg() and "<svg" in job.snapshot_svg(1)
assert "<svg" in sweep.curves_svg()._repr_svg_()

# The snapshots as a GSD trajectory (python3-gsd): a frame per snapshot, a particle per grain at the JSON's pose, and
# the shape a union of spheres that, placed by a grain's pose, lands on that grain's spheres in the sphere dump.
import gsd.hoomd
job = sweep.jobs[0]
path = job.write_gsd("crystal.gsd")
snaps = job.snapshots()
with gsd.hoomd.open(path, "rb") as trajectory:
    assert len(trajectory) == len(snaps), (len(trajectory), len(snaps))
    for frame, info in zip(trajectory, snaps):
        g = client.snapshot(job, info["index"])["grains"]
        n = len(g["x"])
        assert frame.particles.N == n and frame.configuration.step == client.snapshot(job, info["index"])["step"]
        for i in range(n):
            # GSD's HOOMD schema keeps positions and orientations in single precision (2^-24 relative).
            assert all(abs(a - b) < 1e-9 for a, b in zip(frame.particles.position[i], (g["x"][i], g["y"][i], g["z"][i])))
            assert all(abs(a - b) < 1e-7 for a, b in zip(frame.particles.orientation[i],
                                                          (g["qw"][i], g["qx"][i], g["qy"][i], g["qz"][i])))
        shape = frame.particles.type_shapes[0]
        assert shape["type"] == "SphereUnion" and len(shape["centers"]) == len(shape["diameters"]) > 8, shape["type"]
    # The last grain of the last snapshot: its sphere union, turned and placed, is its spheres in the sphere dump.
    from granulab.gsd_file import _rotate
    dump = client.snapshot_file(job, snaps[-1]["index"], "dump_spheres").splitlines()
    at = next(i for i, line in enumerate(dump) if line.startswith("ITEM: ATOMS"))
    names = dump[at].split()[2:]
    rows = [dict(zip(names, map(float, line.split()))) for line in dump[at + 1:]]
    mol = g["id"][-1] + 1
    want = sorted((r["x"], r["y"], r["z"]) for r in rows if int(r["mol"]) == mol)
    q = tuple(frame.particles.orientation[-1])
    x = frame.particles.position[-1]
    got = sorted(tuple(x[k] + v[k] for k in range(3)) for v in (_rotate(q, tuple(c)) for c in shape["centers"]))
    assert len(got) == len(want), (len(got), len(want))
    assert all(abs(a - b) < 1e-8 for p, w in zip(got, want) for a, b in zip(p, w)), (got[:2], want[:2])
print("package ok", json.dumps(seen))
'''


def main():
    missing = package_env.venv_missing(package_env.system_python())
    if missing:
        print("SKIPPED:", missing)
        return package_env.SKIP
    return package_env.run_with_package("granulab_pkg_", drive)


def drive(tmp, env_python, daemon):
    work = os.path.join(tmp, "work")
    os.mkdir(work)
    r = subprocess.run([env_python, "-c", SCRIPT, daemon.url], cwd=work, capture_output=True, text=True, timeout=240)
    print(r.stdout)
    print(r.stderr[-4000:])
    if r.returncode != 0 or "package ok" not in r.stdout:
        print("FAIL: the package's script")
        return 1
    if "2/2 jobs done, 100.0 %" not in r.stderr and "2.00/2 jobs" not in r.stderr:  # the line, or tqdm's
        print("FAIL: granulab.wait showed no progress line")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

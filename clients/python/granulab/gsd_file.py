"""A job's snapshots as a GSD trajectory (the HOOMD schema, which OVITO and freud read): a frame per snapshot, a
particle per grain at its centre with its orientation as a quaternion (w, x, y, z), and each grain's shape as the
union of its spheres (`SphereUnion`, in the grain's own frame), so that OVITO draws the grains themselves.

Needs python3-gsd (Debian) or the gsd package. The sphere union comes from the server's sphere-level dump of the
first snapshot (GET .../snapshots/{k}?format=dump_spheres: up to 1,000,000 spheres), taken back to the first
grain's frame; scaled grains (imperfections) get a type per scale.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, List, Tuple

if TYPE_CHECKING:
    from granulab.jobs import Job

__all__ = ["write_gsd"]

Vec = Tuple[float, float, float]


def _rotate(q: Tuple[float, float, float, float], v: Vec) -> Vec:
    """v turned by the unit quaternion q = (w, x, y, z)."""
    w, x, y, z = q
    # t = 2 q_vec x v; v' = v + w t + q_vec x t
    tx, ty, tz = 2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])
    return (v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx))


def _sphere_union(dump: str, grains: Dict[str, List[Any]]) -> Tuple[List[Vec], List[float]]:
    """The first grain's spheres in its own frame, unscaled: (centres, diameters), from a dump_spheres text."""
    lines = dump.splitlines()
    header = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS "))
    names = lines[header].split()[2:]
    col = {n: names.index(n) for n in ("mol", "x", "y", "z", "radius")}
    mol = int(grains["id"][0]) + 1  # the dump's molecule: the grain's id + 1, as LAMMPS counts
    pos = (grains["x"][0], grains["y"][0], grains["z"][0])
    q = (grains["qw"][0], grains["qx"][0], grains["qy"][0], grains["qz"][0])
    q_inv = (q[0], -q[1], -q[2], -q[3])
    scale = float(grains.get("scale", [1.0])[0])
    centres, diameters = [], []
    for line in lines[header + 1:]:
        f = line.split()
        if not f or int(float(f[col["mol"]])) != mol:
            continue
        d = (float(f[col["x"]]) - pos[0], float(f[col["y"]]) - pos[1], float(f[col["z"]]) - pos[2])
        local = _rotate(q_inv, d)
        centres.append((local[0] / scale, local[1] / scale, local[2] / scale))
        diameters.append(2 * float(f[col["radius"]]) / scale)
    if not centres:
        raise ValueError("the sphere dump holds no sphere of the first grain")
    return centres, diameters


def write_gsd(job: "Job", path: str) -> str:
    """Writes job's snapshots to `path` (.gsd); returns path. ImportError without gsd."""
    try:
        import gsd
        import gsd.hoomd
    except ImportError:
        raise ImportError("GSD files need gsd (Debian: python3-gsd)") from None
    snapshots = job.snapshots()
    if not snapshots:
        raise ValueError(f"job {job.id} has no snapshots")
    docs = [job.client.snapshot(job.id, s["index"]) for s in snapshots]
    first = docs[0]["grains"]
    centres, diameters = _sphere_union(job.client.snapshot_file(job.id, snapshots[0]["index"], "dump_spheres"), first)
    frame_class = getattr(gsd.hoomd, "Frame", None) or gsd.hoomd.Snapshot  # gsd 3 renamed Snapshot to Frame
    mode = "w" if int(gsd.__version__.split(".")[0]) >= 3 else "wb"
    reach = max(max(abs(c) for c in centre) + d / 2 for centre, d in zip(centres, diameters))
    with gsd.hoomd.open(path, mode) as trajectory:
        for doc in docs:
            g = doc["grains"]
            n = len(g["x"])
            scales = [float(v) for v in g.get("scale", [1.0] * n)]
            kinds = sorted(set(scales), reverse=True)
            frame = frame_class()
            frame.configuration.step = int(doc.get("step", 0))
            # A box centred on the origin holding every grain whole (the crystal is not periodic).
            extent = max(max(abs(v) for v in g[a]) for a in ("x", "y", "z")) if n else 0.0
            side = 2 * (extent + reach)
            frame.configuration.box = [side, side, side, 0, 0, 0]
            frame.particles.N = n
            frame.particles.types = ["grain" if s == 1 else f"grain_scale_{s:g}" for s in kinds]
            frame.particles.typeid = [kinds.index(s) for s in scales]
            frame.particles.position = [[g["x"][i], g["y"][i], g["z"][i]] for i in range(n)]
            frame.particles.orientation = [[g["qw"][i], g["qx"][i], g["qy"][i], g["qz"][i]] for i in range(n)]
            frame.particles.diameter = [2 * reach * s for s in scales]
            frame.particles.type_shapes = [
                {"type": "SphereUnion", "centers": [[c * s for c in centre] for centre in centres],
                 "diameters": [d * s for d in diameters]} for s in kinds]
            trajectory.append(frame)
    return path

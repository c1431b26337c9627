#!/usr/bin/python3
"""A cohesive crystal's tensile strength against its surface energy, its law and its bag (docs/results.md, "Crystals
in tension").

usage: python3 examples/tension_sweep.py [--out DIR] [--threads N] [--reuse] [--binary build/granulab] [--full]

Runs examples/tension_dmt_ne4.json (a bare 4 x 4 x 6 slab of the paper's crystal, N_e = 4, confined at 100 Pa) with
`build/granulab run` for each case below into DIR/<name>/, and prints (and writes DIR/tension.csv) per run: the
tensile strength, the strain at failure, why the pull stopped, the failure plane (gap, where, share) and the wall
time. --full adds the paper's reference crystal (8 x 18 x 6 grains, N_e = 10) at gamma = 1 and 2 J/m^2. --reuse skips
runs whose summary.json exists. Standard library only.
"""
import argparse
import copy
import csv
import json
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def case(name, contact=None, loading=None, crystal=None, grain=None):
    return name, contact or {}, loading or {}, crystal or {}, grain or {}


CASES = [case(f"dmt_gamma{g}", {"surface_energy": g}) for g in (0.5, 1, 2, 4)] + [
    case("dmt_gamma2_mindlin", {"surface_energy": 2, "tangential": "mindlin"}),
    case("dmt_gamma4_mindlin", {"surface_energy": 4, "tangential": "mindlin"}),
    case("jkr_gamma1", {"normal": "jkr", "surface_energy": 1}),
    case("jkr_gamma2", {"normal": "jkr", "surface_energy": 2}),
    case("dmt_gamma2_R1e-7", {"surface_energy": 2}, {"rate_number": 1e-7}),
    case("dmt_gamma2_R1e-5", {"surface_energy": 2}, {"rate_number": 1e-5}),
    case("dmt_gamma2_bag_1kPa", {"surface_energy": 2}, {"confinement": "membrane", "confining_pressure": 1e3}),
    case("dmt_gamma2_bag_10kPa", {"surface_energy": 2}, {"confinement": "membrane", "confining_pressure": 1e4}),
    case("dmt_gamma2_one_layer_grips", {"surface_energy": 2}, {"grip_depth": 0}),
    case("hooke", {"normal": "hooke", "surface_energy": 0}, {"rate_number": 1e-6, "max_strain": 3e-4}),
    case("hertz_material", {"normal": "hertz/material", "surface_energy": 0}, {"rate_number": 1e-6, "max_strain": 3e-4}),
]
FULL = [case(f"full_dmt_gamma{g}", {"surface_energy": g}, {},
             {"grains_x": 8, "rows_z": 18, "layers_y": 6}, {"edge_spheres": 10}) for g in (1, 2)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="out/tension")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "granulab"))
    ap.add_argument("--full", action="store_true")
    args = ap.parse_args()
    with open(os.path.join(HERE, "tension_dmt_ne4.json")) as f:
        base = json.load(f)
    base["output"]["snapshot_strains"] = [0.0]
    rows = []
    for name, contact, loading, crystal, grain in CASES + (FULL if args.full else []):
        spec = copy.deepcopy(base)
        for section, changes in (("contact", contact), ("loading", loading), ("crystal", crystal), ("grain", grain)):
            spec.setdefault(section, {}).update(changes)
        spec["label"] = f"tension sweep: {name}"
        out = os.path.join(args.out, name)
        summary_path = os.path.join(out, "summary.json")
        if not (args.reuse and os.path.exists(summary_path)):
            os.makedirs(out, exist_ok=True)
            with open(os.path.join(out, "spec.json"), "w") as f:
                json.dump(spec, f, indent=2)
            cmd = [args.binary, "run", os.path.join(out, "spec.json"), "--out", out, "--quiet"]
            if args.threads:
                cmd += ["--threads", str(args.threads)]
            subprocess.run(cmd, check=True)
        with open(summary_path) as f:
            s = json.load(f)
        plane = s.get("failure_plane", {})
        rows.append({"run": name, "tensile_strength_kPa": round(s["tensile_strength"] / 1e3, 4),
                     "failure_strain": f'{s["failure_strain"]:.3e}', "stopped": s["stopped"],
                     "rate_number": f'{s["rate_number"]:.3g}', "failure_gap": plane.get("gap", ""),
                     "where": plane.get("where", ""), "share": round(plane.get("share", 0), 2),
                     "layers": s["layers"], "spheres": s["spheres"], "wall_seconds": round(s["wall_seconds"], 1)})
        print(rows[-1], flush=True)
    with open(os.path.join(args.out, "tension.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()

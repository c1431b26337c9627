#!/usr/bin/python3
"""How imperfect grains change the crystal's apparent modulus and first yield (README, "Imperfect grains").

usage: python3 examples/imperfection_sweep.py [--out DIR] [--threads N] [--reuse] [--binary build/granulab]

Runs examples/imperfections_ne4.json (the reference crystal at N_e = 4, 60 kPa, to 2 %) with `build/granulab run`
once perfect, then for each size_dispersion and each misorientation below (the other left at 0), into
DIR/<name>/, and prints (and writes DIR/imperfections.csv) per run: the apparent modulus (the summary's: the secant
between 10 % and 40 % of the first yield, or of the largest deviator when there is none, docs/model.md), the first
yield (summary's first_yield; none when the deviator never fell after its largest) and both over the perfect
crystal's. --reuse skips runs whose summary.json exists. Standard library only.
"""
import argparse
import csv
import json
import os
import subprocess

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SIZE_DISPERSIONS = [0.001, 0.002, 0.005, 0.01, 0.02]
MISORIENTATIONS = [0.25, 0.5, 1.0, 2.0, 4.0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default="out/imperfections")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--reuse", action="store_true")
    ap.add_argument("--binary", default=os.path.join(ROOT, "build", "granulab"))
    args = ap.parse_args()
    with open(os.path.join(HERE, "imperfections_ne4.json")) as f:
        base = json.load(f)
    runs = [("perfect", 0.0, 0.0)] + [(f"size_{s}", s, 0.0) for s in SIZE_DISPERSIONS] + \
           [(f"tilt_{m}", 0.0, m) for m in MISORIENTATIONS]
    table = []
    for name, size, tilt in runs:
        out = os.path.join(args.out, name)
        if not (args.reuse and os.path.exists(os.path.join(out, "summary.json"))):
            spec = json.loads(json.dumps(base))
            spec["imperfections"].update({"size_dispersion": size, "misorientation": tilt})
            spec["label"] = f"imperfections: size_dispersion {size}, misorientation {tilt} deg"
            os.makedirs(args.out, exist_ok=True)
            path = os.path.join(args.out, name + ".json")
            with open(path, "w") as f:
                json.dump(spec, f, indent=2)
            cmd = [args.binary, "run", path, "--out", out, "--quiet"]
            if args.threads:
                cmd += ["--threads", str(args.threads)]
            subprocess.run(cmd, check=True)
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        table.append({"run": name, "size_dispersion": size, "misorientation_deg": tilt,
                      "modulus_MPa": summary["apparent_modulus"].get("value", float("nan")) / 1e6,
                      "modulus_from_strain": summary["apparent_modulus"].get("from_strain", float("nan")),
                      "modulus_to_strain": summary["apparent_modulus"].get("to_strain", float("nan")),
                      "first_yield_reason": summary["first_yield"].get("reason", ""),
                      "first_yield_over_p0": summary["first_yield"].get("deviator_over_p0", float("nan")),
                      "first_yield_strain": summary["first_yield"].get("strain", float("nan")),
                      "confinement_steps": summary["confinement"]["steps"]})
    e0, y0 = table[0]["modulus_MPa"], table[0]["first_yield_over_p0"]
    for t in table:
        t["modulus_ratio"] = t["modulus_MPa"] / e0 if e0 else float("nan")
        t["yield_ratio"] = t["first_yield_over_p0"] / y0 if y0 else float("nan")
    with open(os.path.join(args.out, "imperfections.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    print(f"{'run':>10} {'E_app (MPa)':>12} {'/perfect':>9} {'window %':>13} {'yield/p0':>9} {'/perfect':>9} "
          f"{'at strain':>10}")
    for t in table:
        window = f"{100 * t['modulus_from_strain']:.3f}-{100 * t['modulus_to_strain']:.3f}"
        yield_text = (f"{t['first_yield_over_p0']:9.2f} {t['yield_ratio']:9.3f} {t['first_yield_strain']:10.5f}"
                      if t["first_yield_reason"] == "" else "  " + t["first_yield_reason"])
        print(f"{t['run']:>10} {t['modulus_MPa']:12.1f} {t['modulus_ratio']:9.3f} {window:>13} {yield_text}")


if __name__ == "__main__":
    main()

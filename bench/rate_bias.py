#!/usr/bin/python3
"""How far a crystal's curve moves with the loading rate (docs/results.md, "Quasi-static rate"):

    /usr/bin/python3 bench/rate_bias.py SPEC.json --ratios 0.5,1,2,5,10 [--reference 0.5] [--threads 1]
                                         [--out DIR] [--set key=value ...]

Runs the spec (with --set overrides, e.g. loading.confining_pressure=10e3) in-process with `granulab run` at
R = ratio x p0/E for each ratio, and prints, against the run at the reference ratio: the first yield, the
mean deviator over each strain window (weighted by strain: the curve integrated piecewise linearly), the
largest of those differences, and what each run's summary says of it (quasi_static.expected_bias, and its
measured platen imbalance and kinetic-to-elastic ratio). Runs already in DIR are reused.

Standard library only; build/granulab (or $GRANULAB).
"""
import argparse
import csv
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GRANULAB = os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab")
WINDOWS = [(0.0005, 0.0025), (0.0025, 0.005), (0.005, 0.01), (0.01, 0.015), (0.015, 0.02), (0.02, 0.03)]


def set_dotted(spec, dotted, value):
    keys = dotted.split(".")
    at = spec
    for k in keys[:-1]:
        at = at.setdefault(k, {})
    at[keys[-1]] = value


def window_mean(strain, deviator, lo, hi):
    """The strain-weighted mean of the deviator over [lo, hi], or None when the curve does not cover it."""
    if not strain or strain[-1] < hi:
        return None
    area = 0.0
    for k in range(1, len(strain)):
        a, b = max(lo, strain[k - 1]), min(hi, strain[k])
        if b <= a:
            continue
        def at(e):
            t = (e - strain[k - 1]) / (strain[k] - strain[k - 1])
            return deviator[k - 1] + t * (deviator[k] - deviator[k - 1])
        area += 0.5 * (at(a) + at(b)) * (b - a)
    return area / (hi - lo)


def run(spec, ratio, out, threads):
    folder = os.path.join(out, "ratio_%g" % ratio)
    summary = os.path.join(folder, "summary.json")
    if not os.path.exists(summary):
        loading = spec["loading"]
        p0 = loading.get("confining_pressure", 60e3)
        modulus = spec.get("material", {}).get("youngs_modulus", 3e9)
        one = json.loads(json.dumps(spec))
        one["loading"]["rate_number"] = ratio * p0 / modulus
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "spec.json"), "w") as f:
            json.dump(one, f)
        subprocess.run([GRANULAB, "run", os.path.join(folder, "spec.json"), "--out", folder, "--threads", str(threads),
                        "--quiet"], check=True)
    with open(summary) as f:
        s = json.load(f)
    with open(os.path.join(folder, "curve.csv")) as f:
        rows = list(csv.DictReader(f))
    strain = [float(r["strain"]) for r in rows]
    deviator = [float(r["deviator"]) for r in rows]
    return s, strain, deviator


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("spec")
    parser.add_argument("--ratios", default="0.5,1,2,5,10")
    parser.add_argument("--reference", type=float, default=0.5)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--out", default="out/rate_bias")
    parser.add_argument("--set", action="append", default=[], help="key=value (JSON value) applied to the spec")
    args = parser.parse_args()
    with open(args.spec) as f:
        spec = json.load(f)
    for item in args.set:
        key, value = item.split("=", 1)
        set_dotted(spec, key, json.loads(value))
    ratios = sorted(set([args.reference] + [float(r) for r in args.ratios.split(",")]))
    results = {r: run(spec, r, args.out, args.threads) for r in ratios}
    ref_summary, ref_strain, ref_dev = results[args.reference]
    p0 = ref_summary["spec"]["loading"]["confining_pressure"]
    ref_windows = [window_mean(ref_strain, ref_dev, lo, hi) for lo, hi in WINDOWS]
    ref_yield = ref_summary["first_yield"].get("deviator", float("nan"))
    head = ["R / (p0/E)", "steps", "first yield (p0)", "vs ref"] + [
        "%g-%g %%" % (100 * lo, 100 * hi) for lo, hi in WINDOWS] + [
        "largest |difference|", "expected_bias (summary)", "platen imbalance rms", "KE / EE mean"]
    print("| " + " | ".join(head) + " |")
    print("|" + " --- |" * len(head))
    for r in ratios:
        s, strain, dev = results[r]
        y = s["first_yield"].get("deviator", float("nan"))
        cells = ["%g" % r + (" (reference)" if r == args.reference else ""), "%d" % s["steps"], "%.3f" % (y / p0)]
        diffs = []
        cells.append("" if r == args.reference else "%+.2f %%" % (100 * (y / ref_yield - 1)))
        if r != args.reference:
            diffs.append(abs(y / ref_yield - 1))
        for (lo, hi), ref in zip(WINDOWS, ref_windows):
            m = window_mean(strain, dev, lo, hi)
            if m is None or ref is None or r == args.reference:
                cells.append("")
                continue
            cells.append("%+.2f %%" % (100 * (m / ref - 1)))
            diffs.append(abs(m / ref - 1))
        cells.append("%.2f %%" % (100 * max(diffs)) if diffs else "")
        q = s.get("quasi_static", {})
        cells.append("%.1f %%" % (100 * q["expected_bias"]) if "expected_bias" in q else "-")
        cells.append("%.2f %%" % (100 * q["platen_imbalance_rms"]) if "platen_imbalance_rms" in q else "-")
        cells.append("%.2g" % q["kinetic_elastic_mean"] if "kinetic_elastic_mean" in q else "-")
        print("| " + " | ".join(cells) + " |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()

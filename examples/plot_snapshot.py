#!/usr/bin/python3
"""Map one crystal snapshot in the x-z plane (the compression axis is z), coloured by a per-grain field.

usage: /usr/bin/python3 examples/plot_snapshot.py OUT_DIR/snapshots/snapshot_K.json
           [--field equivalent_strain|gamma_max|penetration_ratio] [--layer N] [-o map.png]

Every grain is a dot at its current (x, z); --layer keeps one {111} layer (0 = the front face, y lowest), found
from the reference positions. The server draws the same section without matplotlib: GET /v1/jobs/ID/snapshots/K.svg.
Needs matplotlib (Debian: python3-matplotlib, run with /usr/bin/python3).
"""
import argparse
import json


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("snapshot")
    ap.add_argument("--field", default="equivalent_strain",
                    choices=["equivalent_strain", "gamma_max", "penetration_ratio"])
    ap.add_argument("--layer", type=int)
    ap.add_argument("-o", "--output", default="snapshot.png")
    args = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = json.load(open(args.snapshot))
    g = s["grains"]
    # Layers from the reference positions (y - dy): grains of a deformed snapshot have left their plane.
    ref_y = [y - dy for y, dy in zip(g["y"], g["dy"])]
    lowest = min(ref_y)
    pairs = list(zip(s["interfaces"]["a"], s["interfaces"]["b"]))
    index = {int(gid): i for i, gid in enumerate(g["id"])}
    spacing = None
    if pairs:  # {111} layers are the neighbour distance times sqrt(2/3) apart
        d = sorted(((g["x"][index[int(a)]] - g["dx"][index[int(a)]] - g["x"][index[int(b)]] + g["dx"][index[int(b)]]) ** 2 +
                    (ref_y[index[int(a)]] - ref_y[index[int(b)]]) ** 2 +
                    (g["z"][index[int(a)]] - g["dz"][index[int(a)]] - g["z"][index[int(b)]] + g["dz"][index[int(b)]]) ** 2) ** 0.5
                   for a, b in pairs)
        spacing = d[len(d) // 2] * (2 / 3) ** 0.5
    layer_of = [round((y - lowest) / spacing) if spacing else 0 for y in ref_y]
    keep = [i for i in range(len(g["id"])) if args.layer is None or layer_of[i] == args.layer]
    fig, ax = plt.subplots(figsize=(4, 6.5))
    dots = ax.scatter([g["x"][i] for i in keep], [g["z"][i] for i in keep], c=[g[args.field][i] for i in keep],
                      s=60 if args.layer is not None else 25, cmap="viridis")
    fig.colorbar(dots, ax=ax, label=args.field)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m), compression axis")
    ax.set_title("strain %.3g%s" % (s["strain"], "" if args.layer is None else ", layer %d" % args.layer))
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(args.output)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Pressure and gap maps of every interface of a `jointhb run` output (the paper's Figs 7 and 8).

    /usr/bin/python3 cases/06-control-unit/plot_contact.py OUT_DIR

reads OUT_DIR/contact_<name>.csv (one row per integration point: x, y, z, pressure, gap, ...) and
writes OUT_DIR/contact_<name>.png: the normal pressure p_N [MPa] and the gap g_N [µm] over the
interface, seen from above (+z). Works for any interface lying in a plane z = const; points that
share a position (nodal integration: one per face corner) are averaged. Needs numpy and
matplotlib (Debian: python3-matplotlib).
"""
import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    acc = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            key = (round(float(r["x"]), 9), round(float(r["y"]), 9))
            s = acc.setdefault(key, [0.0, 0.0, 0])
            s[0] += float(r["pressure"])
            s[1] += float(r["gap"])
            s[2] += 1
    xs = np.array(sorted({k[0] for k in acc}))
    ys = np.array(sorted({k[1] for k in acc}))
    p = np.full((len(ys), len(xs)), np.nan)
    g = np.full_like(p, np.nan)
    ix = {x: i for i, x in enumerate(xs)}
    iy = {y: j for j, y in enumerate(ys)}
    for (x, y), (ps, gs, n) in acc.items():
        p[iy[y], ix[x]] = ps / n
        g[iy[y], ix[x]] = gs / n
    return xs, ys, p, g


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    files = sorted(glob.glob(os.path.join(out, "contact_*.csv")))
    if not files:
        sys.exit(f"no contact_*.csv in {out}")
    for path in files:
        name = os.path.basename(path)[len("contact_"):-len(".csv")]
        xs, ys, p, g = read(path)
        fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
        for ax, field, label, cmap in ((axes[0], p / 1e6, "pressure $p_N$ [MPa]", "viridis"),
                                       (axes[1], g * 1e6, "gap $g_N$ [µm] (< 0: closed)", "coolwarm")):
            kw = {}
            if cmap == "coolwarm":   # centre the diverging map on g_N = 0
                m = np.nanmax(np.abs(field))
                kw = {"vmin": -m, "vmax": m}
            im = ax.pcolormesh(xs * 1e3, ys * 1e3, field, shading="gouraud", cmap=cmap, **kw)
            ax.set_aspect("equal")
            ax.set_xlabel("x [mm]")
            ax.set_ylabel("y [mm]")
            ax.set_title(f"{name}: {label}")
            fig.colorbar(im, ax=ax, shrink=0.85)
        png = os.path.join(out, f"contact_{name}.png")
        fig.savefig(png, dpi=120)
        plt.close(fig)
        print(f"{png}: max pressure {np.nanmax(p) / 1e6:.3g} MPa, gap {np.nanmin(g) * 1e6:.3g} … "
              f"{np.nanmax(g) * 1e6:.3g} µm")


if __name__ == "__main__":
    main()

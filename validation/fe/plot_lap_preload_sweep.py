#!/usr/bin/python3
"""Plots the tables of jointhb_validate_fe_lap_preload_sweep.

usage: plot_lap_preload_sweep.py PREFIX   (reads PREFIX_sweep.csv, PREFIX_profile.csv and
                                           PREFIX_rings.csv; writes PREFIX.png)

Left: elastic modes 1..6, f / f_bonded against the preload per bolt (solid) and the closed-tied
reference / f_bonded (dashed). Middle: contact pressure along the centre line y = 15 mm. Right:
mean normal gap against the distance from the nearest bolt axis (rings).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    prefix = sys.argv[1]
    sweep = read(prefix + "_sweep.csv")
    profile = read(prefix + "_profile.csv")
    rings = read(prefix + "_rings.csv")

    fig, ax = plt.subplots(1, 3, figsize=(16, 4.8))
    preload = [float(r["preload_per_bolt_N"]) for r in sweep]
    for j in range(1, 7):
        ratio = [float(r[f"f{j}_over_bonded"]) for r in sweep]
        bonded = [float(r[f"f{j}_hz"]) / float(r[f"f{j}_over_bonded"]) for r in sweep]
        tied = [float(r[f"f{j}_closed_tied_hz"]) / b for r, b in zip(sweep, bonded)]
        line, = ax[0].semilogx(preload, ratio, "o-", label=f"mode {j} ({bonded[0]:.0f} Hz bonded)")
        ax[0].semilogx(preload, tied, "--", color=line.get_color())
    ax[0].axhline(1.0, color="k", lw=0.8)
    ax[0].axvspan(1e4, max(preload), color="0.92", zorder=0)
    ax[0].set_xlabel("preload per bolt [N] (shaded: beyond an M5 bolt's proof load)")
    ax[0].set_ylabel("f / f_bonded   (dashed: closed zone tied / f_bonded)")
    ax[0].set_title("elastic modes about the preloaded state")
    ax[0].legend(fontsize=7)

    shown = [1e2, 1e3, 5e3, 5e4, 1e6]
    for p in shown:
        rows = [r for r in profile if float(r["preload_per_bolt_N"]) == p]
        if not rows:
            continue
        x = [1e3 * float(r["x_m"]) for r in rows]
        pr = [max(float(r["pressure_Pa"]) / 1e6, 1e-6) for r in rows]
        ax[1].semilogy(x, pr, "o-", ms=3, label=f"{p:g} N")
    for xb in (70.0, 90.0):
        ax[1].axvspan(xb - 4.5, xb + 4.5, color="0.9", zorder=0)
    ax[1].set_ylim(1e-6, None)
    ax[1].set_xlabel("x [mm] on y = 15 mm (shaded: bolt footprints)")
    ax[1].set_ylabel("contact pressure [MPa] (floored at 1e-6)")
    ax[1].set_title("pressure along the centre line")
    ax[1].legend(fontsize=7)

    for p in shown:
        rows = [r for r in rings if float(r["preload_per_bolt_N"]) == p]
        if not rows:
            continue
        d = [500.0 * (float(r["d_min_m"]) + float(r["d_max_m"])) for r in rows]
        g = [1e6 * float(r["mean_gap_m"]) for r in rows]
        ax[2].plot(d, g, "o-", label=f"{p:g} N")
    ax[2].axhline(0.0, color="k", lw=0.8)
    ax[2].set_yscale("symlog", linthresh=1.0)
    ax[2].set_xlabel("distance from the nearest bolt axis [mm] (ring centre)")
    ax[2].set_ylabel("mean normal gap [µm] (> 0: opening)")
    ax[2].set_title("the interface opens away from the bolts")
    ax[2].legend(fontsize=7)

    fig.tight_layout()
    fig.savefig(prefix + ".png", dpi=110)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot the cost per Newton iteration from jointhb_validate_hb_cost.

Sample run:
    /usr/bin/python3 validation/hb/plot_cost.py validation/hb/results/cost

reads PREFIX_harmonics.csv and writes PREFIX.png: time per iteration (AFT, assembly, linear solve,
total) against H for the 1-DOF and the 10-DOF model, Gaul-Mayer (solid) and Jenkins (dashed).
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    with open(argv[1] + "_harmonics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), constrained_layout=True)
    parts = [("aft_s", "AFT", "C0"), ("assembly_s", "assembly", "C1"),
             ("solve_s", "linear solve", "C2"), ("total_s", "total", "k")]
    for ax, model in zip(axes, ("1dof", "10dof")):
        for law, style in (("gaul-mayer", "-"), ("jenkins", "--")):
            sel = [r for r in rows if r["model"] == model and r["law"] == law]
            h = np.array([float(r["H"]) for r in sel])
            for key, label, color in parts:
                t = np.array([float(r[key]) for r in sel]) * 1e6
                ax.loglog(h, t, style, marker="o", ms=3, color=color,
                          label=f"{label} ({law})")
        ax.set_xlabel("H (all harmonics kept: n(2H+1) unknowns)")
        ax.set_ylabel("time per Newton iteration [$\\mu$s]")
        ax.set_title(f"{model}, N$_t$ = 256, one thread")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.savefig(argv[1] + ".png", dpi=110)
    print(f"wrote {argv[1]}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

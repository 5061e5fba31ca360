#!/usr/bin/python3
"""Plot the tables of jointhb_validate_hb_epmc_ring_down.

Sample run:
    /usr/bin/python3 validation/hb/plot_epmc_ring_down.py validation/hb/results/epmc_ring_down

reads PREFIX_epmc.csv and PREFIX_cycles.csv and writes PREFIX.png: per case (columns) the
frequency, the damping ratio and the relative errors against log amplitude (peak of the modal
coordinate): EPMC curve (line) and ring-down two-cycle estimates (dots, scored ones filled), with
the library's fixed-centre per-cycle damping ratio for comparison.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

CASES = ["gm1", "jenkins1", "gm2m1", "gm2m2"]
TITLES = {
    "gm1": "1 DOF Gaul-Mayer",
    "jenkins1": "1 DOF Jenkins",
    "gm2m1": "2 DOF Gaul-Mayer, mode 1",
    "gm2m2": "2 DOF Gaul-Mayer, mode 2",
}


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def col(rows, key):
    return np.array([float(r[key]) for r in rows])


def main(prefix):
    curve = read(prefix + "_epmc.csv")
    cycles = read(prefix + "_cycles.csv")
    fig, axes = plt.subplots(3, 4, figsize=(18, 11), constrained_layout=True, sharex="col")
    for j, case in enumerate(CASES):
        c = [r for r in curve if r["case"] == case]
        y = [r for r in cycles if r["case"] == case]
        s = col(y, "scored") > 0
        a = col(y, "amplitude")
        ax = axes[0, j]
        ax.semilogx(col(c, "q_peak"), col(c, "omega"), "k-", label="EPMC (H = 7)")
        ax.semilogx(a[s], col(y, "omega")[s], ".", ms=3, label="ring-down, scored")
        ax.semilogx(a[~s], col(y, "omega")[~s], "x", ms=5, label="ring-down, not scored")
        ax.set_title(TITLES[case])
        ax.set_ylabel("$\\omega$ [rad/s]")
        ax = axes[1, j]
        ax.loglog(col(c, "q_peak"), col(c, "zeta"), "k-", label="EPMC")
        ax.loglog(a[s], col(y, "zeta")[s], ".", ms=3, label="ring-down (two-cycle, drift-free)")
        ax.loglog(a[~s], col(y, "zeta")[~s], "x", ms=5)
        ax.loglog(col(y, "lib_amplitude"), col(y, "lib_zeta"), ".", ms=1.5, alpha=0.5,
                  color="grey", label="ring-down, library $\\zeta_k$ (fixed centre)")
        ax.set_ylabel("$\\zeta$")
        ax = axes[2, j]
        ax.semilogx(a[s], np.abs(col(y, "err_omega")[s]) + 1e-16, ".", ms=3,
                    label="|rel. err. $\\omega$|")
        ax.semilogx(a[s], np.abs(col(y, "err_zeta")[s]) + 1e-16, ".", ms=3,
                    label="|rel. err. $\\zeta$|")
        ax.set_yscale("log")
        ax.set_xlabel("peak modal amplitude $\\hat q$ [$\\sqrt{kg}$ m]")
        ax.set_ylabel("relative error (scored)")
        for row in range(3):
            axes[row, j].grid(True, which="both", lw=0.3)
        if j == 0:
            for row in range(3):
                axes[row, j].legend(fontsize=7)
    fig.savefig(prefix + ".png", dpi=90)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: plot_epmc_ring_down.py PREFIX")
    main(sys.argv[1])

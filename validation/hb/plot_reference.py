#!/usr/bin/python3
"""Plots of the reference studies: harmonic balance vs time integration (time_domain_table.csv)
and vs Den Hartog's exact Coulomb solution (den_hartog_table.csv).

usage: plot_reference.py RESULTS_DIR   (writes time_domain.png and den_hartog.png there)
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main(directory):
    td = rows(os.path.join(directory, "time_domain_table.csv"))
    systems = sorted({r["system"] for r in td})
    fig, axes = plt.subplots(2, len(systems), figsize=(4.2 * len(systems), 6.5), squeeze=False)
    for j, name in enumerate(systems):
        for level in sorted({r["level"] for r in td if r["system"] == name}):
            sel = [r for r in td if r["system"] == name and r["level"] == level]
            om = [float(r["omega"]) for r in sel]
            force = float(sel[0]["force"])
            axes[0][j].plot(om, [float(r["x1_hb"]) / force for r in sel], "-",
                            label=f"HB, F = {force:g} N")
            axes[0][j].plot(om, [float(r["x1_ti"]) / force for r in sel], "o", mfc="none",
                            label=f"Newmark, F = {force:g} N")
            axes[1][j].semilogy(om, [float(r["err_x1"]) for r in sel], "o-",
                                label=f"fundamental, F = {force:g} N")
            axes[1][j].semilogy(om, [max(float(r["err_W"]), 1e-16) for r in sel], "s--",
                                label=f"W_D, F = {force:g} N")
        axes[0][j].set_title(name)
        axes[0][j].set_ylabel("|X1| / F  [m/N]")
        axes[1][j].set_xlabel("Ω [rad/s]")
        axes[1][j].set_ylabel("relative difference HB vs TI")
        axes[0][j].legend(fontsize=7)
        axes[1][j].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "time_domain.png"), dpi=110)

    dh = rows(os.path.join(directory, "den_hartog_table.csv"))
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for beta in sorted({r["beta"] for r in dh}, key=float):
        sel = [r for r in dh if r["beta"] == beta]
        ax.loglog([float(r["kappa"]) for r in sel], [float(r["err_x1"]) for r in sel], "o-",
                  label=f"β = {float(beta):g}")
    k = [10, 1e3]
    ax.loglog(k, [0.09 * (x / 10) ** -0.5 for x in k], "k:", label="slope −1/2")
    ax.set_xlabel("κ = k_T0 / k")
    ax.set_ylabel("relative error of the fundamental")
    ax.set_title("Jenkins → Coulomb: HB (H = 31) vs Den Hartog")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "den_hartog.png"), dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

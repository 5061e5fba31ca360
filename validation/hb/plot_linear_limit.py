#!/usr/bin/python3
"""Plot the tables of jointhb_validate_hb_linear_limit.

Sample run:
    /usr/bin/python3 validation/hb/plot_linear_limit.py validation/hb/results/linear_limit

reads PREFIX_jenkins.csv, PREFIX_gaul_mayer.csv, PREFIX_gaul_mayer_curves.csv and writes
    PREFIX_jenkins.png     stuck Jenkins contacts: |X_1| and the relative error against the complex
                           receptance at every point, default and tight continuation tolerance;
    PREFIX_gaul_mayer.png  Gaul-Mayer contacts: max deviation from the stuck receptance against the
                           force (slope 1), and the deviation along Omega against the first-order
                           prediction.
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(rows, key):
    return np.array([float(r[key]) for r in rows])


def plot_jenkins(prefix):
    rows = read(prefix + "_jenkins.csv")
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), constrained_layout=True)
    for model, color in (("1dof", "C0"), ("3dof", "C1")):
        tight = [r for r in rows if r["model"] == model and r["tolerance"] == "tight"]
        axes[0].semilogy(num(tight, "omega"), num(tight, "receptance"), "-", color=color,
                         label=f"{model}: receptance")
        axes[0].semilogy(num(tight, "omega"), num(tight, "amplitude_h1"), "o", color=color, ms=3,
                         mfc="none", label=f"{model}: trace_frf points")
        for tol, style in (("default", "s"), ("tight", "o")):
            sel = [r for r in rows if r["model"] == model and r["tolerance"] == tol]
            axes[1].semilogy(num(sel, "omega"), np.maximum(num(sel, "rel_err_h1"), 1e-17), style,
                             color=color, ms=3.5, mfc="none" if tol == "default" else color,
                             label=f"{model}, residual_tolerance {'1e-10' if tol == 'default' else '1e-14'}")
    axes[1].axhline(1e-12, color="k", ls=":", lw=1, label="bound (tight), 1e-12")
    axes[1].axhline(1e-9, color="grey", ls=":", lw=1, label="bound (default), 1e-9")
    axes[0].set_xlabel("$\\Omega$ [rad/s]")
    axes[0].set_ylabel("|X$_1$| of the output DOF")
    axes[0].set_title("Stuck Jenkins contacts, F = 0.01")
    axes[1].set_xlabel("$\\Omega$ [rad/s]")
    axes[1].set_ylabel("| |X$_1$| / |X$_{receptance}$| - 1 |  (zero drawn at 1e-17)")
    axes[1].set_title("Relative error against the complex receptance")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.savefig(prefix + "_jenkins.png", dpi=110)


def plot_gaul_mayer(prefix):
    rows = read(prefix + "_gaul_mayer.csv")
    curves = read(prefix + "_gaul_mayer_curves.csv")
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8), constrained_layout=True)
    for model, color in (("1dof", "C0"), ("3dof", "C1")):
        sel = [r for r in rows if r["model"] == model]
        f = num(sel, "force")
        d = num(sel, "max_deviation")
        axes[0].loglog(f, d, "o", color=color, label=f"{model}: measured")
        axes[0].loglog(f, num(sel, "predicted_max_deviation"), "-", color=color, lw=1,
                       label=f"{model}: first-order prediction")
    axes[0].set_xlabel("force amplitude F [N]  (\u03bcF$_N$ = 1)")
    axes[0].set_ylabel("max$_\\Omega$ | |X$_1$| / |X$_{stuck}$| - 1 |")
    axes[0].set_title("Gaul-Mayer (n = 1/3): deviation from the stuck receptance")
    forces = sorted({float(r["force"]) for r in curves})
    for force, color in zip(forces, plt.rcParams["axes.prop_cycle"].by_key()["color"]):
        sel = [r for r in curves if r["model"] == "1dof" and float(r["force"]) == force]
        w = num(sel, "omega")
        axes[1].plot(w, num(sel, "deviation") / force, "o", ms=3, color=color, mfc="none",
                     label=f"F = {force:.0e}: measured / F")
        axes[1].plot(w, num(sel, "predicted_deviation") / force, "-", lw=0.8, color=color)
    axes[1].set_xlim(1.7, 2.4)
    axes[1].set_xlabel("$\\Omega$ [rad/s]")
    axes[1].set_ylabel("( |X$_1$| / |X$_{stuck}$| - 1 ) / F")
    axes[1].set_title("1dof: deviation along $\\Omega$, scaled by F (lines: prediction)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.savefig(prefix + "_gaul_mayer.png", dpi=110)


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    plot_jenkins(argv[1])
    plot_gaul_mayer(argv[1])
    print(f"wrote {argv[1]}_jenkins.png, {argv[1]}_gaul_mayer.png")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

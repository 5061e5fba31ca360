#!/usr/bin/python3
"""Plot the tables of jointhb_validate_hb_convergence.

Sample run:
    /usr/bin/python3 validation/hb/plot_convergence.py validation/hb/results/convergence

reads PREFIX_harmonics.csv, PREFIX_reference.csv, PREFIX_samples.csv, PREFIX_runtime.csv and writes
    PREFIX_H.png        relative error of |X_1| and W_D against H (fixed Omega), with fitted rates;
    PREFIX_Nt.png       relative error of |X_1| against N_t and against N_t/(2H+2), reversal on a
                        sample (aligned), where the solution puts it (natural), half-way (half);
    PREFIX_runtime.png  relative error of the FRF peak against the wall time of trace_frf.
"""

import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

CASES = ["jenkins", "gm-micro", "gm-gross"]
TITLES = {
    "jenkins": "Jenkins, F = 1, $\\Omega$ = 1.15 (stick-slip)",
    "gm-micro": "Gaul-Mayer, F = 0.05, $\\Omega$ = 1.40 (microslip)",
    "gm-gross": "Gaul-Mayer, F = 1, $\\Omega$ = 1.15 (gross slip)",
}


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(rows, key):
    return np.array([float(r[key]) for r in rows])


def plot_harmonics(prefix):
    rows = read(prefix + "_harmonics.csv")
    ref = {r["case"]: r for r in read(prefix + "_reference.csv")}
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    for ax, case in zip(axes, CASES):
        sel = [r for r in rows if r["case"] == case]
        h = num(sel, "H")
        ea = num(sel, "rel_err_amplitude_h1")
        ew = num(sel, "rel_err_W_D")
        ax.loglog(h, ea, "o-", label="|X$_1$|")
        ax.loglog(h, ew, "s--", mfc="none", label="$W_D$")
        rate = float(ref[case]["rate_amplitude_h1"])
        fitted = [int(v) for v in ref[case]["fitted_H"].split()]
        if fitted:
            hf = np.array(fitted, dtype=float)
            i0 = list(h).index(hf[0])
            ax.loglog(hf, ea[i0] * (hf / hf[0]) ** (-rate), "k:",
                      label=f"fit H$^{{-{rate:.2f}}}$")
        floor = float(ref[case]["change_from_half_H_amplitude"])
        ax.axhline(floor, color="grey", lw=0.8, ls="-.",
                   label=f"reference floor (H={ref[case]['H_ref']} vs {int(ref[case]['H_ref']) // 2})")
        ax.set_xlabel("H (odd harmonics kept)")
        ax.set_ylabel("relative error vs reference")
        ax.set_title(TITLES[case], fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"Error vs H at fixed $\\Omega$, N$_t$ = {rows[0]['N_t']}, reversals on samples")
    fig.savefig(prefix + "_H.png", dpi=110)


def plot_samples(prefix):
    rows = read(prefix + "_samples.csv")
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5), constrained_layout=True)
    styles = {"aligned": "o-", "natural": "s-", "half": "^-"}
    colors = {"7": "C0", "15": "C1"}
    for col, case in enumerate(CASES):
        sel = [r for r in rows if r["case"] == case]
        for h in sorted({r["H"] for r in sel}, key=int):
            for variant, style in styles.items():
                s = [r for r in sel if r["H"] == h and r["variant"] == variant]
                n = num(s, "N_t")
                e = np.maximum(num(s, "rel_err_amplitude_h1"), 1e-16)
                kw = dict(color=colors.get(h, "C2"), ms=4, lw=0.9,
                          alpha=1.0 if variant != "natural" else 0.6)
                axes[0, col].loglog(n, e, style, label=f"H={h} {variant}", **kw)
                axes[1, col].loglog(n / (2 * int(h) + 2), e, style, label=f"H={h} {variant}", **kw)
        n = np.array([256.0, 32768.0])
        axes[0, col].loglog(n, 5e-5 * (n / 256.0) ** -2, "k:", lw=1, label="$N_t^{-2}$")
        axes[0, col].set_xlabel("N$_t$")
        axes[1, col].set_xlabel("N$_t$ / (2H + 2)")
        axes[0, col].set_title(TITLES[case], fontsize=10)
        for row in range(2):
            axes[row, col].set_ylabel("relative error of |X$_1$|")
            axes[row, col].grid(True, which="both", alpha=0.3)
        axes[0, col].legend(fontsize=7, ncol=2)
    fig.suptitle("Error vs N$_t$ at fixed H: reversal on a sample (aligned), where the solution "
                 "puts it (natural), half-way between samples (half)")
    fig.savefig(prefix + "_Nt.png", dpi=85)


def plot_runtime(prefix):
    rows = read(prefix + "_runtime.csv")
    cases = [c for c in CASES if any(r["case"] == c for r in rows)]
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4.6), squeeze=False,
                             constrained_layout=True)
    for ax, case in zip(axes[0], cases):
        sel = [r for r in rows if r["case"] == case]
        by_n = defaultdict(list)
        for r in sel:
            by_n[int(r["N_t"])].append(r)
        for n, s in sorted(by_n.items()):
            t = num(s, "seconds")
            e = num(s, "rel_err_peak_refined")
            ax.loglog(t, e, "o-", ms=4, label=f"N$_t$ = {n}")
            for r in s:
                if int(r["H"]) in (1, 7, 31) and n == max(by_n):
                    ax.annotate(f"H={r['H']}", (float(r["seconds"]), float(r["rel_err_peak_refined"])),
                                fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.loglog(num(sel, "seconds"), num(sel, "rel_err_peak_points"), "x", color="grey", ms=4,
                  label="highest accepted point")
        ax.set_xlabel("wall time of trace_frf [s] (best of the repetitions)")
        ax.set_ylabel("relative error of the peak |X$_1$|")
        ax.set_title(TITLES[case].split(",")[0] + f", F = {TITLES[case].split('F = ')[1].split(',')[0]}",
                     fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("FRF over $\\Omega$ in [0.8, 1.8]: error of the peak vs run time, H = 1...31")
    fig.savefig(prefix + "_runtime.png", dpi=110)


def main(argv):
    if len(argv) != 2:
        print(__doc__)
        return 2
    prefix = argv[1]
    plot_harmonics(prefix)
    plot_samples(prefix)
    plot_runtime(prefix)
    print(f"wrote {prefix}_H.png, {prefix}_Nt.png, {prefix}_runtime.png")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

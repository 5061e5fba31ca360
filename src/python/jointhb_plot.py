#!/usr/bin/python3
"""Plots of a `jointhb run` output directory (called by `jointhb run --plot`).

usage: jointhb_plot.py DIR

Reads DIR/frf.csv and/or DIR/backbone.csv (docs/cli.md) and writes
  DIR/frf.png       |fundamental| of the output DOF vs frequency, one curve per force level
  DIR/backbone.png  frequency and damping ratio vs modal amplitude (log axis), one curve per mode
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def plot_frf(directory):
    rows = read(os.path.join(directory, "frf.csv"))
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for level in sorted({r["level"] for r in rows}, key=float):
        sel = [r for r in rows if r["level"] == level]
        ax.semilogy([float(r["frequency_hz"]) for r in sel],
                    [float(r["amplitude_h1"]) for r in sel],
                    label=f"F = {float(sel[0]['force_amplitude']):g} N")
    ax.set_xlabel("excitation frequency [Hz]")
    ax.set_ylabel("|fundamental| of the output DOF [m]")
    ax.set_title("Nonlinear FRF (harmonic balance)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "frf.png"), dpi=120)
    return "frf.png"


def plot_backbone(directory):
    rows = read(os.path.join(directory, "backbone.csv"))
    # Finite-element damping curves also give the amplitude at an output DOF: a physical axis.
    physical = bool(rows) and "output_amplitude" in rows[0] and all(
        float(r["output_amplitude"]) > 0.0 for r in rows)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True)
    for i, mode in enumerate(sorted({r["mode"] for r in rows}, key=float)):
        sel = [r for r in rows if r["mode"] == mode]
        q = [float(r["output_amplitude" if physical else "amplitude"]) for r in sel]
        color = f"C{i}"
        name = f"mode {int(float(mode))}"
        top.semilogx(q, [float(r["frequency_hz"]) for r in sel], color=color, label=name)
        bottom.loglog(q, [float(r["damping_ratio"]) for r in sel], color=color,
                      label=f"{name}: ζ (EPMC, viscous + contacts)")
        bottom.loglog(q, [max(float(r["damping_ratio_energy"]), 1e-12) for r in sel], "--",
                      color=color, label=f"{name}: contacts only, W_D/(4πE)")
    top.set_ylabel("frequency [Hz]")
    top.set_title("Damping curves (EPMC)")
    bottom.set_ylabel("damping ratio ζ")
    bottom.set_xlabel("amplitude of the fundamental at the output [m]" if physical
                      else "modal amplitude q [m·√kg]")
    for ax in (top, bottom):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "backbone.png"), dpi=120)
    return "backbone.png"


def main(directory):
    written = []
    if os.path.exists(os.path.join(directory, "frf.csv")):
        written.append(plot_frf(directory))
    if os.path.exists(os.path.join(directory, "backbone.csv")):
        written.append(plot_backbone(directory))
    if not written:
        sys.exit(f"jointhb_plot: {directory} has neither frf.csv nor backbone.csv")
    print(" ".join(os.path.join(directory, w) for w in written))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

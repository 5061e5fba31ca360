#!/usr/bin/python3
"""Plots of a `jointhb run` output directory (called by `jointhb run --plot`).

usage: jointhb_plot.py DIR

Reads DIR/frf.csv and/or DIR/backbone.csv (docs/cli.md) and writes
  DIR/frf.png       |fundamental| of the output DOF vs frequency, one curve per force level;
                    with a `stable` column, unstable stretches dashed and bifurcations marked
                    (fold ▲, period doubling ■, Neimark–Sacker ◆, branch point ●, reversal ×)
  DIR/backbone.png  frequency and damping ratio vs modal amplitude (log axis), one curve per mode
  DIR/mode<k>_contact.png  for each DIR/mode<k>_contact_points.csv: the contact points' W_D per
                    unit area (colour, scaled per panel) at each field snapshot, one panel per
                    interface, open points crossed (plane of the points' two widest coordinates)
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


MARKERS = {"fold": "^", "period_doubling": "s", "neimark_sacker": "D", "branch_point": "o",
           "reversal": "x"}


def stretches(sel):
    """Consecutive runs of points with the same stability (1 stable, 0 unstable, -1 unknown),
    each run sharing its first point with the previous one so that the line is unbroken."""
    if "stable" not in sel[0]:
        return [(sel, True)]
    runs, start = [], 0
    for k in range(1, len(sel) + 1):
        if k == len(sel) or sel[k]["stable"] != sel[start]["stable"]:
            runs.append((sel[max(start - 1, 0):k], sel[start]["stable"] != "0"))
            start = k
    return runs


def plot_frf(directory):
    rows = read(os.path.join(directory, "frf.csv"))
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    marked = set()
    for i, level in enumerate(sorted({r["level"] for r in rows}, key=float)):
        sel = [r for r in rows if r["level"] == level]
        colour = colours[i % len(colours)]
        for j, (run, stable) in enumerate(stretches(sel)):
            ax.semilogy([float(r["frequency_hz"]) for r in run],
                        [float(r["amplitude_h1"]) for r in run], color=colour,
                        linestyle="-" if stable else "--",
                        label=f"F = {float(sel[0]['force_amplitude']):g} N" if j == 0 else None)
        for r in sel:
            kind = r.get("bifurcation", "none")
            if kind in MARKERS:
                ax.plot(float(r["frequency_hz"]), float(r["amplitude_h1"]), MARKERS[kind],
                        color=colour, markersize=6,
                        label=kind.replace("_", " ") if kind not in marked else None)
                marked.add(kind)
    if any(r.get("stable") == "0" for r in rows):
        ax.plot([], [], "k--", label="unstable")
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
        # The contacts' share ζ_c = W_D / (4π E), E = ½ Ω² q² (the rest is viscous).
        zeta_c = [float(r["W_D"]) / (2 * math.pi * (2 * math.pi * float(r["frequency_hz"])) ** 2
                                     * float(r["amplitude"]) ** 2) for r in sel]
        bottom.loglog(q, [max(z, 1e-12) for z in zeta_c], "--",
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


def plot_contact_fields(directory, name):
    rows = read(os.path.join(directory, name))
    snaps = sorted({int(float(r["snapshot"])) for r in rows})
    faces = sorted({int(float(r["interface"])) for r in rows})
    xyz = [[float(r[c]) for r in rows] for c in ("x", "y", "z")]
    spans = sorted(range(3), key=lambda c: max(xyz[c]) - min(xyz[c]), reverse=True)[:2]
    a, b = sorted(spans)
    width = (max(xyz[a]) - min(xyz[a])) / max(max(xyz[b]) - min(xyz[b]), 1e-300)
    panels = [(k, i) for k in snaps for i in faces]  # one panel per snapshot and interface
    cols = len(faces) if len(faces) > 1 else (2 if len(snaps) > 2 else 1)
    rows_n = (len(panels) + cols - 1) // cols
    panel_w = min(6.0, max(3.0, 2.2 * width))
    fig, axes = plt.subplots(rows_n, cols, figsize=(cols * (panel_w + 1.2), rows_n * (panel_w / max(width, 0.3) + 0.9)),
                             squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, (k, face) in zip(axes.flat, panels):
        sel = [r for r in rows if int(float(r["snapshot"])) == k and int(float(r["interface"])) == face]
        pa = [float(r["xyz"[a]]) * 1e3 for r in sel]
        pb = [float(r["xyz"[b]]) * 1e3 for r in sel]
        w = [float(r["dissipation"]) for r in sel]
        state = [float(r["state"]) for r in sel]
        sc = ax.scatter(pa, pb, c=w, vmin=0.0, vmax=max(w) or 1.0, cmap="viridis", s=28)
        opened = [(x, y) for x, y, s in zip(pa, pb, state) if s == 2]
        if opened:
            ax.scatter(*zip(*opened), marker="x", c="white", s=14, linewidths=0.8)
        r0 = sel[0]
        label = f"interface {face}: " if len(faces) > 1 else ""
        ax.set_title(f"{label}q = {float(r0['amplitude']):.3g}, f = {float(r0['frequency_hz']):.5g} Hz\n"
                     f"{sum(1 for s in state if s == 0)} stuck, {sum(1 for s in state if s == 1)} slipping, "
                     f"{sum(1 for s in state if s == 2)} open", fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlabel(f"{'xyz'[a]} [mm]", fontsize=8)
        ax.set_ylabel(f"{'xyz'[b]} [mm]", fontsize=8)
        ax.tick_params(labelsize=7)
        fig.colorbar(sc, ax=ax, shrink=0.85).set_label("W_D [J/m²/cycle]", fontsize=7)
    fig.tight_layout()
    out = name.replace("_contact_points.csv", "_contact.png")
    fig.savefig(os.path.join(directory, out), dpi=110)
    plt.close(fig)
    return out


def main(directory):
    written = []
    if os.path.exists(os.path.join(directory, "frf.csv")):
        written.append(plot_frf(directory))
    if os.path.exists(os.path.join(directory, "backbone.csv")):
        written.append(plot_backbone(directory))
    for name in sorted(os.listdir(directory)):
        if name.startswith("mode") and name.endswith("_contact_points.csv"):
            written.append(plot_contact_fields(directory, name))
    if not written:
        sys.exit(f"jointhb_plot: {directory} has neither frf.csv nor backbone.csv")
    print(" ".join(os.path.join(directory, w) for w in written))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

#!/usr/bin/python3
"""Plots of a `jointhb run` output directory (called by `jointhb run --plot`).

usage: jointhb_plot.py DIR

Reads DIR/frf.csv and/or DIR/backbone.csv (docs/cli.md) and writes
  DIR/frf.png       |fundamental| of the output DOF vs frequency, one curve per force level;
                    with a `stable` column, unstable stretches dashed and bifurcations marked
                    (fold ▲, period doubling ■, Neimark–Sacker ◆, branch point ●, reversal ×);
                    the peak (★) and folds (▶) located between the points, from summary.json
                    (`curves[]` or `frfs[]`: `peak`, `fold_points` where `refined`)
  DIR/backbone.png  frequency and damping ratio vs modal amplitude (log axis), one curve per mode,
                    and the share of the contact points per state (stuck … open) along the first
                    mode's curve (docs/theory.md §14)
  DIR/mode<k>_contact.png  for each DIR/mode<k>_contact_points.csv: the contact points' W_D per
                    unit area interpolated over the surface at each field snapshot, one panel per
                    interface, one logarithmic colour scale for the figure, the bolts' footprints
                    (dashed) and holes from summary.json, points gapping or open crossed (plane of
                    the points' two widest coordinates)
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors  # noqa: E402
import matplotlib.patches as mpatches  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402


# The codes of the contact points' `state` column (hb::ContactState, docs/theory.md §14).
STATE_NAMES = ((0, "stuck"), (1, "microslip"), (2, "gross slip"), (3, "gapping"), (4, "open"))
# The matching columns of backbone.csv (<name>_points).
STATE_COLUMNS = ("stuck", "microslip", "gross_slip", "gapping", "open")


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


def located_extrema(directory):
    """{level: (peak, folds)} of the extrema located between points (summary.json of a discrete
    FRF: `curves[]`, of a finite-element one: `frfs[]`), refined ones only: (frequency, amplitude)."""
    try:
        with open(os.path.join(directory, "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        return {}
    located = {}
    for curve in summary.get("curves", []) + summary.get("frfs", []):
        peak = curve.get("peak") or {}
        peak_at = (peak["frequency_hz"], peak["amplitude_h1"]) if peak.get("refined") else None
        folds = [(f["frequency_hz"], f["amplitude_h1"]) for f in curve.get("fold_points", []) if f.get("refined")]
        located[str(curve.get("level"))] = (peak_at, folds)
    return located


def plot_frf(directory):
    rows = read(os.path.join(directory, "frf.csv"))
    located = located_extrema(directory)
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
        peak, folds = located.get(level, (None, []))
        for (x, y), kind, marker in [(p, "peak (located)", "*") for p in ([peak] if peak else [])] + \
                [(f, "fold (located)", ">") for f in folds]:
            ax.plot(x, y, marker, color=colour, markersize=9 if marker == "*" else 6, markeredgecolor="k",
                    label=kind if kind not in marked else None)
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
    states = bool(rows) and all(f"{k}_points" in rows[0] for k in STATE_COLUMNS)
    fig, axes = plt.subplots(3 if states else 2, 1, figsize=(6.4, 8.8 if states else 6.4), sharex=True,
                             gridspec_kw={"height_ratios": [1, 1, 0.7] if states else [1, 1]})
    top, bottom = axes[0], axes[1]
    modes = sorted({r["mode"] for r in rows}, key=float)
    for i, mode in enumerate(modes):
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
    if states:
        # Share of the contact points per state along the first mode's curve (docs/theory.md §14).
        sel = [r for r in rows if r["mode"] == modes[0]]
        q = [float(r["output_amplitude" if physical else "amplitude"]) for r in sel]
        counts = [[float(r[f"{k}_points"]) for r in sel] for k in STATE_COLUMNS]
        total = [sum(c[j] for c in counts) or 1.0 for j in range(len(sel))]
        shares = [[c[j] / total[j] for j in range(len(sel))] for c in counts]
        axes[2].stackplot(q, *shares, labels=[name for _, name in STATE_NAMES],
                          colors=["#4c72b0", "#55a868", "#c44e52", "#8172b2", "#999999"], alpha=0.85)
        axes[2].set_xscale("log")
        axes[2].set_ylim(0.0, 1.0)
        axes[2].set_ylabel(f"contact points\n(mode {int(float(modes[0]))})")
    top.set_ylabel("frequency [Hz]")
    top.set_title("Damping curves (EPMC)")
    bottom.set_ylabel("damping ratio ζ")
    axes[-1].set_xlabel("amplitude of the fundamental at the output [m]" if physical
                        else "modal amplitude q [m·√kg]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="best" if ax is not axes[-1] or not states else "center left")
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "backbone.png"), dpi=120)
    return "backbone.png"


def bolt_footprints(directory):
    """The bolts' footprints from summary.json (centre, axis, hole and footprint radius [m]), or []."""
    try:
        with open(os.path.join(directory, "summary.json")) as f:
            bolts = json.load(f).get("preload", {}).get("bolts", [])
    except (OSError, ValueError):
        return []
    return [b for b in bolts if "center" in b and "footprint_radius" in b]


def merged_points(sel, a, b):
    """The panel's points with coincident ones (node pairs of nodal integration) merged: positions
    [mm] and the mean W_D and the highest state of each position."""
    merged = {}
    for r in sel:
        key = (round(float(r["xyz"[a]]) * 1e9), round(float(r["xyz"[b]]) * 1e9))
        m = merged.setdefault(key, [float(r["xyz"[a]]) * 1e3, float(r["xyz"[b]]) * 1e3, 0.0, 0, 0.0])
        m[2] += float(r["dissipation"])
        m[3] += 1
        m[4] = max(m[4], float(r["state"]))
    pts = list(merged.values())
    return ([p[0] for p in pts], [p[1] for p in pts], [p[2] / p[3] for p in pts], [p[4] for p in pts])


def surface_triangulation(pa, pb):
    """Delaunay triangles over the points, without those that bridge a hole or a gap between
    patches (an edge longer than 2.5 times the median edge)."""
    tri = mtri.Triangulation(pa, pb)
    edges = []
    for t in tri.triangles:
        edges.append(max(math.dist((pa[t[i]], pb[t[i]]), (pa[t[(i + 1) % 3]], pb[t[(i + 1) % 3]])) for i in range(3)))
    limit = 2.5 * sorted(edges)[len(edges) // 2]
    tri.set_mask([e > limit for e in edges])
    return tri


def plot_contact_fields(directory, name):
    """W_D per unit area interpolated over each contact surface (one panel per snapshot and
    interface), one logarithmic colour scale for the whole figure, bolt footprints drawn, points
    gapping or open crossed."""
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
    fig, axes = plt.subplots(rows_n, cols, figsize=(cols * panel_w + 1.4, rows_n * (panel_w / max(width, 0.3) + 0.9)),
                             squeeze=False, layout="constrained")
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    # One scale for every panel: six decades below the largest W_D (zero and less are shown at the
    # floor); linear from 0 when nothing dissipates (the linear limit only).
    top = max(float(r["dissipation"]) for r in rows)
    norm = mcolors.LogNorm(vmin=top * 1e-6, vmax=top) if top > 0.0 else mcolors.Normalize(0.0, 1.0)
    floor = top * 1e-6 if top > 0.0 else 0.0
    bolts = bolt_footprints(directory)
    mappable = None
    for ax, (k, face) in zip(axes.flat, panels):
        sel = [r for r in rows if int(float(r["snapshot"])) == k and int(float(r["interface"])) == face]
        pa, pb, w, state = merged_points(sel, a, b)
        shown = [max(v, floor) for v in w]
        if len(pa) >= 3:
            mappable = ax.tripcolor(surface_triangulation(pa, pb), shown, shading="gouraud", norm=norm, cmap="viridis")
        else:
            mappable = ax.scatter(pa, pb, c=shown, norm=norm, cmap="viridis", s=28)
        opened = [(x, y) for x, y, s in zip(pa, pb, state) if s >= 3]  # gapping or open
        if opened:
            ax.scatter(*zip(*opened), marker="x", c="white", s=14, linewidths=0.8)
        for bolt in bolts:
            centre = (bolt["center"][a] * 1e3, bolt["center"][b] * 1e3)
            for radius, style in ((bolt["footprint_radius"], "--"), (bolt.get("hole_radius", 0.0), "-")):
                if radius > 0.0:
                    ax.add_patch(mpatches.Circle(centre, radius * 1e3, fill=False, color="white", lw=0.9, ls=style))
        r0 = sel[0]
        states = [float(r["state"]) for r in sel]
        label = f"interface {face}: " if len(faces) > 1 else ""
        ax.set_title(f"{label}q = {float(r0['amplitude']):.3g}, f = {float(r0['frequency_hz']):.5g} Hz\n"
                     + ", ".join(f"{n} {name}" for code, name in STATE_NAMES
                                 if (n := sum(1 for s in states if s == code)) > 0) + " points",
                     fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlabel(f"{'xyz'[a]} [mm]", fontsize=8)
        ax.set_ylabel(f"{'xyz'[b]} [mm]", fontsize=8)
        ax.tick_params(labelsize=7)
    if mappable is not None:
        bar = fig.colorbar(mappable, ax=list(axes.flat), shrink=0.8)
        bar.set_label("W_D [J/m² per cycle]" + (" (log scale, shared)" if top > 0.0 else ""), fontsize=8)
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

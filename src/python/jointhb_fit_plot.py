#!/usr/bin/env python3
"""Draws DIR/fit.png from the outputs of `jointhb fit`: per target, the measured points, the
model at the start (dashed) and at the optimum (solid). Columns: docs/cli.md, "jointhb fit".

Usage: jointhb_fit_plot.py DIR
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

QUANTITY = {0: "frequency [Hz]", 1: "damping ratio", 2: "amplitude |x1|"}
KIND = {0: "backbone", 1: "frf", 2: "modal"}
ABSCISSA = {0: "modal amplitude q", 1: "frequency [Hz]", 2: "mode"}


def rows(path):
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def main(directory):
    points = rows(os.path.join(directory, "fit_curves.csv"))
    model = rows(os.path.join(directory, "fit_model_curves.csv"))
    panels = sorted({(int(p["target"]), int(p["quantity"])) for p in points})
    if not panels:
        return
    fig, axes = plt.subplots(len(panels), 1, figsize=(6.4, 3.0 * len(panels)), squeeze=False)
    for ax, (target, quantity) in zip(axes[:, 0], panels):
        mine = [p for p in points if int(p["target"]) == target and int(p["quantity"]) == quantity]
        kind = int(mine[0]["kind"])
        for at, style, label in ((0, "--", "start"), (1, "-", "fitted")):
            curve = [c for c in model if int(c["at"]) == at and int(c["target"]) == target
                     and int(c["quantity"]) == quantity]
            if curve:
                ax.plot([c["abscissa"] for c in curve], [c["value"] for c in curve], style,
                        label=label, marker="o" if kind == 2 else None)
        ax.plot([p["abscissa"] for p in mine], [p["measured"] for p in mine], "k.",
                label="measured")
        if kind == 0:
            ax.set_xscale("log")
        if quantity == 1 and min(p["measured"] for p in mine) > 0:
            ax.set_yscale("log")  # damping ratios span decades
        ax.set_xlabel(ABSCISSA[kind])
        ax.set_ylabel(QUANTITY[quantity])
        ax.set_title(f"target {target} ({KIND[kind]}, "
                     f"{'level' if kind == 1 else 'mode'} {int(mine[0]['mode_or_level'])})")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "fit.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])

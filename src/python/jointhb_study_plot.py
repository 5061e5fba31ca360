#!/usr/bin/env python3
"""Draws DIR/study.png from the outputs of `jointhb study`: per damping curve, frequency and
damping ratio against the modal amplitude; per FRF level, the amplitude against the frequency.
Every sample's curve is a thin grey line; the statistics at the study's outputs are the mean
(solid) and the band between the lowest and highest quantile. Columns: docs/studies.md §4.

Usage: jointhb_study_plot.py DIR
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


def value(row, key):
    text = row.get(key, "")
    return float(text) if text not in ("", None) else None


def main(directory):
    curves = rows(os.path.join(directory, "study_curves.csv"))
    stats = rows(os.path.join(directory, "study_statistics.csv"))
    quantile_columns = [k for k in (stats[0].keys() if stats else []) if k[:1] == "q" and k[1:2].isdigit()]
    panels = []  # (curve, index, y column, y label)
    for curve, index in sorted({(r["curve"], int(float(r["mode_or_level"]))) for r in curves}):
        if curve == "backbone":
            panels.append((curve, index, "frequency_hz", "frequency [Hz]"))
            panels.append((curve, index, "damping_ratio", "damping ratio"))
        else:
            panels.append((curve, index, "amplitude", "amplitude |x1|"))
    if not panels:
        return
    fig, axes = plt.subplots(len(panels), 1, figsize=(6.4, 3.0 * len(panels)), squeeze=False)
    for ax, (curve, index, column, label) in zip(axes[:, 0], panels):
        mine = [r for r in curves if r["curve"] == curve and int(float(r["mode_or_level"])) == index]
        for sample in sorted({r["sample"] for r in mine}, key=float):
            pts = [(value(r, "abscissa"), value(r, column)) for r in mine if r["sample"] == sample]
            pts = [p for p in pts if p[0] is not None and p[1] is not None]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], color="0.6", lw=0.6, alpha=0.6)
        quantity = "amplitude" if curve == "frf" else column
        at = [s for s in stats if s["curve"] == curve and int(float(s["mode_or_level"])) == index
              and s["quantity"] == quantity and value(s, "mean") is not None]
        if at:
            x = [value(s, "abscissa") for s in at]
            ax.plot(x, [value(s, "mean") for s in at], "o-", color="C0", label="mean")
            if len(quantile_columns) >= 2:
                lo, hi = quantile_columns[0], quantile_columns[-1]
                ax.fill_between(x, [value(s, lo) for s in at], [value(s, hi) for s in at],
                                color="C0", alpha=0.25, label=f"{lo[1:]} to {hi[1:]} quantile")
        if curve == "backbone":
            ax.set_xscale("log")
            ax.set_xlabel("modal amplitude q")
            ax.set_title(f"damping curve of mode {index}")
        else:
            ax.set_xlabel("frequency [Hz]")
            ax.set_title(f"FRF, level {index}")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        if at:
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "study.png"), dpi=110)


if __name__ == "__main__":
    main(sys.argv[1])

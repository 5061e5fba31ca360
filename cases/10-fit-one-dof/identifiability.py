#!/usr/bin/env python3
"""The identifiability table of docs/identification.md §6: case 10's measurement fitted with
several parameter sets and data subsets; prints a Markdown table of what `jointhb fit` reports.

  python3 identifiability.py /path/to/jointhb

Each row is one `jointhb fit --quiet` on a variant of case.yaml written to a temporary folder
(the measurement copied beside it). Truth: kt0 = 3e4 N/m, mu F_N = 1 N (mu 0.2, F_N 5 N),
zeta = 0.002, n = 1/3.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
P = {
    "F": '{name: "contacts[0].normal_force", lower: 0.5, upper: 50.0, start: 40.0, log_scale: true}',
    "mu": '{name: "contacts[0].mu", lower: 0.02, upper: 2.0, start: 0.2, log_scale: true}',
    "kt0": '{name: "contacts[0].kt0", lower: 3.0e3, upper: 3.0e5, start: 5.0e3, log_scale: true}',
    "zeta": '{name: "damping.modal[0]", lower: 1.0e-4, upper: 0.05, start: 0.01, log_scale: true}',
    "n": '{name: "contacts[0].n", lower: 0.1, upper: 0.9, start: 0.6}',
}
ROWS = [
    ("F_N, kt0, zeta", ["F", "kt0", "zeta"], "frequency_hz, damping_ratio", None),
    ("mu, F_N, kt0, zeta", ["mu", "F", "kt0", "zeta"], "frequency_hz, damping_ratio", None),
    ("F_N, kt0, zeta, n", ["F", "kt0", "zeta", "n"], "frequency_hz, damping_ratio", None),
    ("F_N, kt0, zeta", ["F", "kt0", "zeta"], "frequency_hz", None),
    ("F_N, kt0, zeta", ["F", "kt0", "zeta"], "damping_ratio", None),
    ("F_N, kt0, zeta", ["F", "kt0", "zeta"], "frequency_hz, damping_ratio", 5),
]


def case_text(params, use, rows):
    base = open(os.path.join(HERE, "case.yaml")).read()
    head = base[: base.index("fit:")]
    lines = ["fit:", "  parameters:"] + [f"    - {P[p]}" for p in params]
    lines += ["  targets:", f"    - {{type: backbone, mode: 1, file: data.csv, use: [{use}]}}",
              "  xtol: 1.0e-5", "  max_evaluations: 400"]
    return head + "\n".join(lines) + "\n"


def main(jointhb):
    print("| parameters | data | S | singular values | standard errors (relative) | "
          "flagged combination | evaluations | fit time [s] |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for label, params, use, rows in ROWS:
        with tempfile.TemporaryDirectory() as d:
            lines = open(os.path.join(HERE, "measured_backbone.csv")).read().splitlines(True)
            if rows:  # the header (and comment) plus the first rows: the low amplitudes only
                lines = lines[: 2 + rows]
            open(os.path.join(d, "data.csv"), "w").writelines(lines)
            open(os.path.join(d, "case.yaml"), "w").write(case_text(params, use, rows))
            subprocess.run([jointhb, "fit", os.path.join(d, "case.yaml"), "-o",
                            os.path.join(d, "out"), "--quiet"], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            s = json.load(open(os.path.join(d, "out", "fit.json")))
        sv = ", ".join(f"{v:.3g}" for v in s["singular_values"])
        se = ", ".join(
            f"{p['name'].split('.')[-1]} {p['value']:.4g} ± "
            + (f"{p['standard_error']:.2g} ({p['relative_standard_error']:.1%})"
               if p["standard_error"] is not None else "∞")
            for p in s["parameters"])
        flagged = "; ".join(u["combination"] for u in s["unidentifiable"]) or "none"
        data = use + (f" (q ≤ {float(lines[-1].split(',')[0]):.2g} only)" if rows else "")
        print(f"| {label} | {data} | {s['objective']:.4g} | {sv} | {se} | {flagged} | "
              f"{s['evaluations']} | {s['seconds']['fit']:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1])

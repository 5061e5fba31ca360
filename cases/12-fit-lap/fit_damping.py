"""Case 12 from Python: identify the modal damping ratio of the bolted lap from a measured
damping curve, with a Python objective around the pipeline.

The measured points (measured_backbone.csv, synthetic: truth zeta = 0.005, 2 % noise on the
damping) in microslip (q <= 6e-6). For each trial value the pipeline recomputes only the damping
curve: the damping ratio enters no stage (preload, modes and condensation are computed once, the
counters show it). Run after the README's set-up:
    PYTHONPATH=build/python /usr/bin/python3 cases/12-fit-lap/fit_damping.py
The last line says ok when the truth lies within 3 standard errors.
"""
import csv
import math
from pathlib import Path

import numpy as np

import jointhb

here = Path(__file__).parent
rows = [r for r in csv.DictReader(line for line in open(here / "measured_backbone.csv") if not line.startswith("#"))]
rows = [r for r in rows if float(r["amplitude"]) <= 6e-6]
q = np.array([float(r["amplitude"]) for r in rows])
zeta_measured = np.array([float(r["damping_ratio"]) for r in rows])
sigma = np.array([float(r["sigma_damping_ratio"]) for r in rows])

pipeline = jointhb.Pipeline(jointhb.load_case(str(here / "case.yaml")))


def residuals(values):
    pipeline.set("damping.ratio", values[0])
    curve = pipeline.backbone(1, log10_amplitude=(-8.0, math.log10(q.max()) + 0.1), frequency_drop=0.0)
    if curve["status"] != "ok":
        return None  # a failed evaluation
    zeta = np.interp(np.log10(q), np.log10(curve["amplitude"]), curve["damping_ratio"])
    return (zeta - zeta_measured) / sigma


result = jointhb.fit(residuals, [{"name": "damping.ratio", "lower": 1e-3, "upper": 0.05, "start": 0.015,
                                  "log_scale": True}], {"xtol": 1e-3, "max_evaluations": 25})
zeta, se = result["best"]["damping.ratio"], result["standard_errors"][0]
print(f"damping ratio {zeta:.5f} +- {se:.1e} (truth 0.005) in {result['evaluations']} evaluations; "
      f"stages: {pipeline.counters}")
c = pipeline.counters
assert c["preload_solved"] == 1 and c["condensed"] == 1
assert result["ok"] and abs(zeta - 0.005) < 3 * se
print("ok")

#!/usr/bin/python3
"""One curve of accuracy_on_request.py, timed by itself (for paired timings with farm-bench).

Usage: accuracy_curve_time.py CASE VARIANT
  CASE     03-one-dof-gaul-mayer, 08-lap-damping or 09-control-unit-damping
  VARIANT  accuracy (the study's request, from H = 1, N_t = 32) or H/N_t (a fixed level, e.g. 5/512);
           prefixed by frf: for case 03's FRF at its middle force level (e.g. frf:accuracy, frf:15/256)
Prints the points, the seconds of the curve alone (the static stages of a finite-element case are
computed or loaded before the clock starts) and the status. Needs the Python module on PYTHONPATH.
"""
import sys
import time
from pathlib import Path

import jointhb

from accuracy_on_request import CASES, FRF_CASES, START, SOURCE

case, variant = sys.argv[1], sys.argv[2]
frf = variant.startswith("frf:")
level = variant.split(":")[-1]
model = jointhb.load_case(str(SOURCE / "cases" / case / "case.yaml"))
if not isinstance(model, jointhb.DiscreteModel):
    model = jointhb.Pipeline(model)
    model.interface_model()
request = FRF_CASES[case]["request"] if frf else CASES[case]["request"]
if level == "accuracy":
    kw = dict(harmonics=START[0], time_samples=START[1], accuracy=request)
else:
    h, nt = (int(v) for v in level.split("/"))
    kw = dict(harmonics=h, time_samples=nt)
t0 = time.perf_counter()
if frf:
    c = model.frf(level=FRF_CASES[case]["level"], **kw)
    points = len(c["omega"])
elif isinstance(model, jointhb.Pipeline):
    c = model.backbone(1, frequency_drop=None, **kw)
    points = len(c["amplitude"])
else:
    c = model.backbone(1, **kw)
    points = len(c["amplitude"])
print(f"{case} {variant}: {points} points, curve {time.perf_counter() - t0:.3f} s, {c['status']}", flush=True)

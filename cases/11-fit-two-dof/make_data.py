#!/usr/bin/env python3
"""Makes measured_frf.csv and measured_mode2.csv for case 11 from the truth (truth.yaml) computed
by jointhb itself.

  python3 make_data.py /path/to/jointhb

runs `jointhb run truth.yaml` and keeps continuation points (exact model values, no
interpolation): from frf.csv the points nearest 16 frequencies evenly spaced over 13.5 .. 19 Hz,
amplitude times (1 + 0.01 n); from backbone.csv (mode 2) the points nearest 10 amplitudes
log-spaced over 1e-6 .. 2e-4, frequency times (1 + 0.002 n), damping ratio times (1 + 0.02 n);
n standard normal from random.Random(20261125). sigma_* columns give the noise level.
"""
import csv
import math
import os
import random
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def nearest(rows, key, targets, log):
    f = (lambda v: math.log10(v)) if log else (lambda v: v)
    chosen = []
    for t in targets:
        best = min(rows, key=lambda r: abs(f(float(r[key])) - f(t)))
        if best not in chosen:
            chosen.append(best)
    return chosen


def main(jointhb):
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([jointhb, "run", os.path.join(HERE, "truth.yaml"), "-o", out], check=True)
        frf = list(csv.DictReader(open(os.path.join(out, "frf.csv"))))
        backbone = list(csv.DictReader(open(os.path.join(out, "backbone.csv"))))
    rng = random.Random(20261125)
    with open(os.path.join(HERE, "measured_frf.csv"), "w") as f:
        f.write("# Synthetic FRF for case 11 (make_data.py): force 0.05 N on DOF 1, response of "
                "DOF 1 (fundamental amplitude, m); noise 1 %\n")
        f.write("frequency_hz,amplitude,sigma_amplitude\n")
        for r in nearest(frf, "frequency_hz", [13.5 + 5.5 * k / 15 for k in range(16)], False):
            a = float(r["amplitude_h1"]) * (1 + 0.01 * rng.gauss(0, 1))
            f.write(f"{float(r['frequency_hz']):.10g},{a:.10g},{0.01 * abs(a):.4g}\n")
    with open(os.path.join(HERE, "measured_mode2.csv"), "w") as f:
        f.write("# Synthetic damping curve of mode 2 for case 11 (make_data.py): noise 0.2 % "
                "(frequency), 2 % (damping)\n")
        f.write("amplitude,frequency_hz,damping_ratio,sigma_frequency_hz,sigma_damping_ratio\n")
        wanted = [10 ** (-6 + (math.log10(2e-4) + 6) * k / 9) for k in range(10)]
        for r in nearest(backbone, "amplitude", wanted, True):
            fm = float(r["frequency_hz"]) * (1 + 0.002 * rng.gauss(0, 1))
            zm = float(r["damping_ratio"]) * (1 + 0.02 * rng.gauss(0, 1))
            f.write(f"{float(r['amplitude']):.10g},{fm:.10g},{zm:.10g},"
                    f"{0.002 * abs(fm):.4g},{0.02 * abs(zm):.4g}\n")


if __name__ == "__main__":
    main(sys.argv[1])

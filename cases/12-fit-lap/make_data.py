#!/usr/bin/env python3
"""Makes measured_backbone.csv for case 12 from the truth (truth.yaml) computed by jointhb itself.

  python3 make_data.py /path/to/jointhb

runs `jointhb run truth.yaml` (the bolted lap with mu = 0.3 and zeta = 0.005; continuation steps
of at most 0.05 in log10 q), keeps the continuation points (exact model values, no interpolation)
nearest to 12 amplitudes log-spaced over 1e-7 .. 6e-5, and multiplies each frequency by
(1 + 0.0005 n) and each damping ratio by (1 + 0.02 n), n standard normal from
random.Random(20261125) (0.05 % and 2 % relative noise; the frequency falls by 5 % over the
curve). sigma_* columns give the noise level so that the residuals are in units of the noise.
"""
import csv
import math
import os
import random
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SIGMA_F, SIGMA_Z = 0.0005, 0.02


def main(jointhb):
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([jointhb, "run", os.path.join(HERE, "truth.yaml"), "-o", out], check=True)
        rows = list(csv.DictReader(open(os.path.join(out, "backbone.csv"))))
    rng = random.Random(20261125)
    wanted = [10 ** (-7 + (math.log10(6e-5) + 7) * k / 11) for k in range(12)]
    chosen = []
    for q in wanted:
        best = min(rows, key=lambda r: abs(math.log10(float(r["amplitude"])) - math.log10(q)))
        if best not in chosen:
            chosen.append(best)
    with open(os.path.join(HERE, "measured_backbone.csv"), "w") as f:
        f.write("# Synthetic measurement for case 12 (make_data.py): truth mu = 0.3, zeta = 0.005; "
                "noise 0.05 % (frequency), 2 % (damping)\n")
        f.write("amplitude,frequency_hz,damping_ratio,sigma_frequency_hz,sigma_damping_ratio\n")
        for r in chosen:
            fm = float(r["frequency_hz"]) * (1 + SIGMA_F * rng.gauss(0, 1))
            zm = float(r["damping_ratio"]) * (1 + SIGMA_Z * rng.gauss(0, 1))
            f.write(f"{float(r['amplitude']):.10g},{fm:.10g},{zm:.10g},"
                    f"{SIGMA_F * abs(fm):.4g},{SIGMA_Z * abs(zm):.4g}\n")


if __name__ == "__main__":
    main(sys.argv[1])

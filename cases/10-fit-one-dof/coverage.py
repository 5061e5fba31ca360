#!/usr/bin/env python3
"""Checks that case 10's standard errors describe the scatter of the estimates: fits N noise
realisations of the same truth (make_data.py's construction with seeds 1..N) and compares the
spread of (fitted − truth) with the standard errors jointhb reports.

  python3 coverage.py /path/to/jointhb [N]

Prints, per parameter, the mean and standard deviation of z = (fitted − truth)/standard error
(≈ 0 and ≈ 1 when the Gauss–Newton covariance is right), the share of |z| < 2 (≈ 95 %), the mean
s², evaluations and fit time. docs/identification.md §7 quotes one run.
"""
import csv
import json
import math
import os
import random
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TRUTH = {"contacts[0].normal_force": 5.0, "contacts[0].kt0": 3.0e4, "damping.modal[0]": 0.002}


def main(jointhb, n):
    with tempfile.TemporaryDirectory() as d:
        subprocess.run([jointhb, "run", os.path.join(HERE, "truth.yaml"), "-o", d], check=True,
                       stderr=subprocess.DEVNULL)
        rows = list(csv.DictReader(open(os.path.join(d, "backbone.csv"))))
        wanted = [10 ** (-6 + (math.log10(2e-4) + 6) * k / 13) for k in range(14)]
        chosen = []
        for q in wanted:
            best = min(rows, key=lambda r: abs(math.log10(float(r["amplitude"])) - math.log10(q)))
            if best not in chosen:
                chosen.append(best)
        case = open(os.path.join(HERE, "case.yaml")).read()
        open(os.path.join(d, "case.yaml"), "w").write(case)
        z = {k: [] for k in TRUTH}
        s2, evaluations, seconds = [], [], []
        for seed in range(1, n + 1):
            rng = random.Random(seed)
            with open(os.path.join(d, "measured_backbone.csv"), "w") as f:
                f.write("amplitude,frequency_hz,damping_ratio,sigma_frequency_hz,"
                        "sigma_damping_ratio\n")
                for r in chosen:
                    fm = float(r["frequency_hz"]) * (1 + 0.002 * rng.gauss(0, 1))
                    zm = float(r["damping_ratio"]) * (1 + 0.02 * rng.gauss(0, 1))
                    f.write(f"{float(r['amplitude']):.10g},{fm:.10g},{zm:.10g},"
                            f"{0.002 * abs(fm):.4g},{0.02 * abs(zm):.4g}\n")
            out = os.path.join(d, "out")
            subprocess.run([jointhb, "fit", os.path.join(d, "case.yaml"), "-o", out, "--quiet"],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            s = json.load(open(os.path.join(out, "fit.json")))
            for p in s["parameters"]:
                z[p["name"]].append((p["value"] - TRUTH[p["name"]]) / p["standard_error"])
            s2.append(s["s2"])
            evaluations.append(s["evaluations"])
            seconds.append(s["seconds"]["fit"])
    print(f"{n} noise realisations of case 10 (seeds 1..{n})")
    print("| parameter | mean z | std z | share with abs(z) < 2 |")
    print("| --- | --- | --- | --- |")
    for k, v in z.items():
        inside = sum(abs(x) < 2 for x in v) / len(v)
        print(f"| {k} | {statistics.mean(v):+.2f} | {statistics.stdev(v):.2f} | {inside:.0%} |")
    print(f"mean s2 {statistics.mean(s2):.2f}; evaluations {min(evaluations)}..{max(evaluations)} "
          f"(mean {statistics.mean(evaluations):.0f}); fit time {min(seconds):.2f}..{max(seconds):.2f} s")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 30)

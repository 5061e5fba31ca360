#!/usr/bin/python3
"""Error estimates of finite-element damping curves against their true errors (issue 22).

For a case's damping curve (its own harmonics H and samples N_t, error_estimate on), at a sample
of its points: the estimated relative errors of the frequency and of zeta (truncation: the change
to the converged H + 2 solution, eq. T-41b; aliasing: one Newton step to 2 N_t, T-42) beside the
true ones, from the same point solved at exactly the same modal amplitude q with
  (H + 2, N_t')      the change the truncation estimate claims to be,
  (H, N_ref)         the true aliasing error,
  (H_ref, N_ref)     the true total error (reference),
each as the first point of a curve started at log10 q (Newton from the linear mode at fixed q).

Usage: lap_error_estimate.py OUT_DIR [CASE ...]   (default: cases 08 and 09; needs the Python
module of a Release build on PYTHONPATH, e.g. build/python). Writes OUT_DIR/<case>_error_estimate.csv
row by row and prints a summary line per case.
"""
import csv
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

import jointhb

SOURCE = Path(__file__).resolve().parents[2]
CASES = {"08-lap-damping": {"h_ref": 7, "n_ref": 256, "samples": 8},
         "09-control-unit-damping": {"h_ref": 5, "n_ref": 1024, "samples": 6}}


def point_at(p, lam, harmonics, time_samples):
    """The damping-curve point at exactly q = 10^lam: the first point of a curve started there."""
    first = {}

    def stop(pt):
        first.update(pt)
        return False

    p.backbone(1, stop, log10_amplitude=(lam, lam + 0.5), frequency_drop=0.0, harmonics=harmonics,
               time_samples=time_samples)
    if not first or abs(math.log10(first["amplitude"]) - lam) > 1e-9:
        return None
    return first["frequency_hz"], first["damping_ratio"]


def rel(a, b):
    return (a - b) / abs(b)


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    names = sys.argv[2:] or list(CASES)
    for name in names:
        settings = CASES[name]
        p = jointhb.Pipeline(jointhb.load_case(str(SOURCE / "cases" / name / "case.yaml")))
        t0 = time.perf_counter()
        curve = p.backbone(1, error_estimate=True)
        t_curve = time.perf_counter() - t0
        h, nt = curve["harmonics"], curve["time_samples"]
        nt_fine = max(nt, 2 * (h + 2) + 2)
        n = len(curve["amplitude"])
        picks = sorted(set(np.linspace(0, n - 1, settings["samples"]).round().astype(int)))
        path = out / f"{name}_error_estimate.csv"
        columns = ["q", "frequency_hz", "damping_ratio",
                   "est_f_truncation", "est_f_aliasing", "est_zeta_truncation", "est_zeta_aliasing",
                   "true_f_to_h_plus_2", "true_zeta_to_h_plus_2", "true_f_aliasing", "true_zeta_aliasing",
                   "true_f_total", "true_zeta_total"]
        worst_ratio = []
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(columns)
            for i in picks:
                q = curve["amplitude"][i]
                lam = math.log10(q)
                base = point_at(p, lam, h, nt)
                up = point_at(p, lam, h + 2, nt_fine)
                fine = point_at(p, lam, h, settings["n_ref"])
                ref = point_at(p, lam, settings["h_ref"], settings["n_ref"])
                if None in (base, up, fine, ref):
                    print(f"{name}: q = {q:.3e}: a reference point did not converge; skipped", flush=True)
                    continue
                fb, zb = base
                row = [q, fb, zb, curve["omega_error_truncation"][i], curve["omega_error_aliasing"][i],
                       curve["damping_error_truncation"][i], curve["damping_error_aliasing"][i],
                       rel(up[0], fb), rel(up[1], zb), rel(fine[0], fb), rel(fine[1], zb), rel(ref[0], fb),
                       rel(ref[1], zb)]
                w.writerow([f"{v:.6e}" for v in row])
                f.flush()
                est = abs(row[5]) + abs(row[6])
                if abs(row[12]) > 1e-6:
                    worst_ratio.append(est / abs(row[12]))
                print(f"{name}: q {q:.3e}: zeta est trunc {row[5]:+.2e} (to H+2 {row[8]:+.2e}) alias {row[6]:+.2e} "
                      f"(true {row[10]:+.2e}); total true {row[12]:+.2e}", flush=True)
        ratios = np.array(worst_ratio)
        print(f"{name}: H = {h}, N_t = {nt}: {n} points, curve {t_curve:.2f} s of which estimates "
              f"{curve['seconds']['error_estimate']:.2f} s; (|e_T| + |e_A|)/|true total| of zeta over "
              f"{len(ratios)} points: min {ratios.min() if len(ratios) else float('nan'):.2f}, "
              f"median {np.median(ratios) if len(ratios) else float('nan'):.2f}, "
              f"max {ratios.max() if len(ratios) else float('nan'):.2f} -> {path}", flush=True)


if __name__ == "__main__":
    main()

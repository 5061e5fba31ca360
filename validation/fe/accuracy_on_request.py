#!/usr/bin/python3
"""Accuracy on request (issue 22, docs/theory.md §13 eq. T-44): damping curves whose harmonics H and
time samples N_t are chosen per point, against fixed levels and a converged reference.

For each case: the curve traced with `accuracy` (starting at H = 1, N_t = 32), the same curve at
fixed levels (H, N_t), timed as whole curves; at a sample of
the adaptive curve's amplitudes q the TRUE errors of f and zeta of every variant against the point
solved at exactly that q with (H_ref, N_ref) — the adaptive curve's own point, the fixed curves' point
solved at exactly that q (the first point of a curve started there). The estimated error of the
adaptive point (|e_T| + |e_A| per output) is listed beside its true error.

For case 03 also its FRF at the middle force level with `accuracy: {amplitude: 1e-4}` against fixed
levels, the true error of amplitude_h1 against the point at exactly the same Omega at (H_ref, N_ref).

Usage: accuracy_on_request.py OUT_DIR [CASE ...]   (default: cases 03, 08 and 09; needs the
Python module of a Release build on PYTHONPATH, e.g. build/python). Writes
OUT_DIR/accuracy_<case>_points.csv and accuracy_<case>_curves.csv row by row and prints a table.
"""
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

import jointhb

SOURCE = Path(__file__).resolve().parents[2]
CASES = {
    "03-one-dof-gaul-mayer": {"request": {"damping": 1e-3, "frequency": 1e-5, "max_harmonics": 21},
                              "fixed": [(1, 32), (3, 32), (5, 64), (9, 128), (15, 128), (13, 2048), (21, 2048)],
                              "h_ref": 31, "n_ref": 1024, "samples": 12},
    "08-lap-damping": {"request": {"damping": 1e-2, "frequency": 1e-4, "max_harmonics": 7},
                       "fixed": [(1, 32), (3, 32), (5, 64), (7, 512)], "h_ref": 7, "n_ref": 256, "samples": 8},
    "09-control-unit-damping": {"request": {"damping": 1e-2, "frequency": 1e-4, "max_harmonics": 5},
                                "fixed": [(1, 256), (3, 256), (5, 512)], "h_ref": 5, "n_ref": 1024, "samples": 5},
}
START = (1, 32)


def curve_of(model, **kw):
    if isinstance(model, jointhb.Pipeline):
        return model.backbone(1, frequency_drop=None, **kw)
    return model.backbone(1, **kw)


def point_at(model, lam, harmonics, time_samples):
    """(f [Hz], zeta) of the damping-curve point at exactly q = 10^lam."""
    first = {}

    def stop(pt):
        first.update(pt)
        return False

    curve_of(model, log10_amplitude=(lam, lam + 0.5), harmonics=harmonics, time_samples=time_samples,
             callback=stop)
    if not first or abs(math.log10(first["amplitude"]) - lam) > 1e-9:
        return None
    f = first["frequency_hz"] if "frequency_hz" in first else first["omega"] / (2 * math.pi)
    return f, first["damping_ratio"]


def number(v):
    """A CSV field: empty for NaN (not computed)."""
    return "" if math.isnan(v) else f"{v:.3e}"


def rel(a, b):
    return (a - b) / abs(b)


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for name in sys.argv[2:] or list(CASES):
        s = CASES[name]
        model = jointhb.load_case(str(SOURCE / "cases" / name / "case.yaml"))
        if not isinstance(model, jointhb.DiscreteModel):
            model = jointhb.Pipeline(model)
            model.interface_model()  # the static stages are not part of a curve's time
        t0 = time.perf_counter()
        adaptive = curve_of(model, harmonics=START[0], time_samples=START[1], accuracy=s["request"])
        t_adaptive = time.perf_counter() - t0
        q = np.asarray(adaptive["amplitude"])
        picks = sorted(set(np.linspace(0, len(q) - 1, s["samples"]).round().astype(int)))
        refs = {}
        for i in picks:
            refs[i] = point_at(model, math.log10(q[i]), s["h_ref"], s["n_ref"])
        curves_path = out / f"accuracy_{name}_curves.csv"
        points_path = out / f"accuracy_{name}_points.csv"
        with open(curves_path, "w", newline="") as fc, open(points_path, "w", newline="") as fp:
            wc, wp = csv.writer(fc), csv.writer(fp)
            wc.writerow(["variant", "points", "seconds", "harmonics_used", "time_samples_used", "worst_true_f",
                         "worst_true_zeta", "status"])
            wp.writerow(["variant", "q", "harmonics", "time_samples", "frequency_hz", "damping_ratio", "true_f",
                         "true_zeta", "estimated_f", "estimated_zeta"])
            variants = [("accuracy", adaptive, t_adaptive)]
            for h, nt in s["fixed"]:
                t0 = time.perf_counter()
                c = curve_of(model, harmonics=h, time_samples=nt)
                variants.append((f"H={h}/{nt}", c, time.perf_counter() - t0))
            for label, c, seconds in variants:
                worst_f = worst_z = 0.0
                for i in picks:
                    if refs[i] is None:
                        continue
                    lam = math.log10(q[i])
                    if label == "accuracy":
                        h, nt = int(c["harmonics_of_points"][i]), int(c["time_samples_of_points"][i])
                        value = (c["frequency_hz"][i], c["damping_ratio"][i])
                        # NaN (written empty) where the truncation part was not computed (at the
                        # largest H, finite-element curves make it at every third point only)
                        est_f = abs(c["omega_error_truncation"][i]) + abs(c["omega_error_aliasing"][i])
                        est_z = abs(c["damping_error_truncation"][i]) + abs(c["damping_error_aliasing"][i])
                    else:
                        h, nt = (int(v) for v in label[2:].split("/"))
                        value = point_at(model, lam, h, nt)
                        est_f = est_z = float("nan")
                        if value is None:
                            continue
                    ef, ez = rel(value[0], refs[i][0]), rel(value[1], refs[i][1])
                    worst_f, worst_z = max(worst_f, abs(ef)), max(worst_z, abs(ez))
                    wp.writerow([label, f"{q[i]:.6e}", h, nt, f"{value[0]:.10e}", f"{value[1]:.10e}", f"{ef:.3e}",
                                 f"{ez:.3e}", number(est_f), number(est_z)])
                    fp.flush()
                hs = c.get("harmonics_of_points")
                ns = c.get("time_samples_of_points")
                used_h = f"{int(min(hs))}-{int(max(hs))}" if hs is not None and len(hs) else ""
                used_n = f"{int(min(ns))}-{int(max(ns))}" if ns is not None and len(ns) else ""
                wc.writerow([label, len(c["amplitude"]), f"{seconds:.3f}", used_h, used_n, f"{worst_f:.3e}",
                             f"{worst_z:.3e}", c["status"]])
                fc.flush()
                print(f"{name}: {label:10s} {len(c['amplitude']):4d} points {seconds:8.2f} s  H {used_h:6s} "
                      f"N_t {used_n:9s} worst true error f {worst_f:.2e}  zeta {worst_z:.2e}  ({c['status']})",
                      flush=True)
        print(f"{name}: request {s['request']}; reference H = {s['h_ref']}, N_t = {s['n_ref']} at "
              f"{sum(r is not None for r in refs.values())} of {len(picks)} amplitudes -> {curves_path}", flush=True)


FRF_CASES = {
    "03-one-dof-gaul-mayer": {"level": 1, "request": {"amplitude": 1e-4, "max_harmonics": 21},
                              "fixed": [(1, 32), (3, 32), (7, 128), (15, 256), (21, 1024)],
                              "h_ref": 31, "n_ref": 1024, "samples": 10},
}


def frf_at(model, level, omega, harmonics, time_samples):
    """amplitude_h1 of the FRF point at exactly Omega (the first point of a curve started there)."""
    first = {}

    def stop(pt):
        first.update(pt)
        return False

    model.frf(level=level, omega=(omega, omega * 1.001), harmonics=harmonics, time_samples=time_samples,
              callback=stop)
    if not first or first["omega"] != omega:
        return None
    return first["amplitude_h1"]


def frf_study(out, name):
    """The case's FRF at one force level with `accuracy: {amplitude}` against fixed levels."""
    s = FRF_CASES[name]
    model = jointhb.load_case(str(SOURCE / "cases" / name / "case.yaml"))
    t0 = time.perf_counter()
    adaptive = model.frf(level=s["level"], harmonics=START[0], time_samples=START[1], accuracy=s["request"])
    t_adaptive = time.perf_counter() - t0
    omega = np.asarray(adaptive["omega"])
    picks = sorted(set(np.linspace(0, len(omega) - 1, s["samples"]).round().astype(int)))
    refs = {i: frf_at(model, s["level"], omega[i], s["h_ref"], s["n_ref"]) for i in picks}
    path = out / f"accuracy_{name}_frf.csv"
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["variant", "points", "seconds", "harmonics_used", "time_samples_used", "worst_true_amplitude",
                    "worst_estimated_amplitude", "status"])
        variants = [("accuracy", adaptive, t_adaptive)]
        for h, nt in s["fixed"]:
            t0 = time.perf_counter()
            c = model.frf(level=s["level"], harmonics=h, time_samples=nt)
            variants.append((f"H={h}/{nt}", c, time.perf_counter() - t0))
        for label, c, seconds in variants:
            worst = worst_est = 0.0
            for i in picks:
                if refs[i] is None:
                    continue
                if label == "accuracy":
                    value = c["amplitude_h1"][i]
                    worst_est = max(worst_est, abs(c["amplitude_error_truncation"][i]) +
                                    abs(c["amplitude_error_aliasing"][i]))
                else:
                    h, nt = (int(v) for v in label[2:].split("/"))
                    value = frf_at(model, s["level"], omega[i], h, nt)
                    if value is None:
                        continue
                worst = max(worst, abs(rel(value, refs[i])))
            hs, ns = c["harmonics_of_points"], c["time_samples_of_points"]
            w.writerow([label, len(c["omega"]), f"{seconds:.3f}", f"{int(min(hs))}-{int(max(hs))}",
                        f"{int(min(ns))}-{int(max(ns))}", f"{worst:.3e}", f"{worst_est:.3e}", c["status"]])
            f.flush()
            print(f"{name} FRF: {label:10s} {len(c['omega']):4d} points {seconds:8.2f} s  H {int(min(hs))}-{int(max(hs))} "
                  f"N_t {int(min(ns))}-{int(max(ns))}  worst true error {worst:.2e}"
                  + (f" (estimated {worst_est:.2e})" if label == "accuracy" else "") + f"  ({c['status']})", flush=True)
    print(f"{name} FRF: request {s['request']}; reference H = {s['h_ref']}, N_t = {s['n_ref']} at "
          f"{sum(r is not None for r in refs.values())} of {len(picks)} frequencies -> {path}", flush=True)


if __name__ == "__main__":
    main()
    for case in sys.argv[2:] or list(CASES):
        if case in FRF_CASES:
            frf_study(Path(sys.argv[1]), case)

#!/usr/bin/env python3
"""Markdown tables and cost-growth fits from interface_scaling's PREFIX_table.csv.

    python3 validation/fe/interface_scaling_table.py /tmp/isc/run_table.csv

Fits log t = c + a log P + b log m by least squares over the configurations where t was measured
(a single-variable fit when only one of P, m varies)."""
import csv
import math
import sys


def num(row, key):
    v = float(row[key])
    return None if v < 0 else v


def fmt(v, unit="", digits=3):
    if v is None:
        return "—"
    if v == 0:
        return "0"
    if abs(v) >= 100:
        return f"{v:.0f}{unit}"
    return f"{v:.{digits}g}{unit}"


def fit(rows, key):
    pts = [(math.log(float(r["points"])), math.log(2 * int(r["harmonics"]) + 1), math.log(num(r, key)))
           for r in rows if num(r, key) and num(r, key) > 0]
    if len(pts) < 3:
        return None
    # normal equations for t = c + a x + b y
    n = len(pts)
    sx = sum(p[0] for p in pts); sy = sum(p[1] for p in pts); st = sum(p[2] for p in pts)
    sxx = sum(p[0] ** 2 for p in pts); syy = sum(p[1] ** 2 for p in pts); sxy = sum(p[0] * p[1] for p in pts)
    sxt = sum(p[0] * p[2] for p in pts); syt = sum(p[1] * p[2] for p in pts)
    A = [[n, sx, sy], [sx, sxx, sxy], [sy, sxy, syy]]
    b = [st, sxt, syt]
    # Gaussian elimination
    for i in range(3):
        piv = max(range(i, 3), key=lambda r: abs(A[r][i]))
        A[i], A[piv] = A[piv], A[i]; b[i], b[piv] = b[piv], b[i]
        if abs(A[i][i]) < 1e-12:
            return None
        for r in range(i + 1, 3):
            f = A[r][i] / A[i][i]
            for c in range(i, 3):
                A[r][c] -= f * A[i][c]
            b[r] -= f * b[i]
    x = [0.0] * 3
    for i in (2, 1, 0):
        x[i] = (b[i] - sum(A[i][c] * x[c] for c in range(i + 1, 3))) / A[i][i]
    return x[1], x[2], n


rows = list(csv.DictReader(open(sys.argv[1])))
print("| config | U | dense J [GiB] | AFT | AFT+B_p | dense assembly | product | dense LU | preconditioner build |")
print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for r in rows:
    print(f"| {r['label']} | {r['unknowns']} | {float(r['dense_GiB']):.3g} | {fmt(num(r,'aft_s'),' s')} | "
          f"{fmt(num(r,'aft_blocks_s'),' s')} | {fmt(num(r,'dense_assembly_s'),' s')} | {fmt(num(r,'product_s'),' s')} | "
          f"{fmt(num(r,'lu_s'),' s')} | {fmt(num(r,'preconditioner_s'),' s')} |")
print()
print("| config | solver | curve [s] | points | Newton | LU / PC builds | GMRES | AFT [s] | assembly or products [s] | solve [s] | drop | last ‖R‖∞ | agreement | peak RSS [MiB] |")
print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for r in rows:
    if num(r, "dense_curve_s") is not None:
        print(f"| {r['label']} | dense LU | {fmt(num(r,'dense_curve_s'))} | | | {r['dense_factorisations']} | | | | | | | reference | |")
    if num(r, "curve_s") is not None:
        print(f"| {r['label']} | dense Krylov | {fmt(num(r,'curve_s'))} | {r['curve_points']} | {r['newton']} | {r['factorisations']} | "
              f"{r['gmres']} | {fmt(num(r,'curve_aft_s'))} | {fmt(num(r,'curve_assembly_s'))} | {fmt(num(r,'curve_solve_s'))} | "
              f"{float(r['drop']):.4f} | {fmt(num(r,'last_residual'),'',2)} | {fmt(num(r,'agreement'),'',2)} | |")
    if num(r, "mf_s") is not None:
        print(f"| {r['label']} | matrix-free | {fmt(num(r,'mf_s'))} | {r['mf_points']} | {r['mf_newton']} | {r['mf_preconditioners']} | "
              f"{r['mf_gmres']} | {fmt(num(r,'mf_aft_s'))} | {fmt(num(r,'mf_products_s'))} | {fmt(num(r,'mf_solve_s'))} | "
              f"{float(r['mf_drop']):.4f} | {fmt(num(r,'mf_last_residual'),'',2)} | {fmt(num(r,'mf_agreement'),'',2)} | {r['peak_rss_MiB']} |")
print()
print("Per Newton iteration, from the curves (component time / Newton iterations; line-search and tangent work included):")
print()
print("| config | solver | AFT [s] | assembly or products [s] | linear solve [s] | total [s] |")
print("| --- | --- | ---: | ---: | ---: | ---: |")
for r in rows:
    for name, pre, asm in (("dense Krylov", "curve", "curve_assembly_s"), ("matrix-free", "mf", "mf_products_s")):
        t = num(r, "curve_s" if pre == "curve" else "mf_s")
        nn = num(r, "newton" if pre == "curve" else "mf_newton")
        if t is None or not nn:
            continue
        aft = num(r, pre + "_aft_s"); a = num(r, asm); sv = num(r, pre + "_solve_s")
        print(f"| {r['label']} | {name} | {fmt(aft / nn)} | {fmt(a / nn)} | {fmt(sv / nn)} | {fmt(t / nn)} |")
print()
for r in rows:
    if r["note"]:
        print(f"- {r['label']}: {r['note']}")
print()
print("| quantity | exponent in P | exponent in m = 2H+1 | configurations |")
print("| --- | ---: | ---: | ---: |")
for key in ["aft_blocks_s", "dense_assembly_s", "product_s", "lu_s", "preconditioner_s", "mf_s"]:
    f = fit(rows, key)
    if f:
        print(f"| {key} | {f[0]:.2f} | {f[1]:.2f} | {f[2]} |")

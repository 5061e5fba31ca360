#!/usr/bin/env python3
"""Markdown tables of lap_hb_vs_newmark's PREFIX_points.csv (README_lap_hb_vs_newmark.md).

    python3 lap_hb_vs_newmark_table.py PREFIX_points.csv
Errors are relative to the Richardson-extrapolated Newmark value at the same frequency (phase:
absolute, rad).
"""
import csv
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
for mesh in dict.fromkeys(r["mesh"] for r in rows):
    print(f"\n{mesh}:\n")
    print("| f [Hz] (Ω/Ω_bb) | method | \\|X1\\| [m] | phase [rad] | W_ext [J] | W_D [J] | e\\|X1\\| | e_phase [rad] | e_Wext | e_WD |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if r["mesh"] != mesh:
            continue
        print(f"| {float(r['frequency_hz']):.1f} ({float(r['omega_ratio']):.3f}) | {r['method']} | "
              f"{float(r['amplitude_m']):.4e} | {float(r['phase_rad']):.4f} | {float(r['external_work_J']):.4e} | "
              f"{float(r['friction_dissipation_J']):.4e} | {float(r['err_amplitude']):.1e} | "
              f"{float(r['err_phase_rad']):.1e} | {float(r['err_external_work']):.1e} | "
              f"{float(r['err_dissipation']):.1e} |")

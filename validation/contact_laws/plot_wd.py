#!/usr/bin/python3
"""Plot W_D against a/g_max from the table written by jointhb_validate_contact_laws.

Sample run:
    /usr/bin/python3 validation/contact_laws/plot_wd.py \
        build-val/validation/contact_laws/wd_table.csv validation/contact_laws/results/wd_vs_amplitude.png

Left: W_D of the time-domain loop (markers), the general-n formula at the loop's span (lines),
eq. (11)/(12) as printed (dashed; negative values cannot be drawn on a log axis and are left out).
Right: relative errors against the general formula, with the validation bound (dotted), and for
n = 1/3 eq. (11) typed in literally in double precision (dash-dotted: digits lost to cancellation).
"""

import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    table = {}
    for row in rows:
        n = float(row["n"])
        table.setdefault(n, []).append({k: float(v) for k, v in row.items()})
    return table


def column(rows, key):
    return np.array([r[key] for r in rows])


def main(argv):
    if len(argv) != 3:
        print(__doc__)
        return 2
    table = read(argv[1])
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 5.2), constrained_layout=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    floor = 1e-17  # zero errors are drawn at this level
    for color, (n, rows) in zip(colors, sorted(table.items())):
        x = column(rows, "a_over_gmax")
        label = f"n = {n:.3g}"
        loop = column(rows, "W_D_loop")
        general = column(rows, "W_D_general")
        paper = column(rows, "W_D_paper")
        left.loglog(x, loop, "o", color=color, ms=4, mfc="none", label=f"{label}: loop")
        left.loglog(x, general, "-", color=color, lw=1.2)
        positive = paper > 0
        left.loglog(x[positive], paper[positive], "--", color=color, lw=1.0)

        right.loglog(x, np.maximum(column(rows, "rel_err_loop_vs_general"), floor), "o-",
                     color=color, ms=4, lw=0.8, label=f"{label}: loop vs general")
        right.loglog(x, np.maximum(column(rows, "rel_err_paper_vs_general"), floor), "--",
                     color=color, lw=1.0)
        right.loglog(x, column(rows, "tolerance"), ":", color=color, lw=0.8)
        if abs(n - 1.0 / 3.0) < 1e-9:
            right.loglog(x, np.maximum(column(rows, "rel_err_paper_literal_vs_general"), floor),
                         "-.", color=color, lw=1.0,
                         label="n = 1/3: eq. (11) typed in literally (cancellation)")

    left.plot([], [], "k-", label="general-n formula")
    left.plot([], [], "k--", label="eq. (11)/(12) as printed (W_D > 0 only)")
    left.set_xlabel(r"$a/g_{max}$,  $g_{max} = \mu F_N/((1-n)k_{T0})$")
    left.set_ylabel(r"$W_D$ [J] per cycle")
    left.set_title(r"Dissipation per cycle, $g_T = a\cos\omega t$")
    left.grid(True, which="major", alpha=0.3)
    left.legend(fontsize=7, loc="upper left")

    right.plot([], [], "k--", label="eq. (11)/(12) as printed vs general")
    right.plot([], [], "k:", label=r"validation bound, max(1e-12, 3 $\beta_F^2$)")
    right.set_xlabel(r"$a/g_{max}$")
    right.set_ylabel("relative error vs general formula")
    right.set_title("Relative errors (zero drawn at 1e-17)")
    right.grid(True, which="major", alpha=0.3)
    right.legend(fontsize=7, loc="upper right")
    fig.savefig(argv[2], dpi=130)
    print(f"wrote {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

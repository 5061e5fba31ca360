"""Case 08 from Python: the damping curve of the bolted lap's first bending mode.

The same computation as `jointhb run cases/08-lap-damping/case.yaml` (preload, modes, condensed
interface model, EPMC by harmonic balance), driven from Python. Run after the README's set-up:
    PYTHONPATH=build/python /usr/bin/python3 cases/08-lap-damping/damping_curve.py
Writes damping_curve.png in the working directory; the last line says ok.
"""
from pathlib import Path

import jointhb

case = jointhb.load_case(str(Path(__file__).with_name("case.yaml")))
pipeline = jointhb.Pipeline(case)
curve = pipeline.backbone(mode=1)  # from the linear limit to a 3 % frequency drop
f, zeta, q = curve["frequency_hz"], curve["damping_ratio"], curve["amplitude"]
print(f"{len(q)} points: f {f[0]:.2f} -> {f[-1]:.2f} Hz, zeta {zeta[0]:.4f} -> {zeta[-1]:.4f}")

import matplotlib  # noqa: E402  (the plot is optional for the computation above)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(5, 5))
a.semilogx(q, f, "o-")
b.semilogx(q, 100 * zeta, "o-")
a.set_ylabel("frequency [Hz]")
b.set_ylabel("damping ratio [%]")
b.set_xlabel("modal amplitude q [m sqrt(kg)]")
fig.tight_layout()
fig.savefig("damping_curve.png", dpi=120)
assert curve["status"] == "ok" and f[-1] < f[0] and zeta[-1] > zeta[0]
print("ok: damping_curve.png")

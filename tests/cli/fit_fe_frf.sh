# jointhb fit of an FRF target on a finite-element case (case 12's bolted lap): the truth's FRF at
# 2 N near the resonance, the damping ratio fitted back from 0.008 to within 2 %.
# (Split from fit_fe_case.sh so that the three FE fits run in parallel under ctest -j.)
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE_DIR="$SOURCE_DIR/cases/12-fit-lap"
# An FRF target on the FE case: the truth's FRF at 2 N near the resonance (every third of its
# continuation points, exact values), the damping ratio fitted back from 0.008.
sed -e 's/  nonlinear_modes:/  frf: {frequency_hz: [941, 949], force: [2.0], harmonics: 1}\n  nonlinear_modes:/' \
  "$CASE_DIR/truth.yaml" >"$WORK/frf_truth.yaml"
run_capture run "$WORK/frf_truth.yaml" -o "$WORK/frf_truth"
[ "$STATUS" -eq 0 ] || fail "truth FRF run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/frf_truth/frf.csv" "$WORK/measured_frf.csv" <<'PY' || fail "FRF data"
import csv, json, os, sys
rows = list(csv.DictReader(open(sys.argv[1])))
# Stability (analysis.frf.stability: auto) is off for a joint of more than 10 contact points: no
# stable/max_floquet_multiplier columns, the bifurcation word column last, summary says so.
assert list(rows[0])[-1] == "bifurcation" and "stable" not in rows[0], list(rows[0])
assert all(r["bifurcation"] in ("none", "fold") for r in rows), {r["bifurcation"] for r in rows}
st = json.load(open(os.path.join(os.path.dirname(sys.argv[1]), "summary.json")))["frfs"][0]["stability"]
assert st["computed"] is False and st["points_known"] == 0, st
with open(sys.argv[2], "w") as f:
    f.write("frequency_hz,amplitude\n")
    for r in rows[1:-1:3]:
        f.write(f"{r['frequency_hz']},{r['amplitude_h1']}\n")
PY
{ sed -e 's/  nonlinear_modes:/  frf: {frequency_hz: [941, 949], force: [2.0], harmonics: 1}\n  nonlinear_modes:/' \
    -e '/^fit:/,$d' "$CASE_DIR/case.yaml"
  cat <<'YAML'
fit:
  parameters:
    - {name: damping.ratio, lower: 1.0e-3, upper: 0.05, start: 0.008, log_scale: true}
  targets:
    - {type: frf, level: 0, file: measured_frf.csv}
  xtol: 1.0e-3
  max_evaluations: 15
YAML
} >"$WORK/frf.yaml"
run_capture fit "$WORK/frf.yaml" -o "$WORK/out-frf" --quiet
[ "$STATUS" -eq 0 ] || fail "FRF fit exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/out-frf" <<'PY' || fail "FE fit of an FRF"
import json, sys
s = json.load(open(f"{sys.argv[1]}/fit.json"))
z = s["parameters"][0]["value"]
assert abs(z / 0.005 - 1) < 0.02, z
st = s["stages"]
assert st["preload"]["solved"] == 1 and st["condensation"]["solved"] == 1, st
print(f"ok: FRF target: zeta = {z:.6g} (truth 0.005, data without noise) in {s['model_evaluations']} evaluations, "
      f"{s['seconds']['fit']:.1f} s")
PY

finish

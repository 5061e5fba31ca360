# jointhb fit on a finite-element case (case 12's bolted lap and its synthetic damping curve),
# reduced to what a test can afford: the damping ratio alone from the microslip part of the
# curve (q <= 6e-6, 8 points), so every evaluation after the first reuses preload, modes and
# condensation (kept by the pipeline: the counters in fit.json say so) and only a short damping
# curve is recomputed; the truth (0.005) must lie within 3 standard errors. Then bad fit sections of an FE case: one line naming the key, exit code 2.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE_DIR="$SOURCE_DIR/cases/12-fit-lap"
head -n 10 "$CASE_DIR/measured_backbone.csv" >"$WORK/measured_backbone.csv"  # comment, header, 8 rows
grep -v 'interfaces.lap.mu' "$CASE_DIR/case.yaml" | sed -e 's/max_evaluations: 80/max_evaluations: 25/' \
  -e 's/xtol: 1.0e-4/xtol: 1.0e-3/' >"$WORK/zeta.yaml"
grep -q 'damping.ratio' "$WORK/zeta.yaml" || fail "could not make the damping-only case"

run_capture fit "$WORK/zeta.yaml" -o "$WORK/out" --quiet
[ "$STATUS" -eq 0 ] || fail "fit exited $STATUS: $(cat "$ERR")"
for f in fit.json fit_history.csv fit_curves.csv fit_model_curves.csv; do
  [ -s "$WORK/out/$f" ] || fail "missing $f"
done
"$PYTHON" - "$WORK/out" <<'PY' || fail "FE fit result"
import json, sys
s = json.load(open(f"{sys.argv[1]}/fit.json"))
assert s["status"] == "ok", s["status"]
p = s["parameters"][0]
assert p["name"] == "damping.ratio", p
z, se = p["value"], p["standard_error"]
assert se is not None and se > 0 and abs(z - 0.005) < 3 * se, (z, se)
st = s["stages"]
n = s["model_evaluations"]
assert st["preload"]["solved"] == 1 and st["modes"]["solved"] == 1 and st["condensation"]["solved"] == 1, st
assert st["condensation"]["reused"] + st["condensation"]["from_cache"] >= n - 1, (st, n)
assert st["values_put_on_the_curve"] >= 0.9 * 16 * st["damping_curves"], st  # 8 amplitudes x (f, zeta), on the curve
print(f"ok: zeta = {z:.6g} +- {se:.2g} (truth 0.005) in {n} evaluations, {s['seconds']['fit']:.1f} s; "
      f"preload, modes and condensation computed once, reused {st['condensation']['reused']} times")
PY

# friction_in_dynamics_only: mu alone from the same points; the stages keep the case's mu (0.3,
# the truth's), so preload, modes and condensation are solved once although mu changes at every
# evaluation, and the truth is recovered.
sed -e 's/name: damping.ratio, lower: 1.0e-3, upper: 0.05, start: 0.015/name: interfaces.lap.mu, lower: 0.05, upper: 1.0, start: 0.6/' \
  -e 's/  max_evaluations: 25/  max_evaluations: 25\n  friction_in_dynamics_only: true/' "$WORK/zeta.yaml" >"$WORK/mu.yaml"
grep -q 'friction_in_dynamics_only: true' "$WORK/mu.yaml" && grep -q 'name: interfaces.lap.mu' "$WORK/mu.yaml" || fail "could not make the mu case"
run_capture fit "$WORK/mu.yaml" -o "$WORK/out-mu" --quiet
[ "$STATUS" -eq 0 ] || fail "mu fit exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/out-mu" <<'PY' || fail "FE fit of mu in the dynamics only"
import json, sys
s = json.load(open(f"{sys.argv[1]}/fit.json"))
p = s["parameters"][0]
mu, se = p["value"], p["standard_error"]
assert s["options"]["friction_in_dynamics_only"] is True
assert se is not None and se > 0 and abs(mu - 0.3) < 3 * se, (mu, se)
st = s["stages"]
assert st["preload"]["solved"] == 1 and st["condensation"]["solved"] == 1, st
print(f"ok: mu = {mu:.5g} +- {se:.2g} (truth 0.3) in {s['model_evaluations']} evaluations, "
      f"{s['seconds']['fit']:.1f} s; preload and condensation solved once")
PY

# An FRF target on the FE case: the truth's FRF at 2 N near the resonance (every third of its
# continuation points, exact values), the damping ratio fitted back from 0.008.
sed -e 's/  nonlinear_modes:/  frf: {frequency_hz: [941, 949], force: [2.0], harmonics: 1}\n  nonlinear_modes:/' \
  "$CASE_DIR/truth.yaml" >"$WORK/frf_truth.yaml"
run_capture run "$WORK/frf_truth.yaml" -o "$WORK/frf_truth"
[ "$STATUS" -eq 0 ] || fail "truth FRF run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/frf_truth/frf.csv" "$WORK/measured_frf.csv" <<'PY' || fail "FRF data"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
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

# Bad input: an unknown parameter lists the valid ones; an frf target needs analysis.frf.
sed 's/name: damping.ratio/name: interfaces.lap.friction/' "$WORK/zeta.yaml" >"$WORK/bad1.yaml"
expect_bad_input fit "$WORK/bad1.yaml" -o "$WORK/bad"
grep -q "fit.parameters\[0\].name" "$ERR" && grep -q "interfaces.lap.mu" "$ERR" || fail "unknown parameter message: $(cat "$ERR")"
sed 's/type: backbone, mode: 1,/type: frf,/' "$WORK/zeta.yaml" >"$WORK/bad2.yaml"
expect_bad_input fit "$WORK/bad2.yaml" -o "$WORK/bad"
grep -q "fit.targets\[0\].type" "$ERR" && grep -q "analysis.frf" "$ERR" || fail "frf target message: $(cat "$ERR")"
[ -e "$WORK/bad" ] && fail "a bad case created the output directory"
finish

# jointhb fit on a finite-element case (case 12's bolted lap and its synthetic damping curve),
# reduced to what a test can afford: the damping ratio alone from the microslip part of the
# curve (q <= 6e-6, 8 points), so every evaluation after the first reuses preload, modes and
# condensation (kept by the pipeline: the counters in fit.json say so) and only a short damping
# curve is recomputed; the truth (0.005) must lie within 3 standard errors. Then bad fit sections of an FE case: one line naming the key, exit code 2.
source "$(dirname "$0")/common.inc" "$@"
source "$(dirname "$0")/fit_fe_common.inc"

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

# Bad input: an unknown parameter lists the valid ones; an frf target needs analysis.frf.
sed 's/name: damping.ratio/name: interfaces.lap.friction/' "$WORK/zeta.yaml" >"$WORK/bad1.yaml"
expect_bad_input fit "$WORK/bad1.yaml" -o "$WORK/bad"
grep -q "fit.parameters\[0\].name" "$ERR" && grep -q "interfaces.lap.mu" "$ERR" || fail "unknown parameter message: $(cat "$ERR")"
sed 's/type: backbone, mode: 1,/type: frf,/' "$WORK/zeta.yaml" >"$WORK/bad2.yaml"
expect_bad_input fit "$WORK/bad2.yaml" -o "$WORK/bad"
grep -q "fit.targets\[0\].type" "$ERR" && grep -q "analysis.frf" "$ERR" || fail "frf target message: $(cat "$ERR")"
[ -e "$WORK/bad" ] && fail "a bad case created the output directory"
finish

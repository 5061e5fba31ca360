# jointhb fit on a finite-element case (case 12's bolted lap, its synthetic damping curve reduced to
# the microslip part, q <= 6e-6, 8 points) with friction_in_dynamics_only: mu alone; the stages keep
# the case's mu, so preload and condensation are solved once, and the truth (0.3) is recovered.
# (Split from fit_fe_case.sh so that the three FE fits run in parallel under ctest -j.)
source "$(dirname "$0")/common.inc" "$@"
source "$(dirname "$0")/fit_fe_common.inc"

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

finish

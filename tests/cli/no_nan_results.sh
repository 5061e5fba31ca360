# No message or file ever contains nan (issue 20, item 4): the closed forms are evaluated stably as
# n -> 1, a formula that overflows is reported as unavailable (null), and a failed point says what
# overflowed in words.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

# no_nan FILE...: none of the files contains "nan" (any case).
no_nan() {
  local f
  for f in "$@"; do
    if grep -qi nan "$f"; then fail "$f contains nan: $(grep -i nan "$f" | head -3)"; fi
  done
}

# n -> 1: the printed formula's series overflowed to NaN (the loop itself was fine).
run_capture loop --n 0.9999999 --json
[ "$STATUS" -eq 0 ] || fail "loop --n 0.9999999 --json exited $STATUS: $(cat "$ERR")"
no_nan "$OUT" "$ERR"
"$PYTHON" - "$OUT" <<'PY' || fail "loop --n 0.9999999 --json output"
import json, sys
d = json.load(open(sys.argv[1]))
for k in ("W_D", "W_D_paper", "W_D_general", "W_D_paper_amplitude_reading"):
    assert isinstance(d[k], float) and d[k] > 0, (k, d[k])
rel = abs(d["W_D_general"] - d["W_D"]) / d["W_D"]
assert rel <= 1e-6, f"W_D_general differs from W_D by {rel:g}"
print(f"ok: n = 0.9999999: W_D {d['W_D']:.6g}, paper {d['W_D_paper']:.6g}, general rel. diff. {rel:.1e}")
PY
run_capture loop --n 0.9999999
[ "$STATUS" -eq 0 ] || fail "loop --n 0.9999999 exited $STATUS: $(cat "$ERR")"
no_nan "$OUT" "$ERR"

# Extreme normal forces: whatever the outcome, no nan on stdout, stderr or in the files.
for force in 1e300 1e160; do
  run_capture loop --normal-force "$force" --json
  no_nan "$OUT" "$ERR"
  echo "ok: loop --normal-force $force: exit $STATUS, no nan"
done

# Amplitudes whose slip over the stick range leaves [1e-100, 1e100] are refused (exit 2, naming
# the amplitude), not answered with W_D = 0 (issue 20, item 3).
for args in "--amplitude 1e160" "--amplitude 1e-5 --normal-force 1e120"; do
  # shellcheck disable=SC2086
  expect_bad_input loop $args --json
  grep -q "option '--amplitude'" "$ERR" || fail "loop $args: the message does not name --amplitude: $(cat "$ERR")"
  no_nan "$OUT" "$ERR"
done

cat >"$WORK/huge.yaml" <<'YAML'
analysis:
  loop_sweep:
    law: gaul-mayer
    mu: 0.3
    normal_force: 1.0e300
    points: 3
YAML
run_capture run "$WORK/huge.yaml" -o "$WORK/huge"
no_nan "$ERR" "$WORK/huge/summary.json" "$WORK/huge/wd_sweep.csv"
echo "ok: loop sweep with normal_force 1e300: exit $STATUS, no nan ($(cat "$ERR"))"
finish

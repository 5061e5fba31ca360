# Curves that reach their end (issue 23), through the CLI: the lightly damped 1-DOF friction
# oscillator whose FRFs stopped below the stuck resonance (all five levels must reach Ω_end), case
# 02 without damping and with beta = 1e-10 (stopped at its stuck resonance, 111.29 rad/s), and
# case 08's damping curve started at q = 1e-14 (failed at its first step): it must end normally
# (the case's 3 % frequency-shift stop) with its first point on the linear limit.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

cat >"$WORK/light.yaml" <<'YAML'
model: {type: discrete, mass: [[1.0]], stiffness: [[1.0]], damping: {matrix: [[0.004]]}}
contacts: [{law: jenkins, dofs: [0], kt0: 10.0, mu: 0.1, normal_force: 1.0}]
excitation: [{dof: 0, amplitude: [0.005, 0.01, 0.02, 0.04, 0.08]}]
analysis: {frf: {omega: [0.5, 4.5], harmonics: 7, time_samples: 256, output_dof: 0}}
YAML
for beta in 0.0 1.0e-10; do
  sed "s/beta: 1.0e-4/beta: $beta/" "$SOURCE_DIR/cases/02-two-dof-frf/case.yaml" >"$WORK/c02_$beta.yaml"
  grep -q "beta: $beta" "$WORK/c02_$beta.yaml" || fail "could not set beta = $beta in case 02"
done
for c in light c02_0.0 c02_1.0e-10; do
  run_capture run "$WORK/$c.yaml" -o "$WORK/out-$c"
  [ "$STATUS" -eq 0 ] || fail "$c exited $STATUS: $(cat "$ERR")"
  "$PYTHON" - "$WORK/out-$c/summary.json" "$c" <<'PY' || fail "$c: not every curve reached its end"
import json, sys
s = json.load(open(sys.argv[1]))
curves = s["curves"]
bad = [(c["level"], c["termination"], c["message"]) for c in curves if c["termination"] != "reached_end"]
assert not bad, bad
print(f"ok: {sys.argv[2]}: {len(curves)} curves reached the end ({sum(c['points'] for c in curves)} points)")
PY
done

sed 's/log10_amplitude: \[-8, -4\]/log10_amplitude: [-14, -1]/' "$SOURCE_DIR/cases/08-lap-damping/case.yaml" \
  >"$WORK/c08.yaml"  # the case's parts are boxes: no file next to it is needed
grep -q 'log10_amplitude: \[-14, -1\]' "$WORK/c08.yaml" || fail "could not set the range of case 08"
run_capture run "$WORK/c08.yaml" -o "$WORK/out-08" --no-cache
[ "$STATUS" -eq 0 ] || fail "case 08 over [-14, -1] exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/out-08" <<'PY' || fail "case 08 over [-14, -1]"
import csv, json, sys
s = json.load(open(f"{sys.argv[1]}/summary.json"))
b = s["backbones"][0]
assert b["ok"] and b["termination"] == "reached_end", b["message"]
rows = list(csv.DictReader(open(f"{sys.argv[1]}/backbone.csv")))
first = rows[0]
assert float(first["amplitude"]) == 1e-14, first["amplitude"]
df = float(first["frequency_hz"]) / b["linear_frequency_hz"] - 1
assert abs(df) < 1e-9, df
print(f"ok: case 08 from q = 1e-14: {len(rows)} points, first f/f_linear - 1 = {df:.1e}, ended: {b['message']}")
PY
finish

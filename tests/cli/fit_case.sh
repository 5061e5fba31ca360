# jointhb fit: a small identification from case 10's synthetic backbone (outputs, history, resume
# from a cut history), then bad fit sections: one line FILE:LINE:COL naming the key, exit code 2.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE_DIR="$SOURCE_DIR/cases/10-fit-one-dof"
cp "$CASE_DIR/measured_backbone.csv" "$WORK/"

source "$(dirname "$0")/fit_common.inc"

GOOD='    - {name: "contacts[0].normal_force", lower: 0.5, upper: 50.0, start: 20.0, log_scale: true}
    - {name: "contacts[0].kt0", lower: 3.0e3, upper: 3.0e5, start: 1.0e4, log_scale: true}'
write_case "$WORK/fit.yaml" "$GOOD"
run_capture fit "$WORK/fit.yaml" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "fit exited $STATUS: $(cat "$ERR")"
for f in fit.json fit_history.csv fit_curves.csv fit_model_curves.csv; do
  [ -s "$WORK/out/$f" ] || fail "missing $f"
done
"$PYTHON" - "$WORK/out" <<'PY' || fail "fit outputs"
import csv, json, sys, os
d = sys.argv[1]
s = json.load(open(os.path.join(d, "fit.json")))
assert s["status"] == "ok", s["status"]
# How the search ended (FitResult::status(), docs/cli.md "Status blocks"), after "status".
assert list(s)[1:5] == ["status", "termination", "ok", "message"], list(s)
assert s["termination"] in ("converged", "no_convergence", "failed"), s["termination"]
assert s["ok"] == (s["termination"] == "converged") and s["stop_reason"] in s["message"], s["message"]
names = [p["name"] for p in s["parameters"]]
assert names == ["contacts[0].normal_force", "contacts[0].kt0"], names
fn, kt = (p["value"] for p in s["parameters"])
# The truth (F_N = 5 N with mu = 0.2, kt0 = 3e4 N/m) within a loose tolerance at xtol 1e-3.
assert abs(fn - 5.0) < 0.5 and abs(kt - 3e4) < 3e3, (fn, kt)
assert all(p["standard_error"] > 0 for p in s["parameters"])
assert s["unidentifiable"] == [] and len(s["singular_values"]) == 2
assert s["failed_evaluations"] >= 0 and s["model_evaluations"] == s["evaluations"] > 4
assert s["targets"][0]["points"] == 28 and s["residual_points"] == 28
history = list(csv.DictReader(open(os.path.join(d, "fit_history.csv"))))
assert len(history) == s["evaluations"], (len(history), s["evaluations"])
assert list(history[0].keys())[:6] == ["eval", "start", "objective", "failed",
                                       "contacts[0].normal_force", "contacts[0].kt0"]
curves = list(csv.DictReader(open(os.path.join(d, "fit_curves.csv"))))
assert len(curves) == 28
print(f"ok: F_N = {fn:.4g}, kt0 = {kt:.5g} after {s['evaluations']} evaluations")
PY
if "$PYTHON" -c 'import matplotlib' 2>/dev/null; then
  [ -s "$WORK/out/fit.png" ] || fail "fit.png not drawn"
fi

# Resume from a history cut after 10 rows (the last line half-written): same result, the rest
# computed anew; then from the complete history: nothing computed.
cp "$WORK/out/fit.json" "$WORK/first.json"
head -n 11 "$WORK/out/fit_history.csv" >"$WORK/cut.csv"
sed -n 12p "$WORK/out/fit_history.csv" | head -c 20 >>"$WORK/cut.csv"
mkdir -p "$WORK/resumed" && cp "$WORK/cut.csv" "$WORK/resumed/fit_history.csv"
run_capture fit "$WORK/fit.yaml" -o "$WORK/resumed" --resume --quiet
[ "$STATUS" -eq 0 ] || fail "resume exited $STATUS: $(cat "$ERR")"
run_capture fit "$WORK/fit.yaml" -o "$WORK/out" --resume --quiet
[ "$STATUS" -eq 0 ] || fail "second resume exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/first.json" "$WORK/resumed/fit.json" "$WORK/out/fit.json" <<'PY' || fail "resume"
import json, sys
a, b, c = (json.load(open(f)) for f in sys.argv[1:])
for x in (b, c):
    assert [p["value"] for p in x["parameters"]] == [p["value"] for p in a["parameters"]]
    assert x["objective"] == a["objective"] and x["evaluations"] == a["evaluations"]
assert b["replayed_evaluations"] == 10 and b["model_evaluations"] == a["evaluations"] - 10, b
assert c["model_evaluations"] == 0 and c["replayed_evaluations"] == a["evaluations"], c
print(f"ok: resumed after 10 of {a['evaluations']} evaluations: the same optimum")
PY

# Bad input: one line naming file:line:column and the key, nothing computed.
write_case "$WORK/bounds.yaml" '    - {name: "contacts[0].kt0", lower: 3.0e5, upper: 3.0e3, start: 1.0e4}'
expect_bad_input fit "$WORK/bounds.yaml" -o "$WORK/none"
grep -q "bounds.yaml:12:.*key 'fit.parameters\[0\].upper': must be > lower = 300000, got 3000" "$ERR" ||
  fail "bounds: $(cat "$ERR")"
write_case "$WORK/log.yaml" '    - {name: "contacts[0].kt0", lower: 0.0, upper: 3.0e5, start: 1.0e4, log_scale: true}'
expect_bad_input fit "$WORK/log.yaml" -o "$WORK/none"
grep -q "log.yaml:12:.*key 'fit.parameters\[0\].lower': must be > 0 with log_scale" "$ERR" ||
  fail "log scale: $(cat "$ERR")"
write_case "$WORK/start.yaml" '    - {name: "contacts[0].kt0", lower: 1.0, upper: 3.0e5, start: 1.0e6}'
expect_bad_input fit "$WORK/start.yaml" -o "$WORK/none"
grep -q "key 'fit.parameters\[0\].start': must be in \[lower, upper\]" "$ERR" || fail "start: $(cat "$ERR")"
write_case "$WORK/name.yaml" '    - {name: "contacts[1].mu", lower: 0.1, upper: 1.0, start: 0.5}'
expect_bad_input fit "$WORK/name.yaml" -o "$WORK/none"
grep -q "name.yaml:12:.*key 'fit.parameters\[0\].name': unknown parameter 'contacts\[1\].mu'; this case has: contacts\[0\].kt0, contacts\[0\].mu, contacts\[0\].normal_force, contacts\[0\].n, damping.modal\[0\]" "$ERR" ||
  fail "name: $(cat "$ERR")"
write_case "$WORK/key.yaml" "$GOOD" '  algoritm: direct'
expect_bad_input fit "$WORK/key.yaml" -o "$WORK/none"
grep -q "key.yaml:17:3: key 'fit.algoritm': unknown key" "$ERR" || fail "key: $(cat "$ERR")"
write_case "$WORK/missing.yaml" "$GOOD"
sed -i 's/measured_backbone.csv/nowhere.csv/' "$WORK/missing.yaml"
expect_bad_input fit "$WORK/missing.yaml" -o "$WORK/none"
grep -q "missing.yaml:15:.*key 'fit.targets\[0\].file': cannot read '.*nowhere.csv'" "$ERR" ||
  fail "missing csv: $(cat "$ERR")"
write_case "$WORK/row.yaml" "$GOOD"
sed -i 's/measured_backbone.csv/bad.csv/' "$WORK/row.yaml"
printf 'amplitude,frequency_hz,damping_ratio\n1e-6,31.8,0.001\n2e-6,abc,0.001\n' >"$WORK/bad.csv"
expect_bad_input fit "$WORK/row.yaml" -o "$WORK/none"
grep -q "bad.csv:3:6: key 'fit.targets\[0\].file': column 'frequency_hz' must be a finite number, got 'abc'" "$ERR" ||
  fail "csv row: $(cat "$ERR")"
write_case "$WORK/range.yaml" "$GOOD"
sed -i 's/log10_amplitude: \[-7, -3.5\]/log10_amplitude: [-7, -5]/' "$WORK/range.yaml"
expect_bad_input fit "$WORK/range.yaml" -o "$WORK/none"
grep -q "measured_backbone.csv:9:1: key 'fit.targets\[0\].file': amplitude 1.204029976e-05 lies outside analysis.nonlinear_modes.log10_amplitude \[-7, -5\]" "$ERR" ||
  fail "range: $(cat "$ERR")"
expect_bad_input fit "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" -o "$WORK/none"
grep -q "has no fit section" "$ERR" || fail "no fit section: $(cat "$ERR")"
expect_bad_input fit "$WORK/fit.yaml" -o "$WORK/fresh" --resume
grep -q "option '--resume': no history to resume from" "$ERR" || fail "resume nothing: $(cat "$ERR")"
[ ! -e "$WORK/none" ] || fail "an input error left output behind"
finish

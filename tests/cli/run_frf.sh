# jointhb run on a discrete-model case: cases/02-two-dof-frf/case.yaml (three FRF curves), a
# variant whose curves stop early (exit 1, rows kept), and set-up errors (exit 2, nothing written).
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/02-two-dof-frf/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/out/frf.csv" "$WORK/out/summary.json" <<'PY' || fail "frf outputs"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
need = ["level", "omega", "frequency_hz", "amplitude_h1", "amplitude_max"]
assert all(c in rows[0] for c in need), rows[0].keys()
assert s["status"] == "ok" and s["analyses"] == ["frf"], (s["status"], s["analyses"])
curves = s["curves"]
assert len(curves) == 3 and all("status" not in c for c in curves), curves
assert all(c["termination"] == "reached_end" and c["ok"] is True for c in curves), curves
lo, hi = s["inputs"]["frf"]["omega"]
for c in curves:
    mine = [r for r in rows if int(float(r["level"])) == c["level"]]
    assert len(mine) == c["points"] > 5, (len(mine), c["points"])
    assert float(mine[0]["omega"]) == lo and float(mine[-1]["omega"]) == hi
    for r in mine:
        om = float(r["omega"])
        assert abs(float(r["frequency_hz"]) - om / (2 * math.pi)) <= 1e-12 * om
        assert float(r["amplitude_max"]) > 0 and float(r["amplitude_h1"]) > 0
    assert lo < c["peak"]["omega"] < hi and c["newton_iterations"] > 0
    assert set(c["seconds"]) >= {"aft", "assembly", "linear_solve", "total"}
# Friction softens the joint: the resonance moves down as the force grows.
peaks = [c["peak"]["omega"] for c in curves]
assert peaks[0] > peaks[1] > peaks[2], peaks
print(f"ok: {len(rows)} points, peaks at {[round(p, 3) for p in peaks]} rad/s")
PY

# Curves cut short by max_points: exit 1, every accepted point kept, status failed.
sed 's/output_dof: 1/output_dof: 1\n    continuation: {max_points: 4}/' "$CASE" >"$WORK/short.yaml"
run_capture run "$WORK/short.yaml" -o "$WORK/short"
[ "$STATUS" -eq 1 ] || fail "short run exited $STATUS, expected 1: $(cat "$ERR")"
"$PYTHON" - "$WORK/short/frf.csv" "$WORK/short/summary.json" <<'PY' || fail "short outputs"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
assert s["status"] == "failed" and len(rows) == 12, (s["status"], len(rows))
assert (s["termination"], s["ok"]) == ("no_convergence", False) and s["message"].startswith("frf level 0: "), s
assert all(c["stop_reason"] == "max_points" for c in s["curves"]), s["curves"]
assert all(c["termination"] == "no_convergence" and c["ok"] is False for c in s["curves"]), s["curves"]
print("ok: stopped curves keep their points")
PY

# check_jacobian: the analytic Jacobian agrees with central differences along every curve.
sed 's/output_dof: 1/output_dof: 1\n    check_jacobian: true/' "$CASE" >"$WORK/check.yaml"
run_capture run "$WORK/check.yaml" -o "$WORK/check"
[ "$STATUS" -eq 0 ] || fail "check_jacobian run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/check/summary.json" <<'PY' || fail "jacobian check"
import json, sys
s = json.load(open(sys.argv[1]))
worst = max(c["jacobian_check_error"] for c in s["curves"])
# A wrong Jacobian shows as O(1); partial kinks of the Jenkins damper within ±h leave < 1e-4.
assert 0 < worst < 1e-4, worst
print(f"ok: Jacobian vs central differences, worst {worst:.1e}")
PY

# Error estimates (docs/theory.md §13): on by default, a number in every row's four error columns,
# the worst per curve in summary.json; error_estimate: false leaves the columns empty (never nan);
# a value other than true/false is refused on one line naming the key.
"$PYTHON" - "$WORK/out/frf.csv" "$WORK/out/summary.json" <<'PY' || fail "error estimates"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
cols = ["amplitude_error_truncation", "amplitude_error_aliasing", "amplitude_max_error_truncation",
        "amplitude_max_error_aliasing"]
assert all(c in s["columns"]["frf"] for c in cols), s["columns"]["frf"]
assert s["inputs"]["frf"]["error_estimate"] is True
for c in s["curves"]:
    mine = [r for r in rows if int(float(r["level"])) == c["level"]]
    e = c["error_estimate"]
    assert e["points_known"] == len(mine), (e["points_known"], len(mine))
    for out, (t, a) in (("amplitude_h1", cols[:2]), ("amplitude_max", cols[2:])):
        vt = [abs(float(r[t])) for r in mine]
        va = [abs(float(r[a])) for r in mine]
        assert all(math.isfinite(v) for v in vt + va)
        assert e[out]["truncation"] == max(vt) and e[out]["aliasing"] == max(va), (out, e[out])
        # H = 7, N_t = 128 on a two-DOF Jenkins case: percent-level at worst, not zero
        assert 0 < max(vt) < 0.1 and 0 < max(va) < 0.1, (out, max(vt), max(va))
    assert c["seconds"]["error_estimate"] > 0
print("ok: error estimates in frf.csv and summary.json, worst "
      f"{max(c['error_estimate']['amplitude_h1']['truncation'] for c in s['curves']):.1e} (truncation), "
      f"{max(c['error_estimate']['amplitude_h1']['aliasing'] for c in s['curves']):.1e} (aliasing)")
PY
sed 's/output_dof: 1/output_dof: 1\n    error_estimate: false/' "$CASE" >"$WORK/noest.yaml"
run_capture run "$WORK/noest.yaml" -o "$WORK/noest"
[ "$STATUS" -eq 0 ] || fail "error_estimate: false run exited $STATUS: $(cat "$ERR")"
grep -qi nan "$WORK/noest/frf.csv" && fail "frf.csv of error_estimate: false contains nan"
"$PYTHON" - "$WORK/noest/frf.csv" "$WORK/noest/summary.json" <<'PY' || fail "error_estimate: false"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
assert rows and all(r[c] == "" for r in rows for c in r if "_error_" in c), rows[0]
assert all(c["error_estimate"]["points_known"] == 0 and c["error_estimate"]["amplitude_h1"]["truncation"] is None
           for c in s["curves"]), s["curves"][0]["error_estimate"]
print(f"ok: error_estimate: false: {len(rows)} rows with empty error columns")
PY
sed 's/output_dof: 1/output_dof: 1\n    error_estimate: maybe/' "$CASE" >"$WORK/badest.yaml"
refused badest "badest.yaml:[0-9]*:[0-9]*: key 'analysis.frf.error_estimate'" run "$WORK/badest.yaml"

# Set-up errors: one line, exit 2, no output directory.
sed 's/amplitude: \[0.05, 0.5, 1.5\]/amplitude: [0.05, 0.5, 1.5], harmonic: 9/' "$CASE" >"$WORK/h9.yaml"
expect_bad_input run "$WORK/h9.yaml" -o "$WORK/none"
[ ! -e "$WORK/none" ] || fail "a set-up error left $WORK/none behind"
sed 's/kt0: 5.0e3/kt0: -5.0e3/' "$CASE" >"$WORK/neg.yaml"
expect_bad_input run "$WORK/neg.yaml" -o "$WORK/none"
grep -q "neg.yaml:[0-9]*:[0-9]*: key 'contacts\[0\].kt0'" "$ERR" || fail "kt0 error: $(cat "$ERR")"
# max_output_change: every step of each curve changes amplitude_h1 by at most 10 % (relative).
sed 's/^\(    omega: \[70.0, 150.0\].*\)$/\1\n    max_output_change: 0.1/' "$CASE" >"$WORK/smooth.yaml"
grep -q 'max_output_change: 0.1' "$WORK/smooth.yaml" || fail "could not set max_output_change"
run_capture run "$WORK/smooth.yaml" -o "$WORK/smooth"
[ "$STATUS" -eq 0 ] || fail "max_output_change run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/smooth/frf.csv" "$WORK/out/frf.csv" <<'PY' || fail "max_output_change"
import csv, sys
def largest(path):
    rows = list(csv.DictReader(open(path)))
    w = max(abs(float(b["amplitude_h1"]) / float(a["amplitude_h1"]) - 1)
            for a, b in zip(rows, rows[1:]) if a["level"] == b["level"])
    return len(rows), w
(n, w), (n0, w0) = largest(sys.argv[1]), largest(sys.argv[2])
assert w <= 0.1 * (1 + 1e-9) and n >= n0, (n, w, n0, w0)
print(f"ok: max_output_change 0.1: {n} rows, largest change of |X1| {w:.4f} (without: {n0} rows, {w0:.3f})")
PY
finish

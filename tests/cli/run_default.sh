# jointhb run without a case runs the built-in default case and writes wd_sweep.csv, summary.json.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

run_capture run -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run exited $STATUS: $(cat "$ERR")"
[ -s "$OUT" ] && fail "run printed on stdout: $(cat "$OUT")"
grep -q 'built-in default case' "$ERR" || fail "stderr does not say 'built-in default case'"
[ "$(wc -l <"$ERR")" -eq 1 ] || fail "expected one summary line on stderr: $(cat "$ERR")"
grep -q ' s ' "$ERR" || fail "summary line has no timing: $(cat "$ERR")"
CSV="$WORK/out/wd_sweep.csv"
[ -f "$CSV" ] || fail "no wd_sweep.csv"
[ -f "$WORK/out/summary.json" ] || fail "no summary.json"
grep -qi 'nan\|inf' "$CSV" && fail "non-finite value in wd_sweep.csv"
"$PYTHON" - "$CSV" "$WORK/out/summary.json" <<'PY' || fail "run outputs"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert list(rows[0].keys()) == ["amplitude_m", "amplitude_over_gmax", "F_hat_N", "loading_span_m",
    "W_D_J", "W_D_general_J", "W_D_paper_J", "rel_err_general", "rel_err_paper"], rows[0].keys()
assert len(rows) == 25, len(rows)
ratios = [float(r["amplitude_over_gmax"]) for r in rows]
assert ratios[0] == 1e-6 and ratios[-1] == 10.0, (ratios[0], ratios[-1])
assert all(b > a for a, b in zip(ratios, ratios[1:]))
s = json.load(open(sys.argv[2]))
assert s["status"] == "ok", s
assert s["case"] == "built-in" and s["description"] == "built-in default case", s
assert s["points"] == 25 and s["points_completed"] == 25, s
assert s["jointhb_version"], s
for key in ["max_rel_err_general", "max_rel_err_paper", "seconds", "inputs"]:
    assert key in s, key
assert s["max_rel_err_general"] == max(float(r["rel_err_general"]) for r in rows)
print(f"ok: 25 points in {s['seconds']:.3f} s, max rel. err. general {s['max_rel_err_general']:.2e}"
      f", paper {s['max_rel_err_paper']:.2e}")
PY

# The default output directory is ./jointhb-out.
(cd "$WORK" && "$JOINTHB" run 2>/dev/null) || fail "run in $WORK exited $?"
[ -f "$WORK/jointhb-out/summary.json" ] || fail "no jointhb-out/summary.json by default"

# An output path that is a file is bad input.
touch "$WORK/a-file"
expect_bad_input run -o "$WORK/a-file"

# A failure after the output directory exists still leaves a summary.json with status "failed".
mkdir -p "$WORK/blocked/wd_sweep.csv"
run_capture run -o "$WORK/blocked"
[ "$STATUS" -eq 1 ] || fail "run into a blocked wd_sweep.csv exited $STATUS, expected 1"
[ "$(wc -l <"$ERR")" -eq 1 ] || fail "expected one line on stderr: $(cat "$ERR")"
"$PYTHON" -c 'import json,sys; s=json.load(open(sys.argv[1])); assert s["status"]=="failed" and "wd_sweep.csv" in s["message"], s' \
  "$WORK/blocked/summary.json" || fail "summary.json of a failed run"
finish

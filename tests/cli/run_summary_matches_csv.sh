# A curve that ends early leaves a summary.json that describes exactly the rows of its CSV
# (issue 20, items 2 and 3): the damping curve of case 03 driven to log10 q = 300 leaves the range
# the laws are computed in (slip over 1e100 stick ranges near q = 1e100; W_D overflowed near 1e154
# before) and must end there with stop_reason out_of_range, the points it reached and the linear
# values it computed; driven from log10 q = -300 it must give finite energy ratios.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

# check_consistent DIR REASON: summary.json's damping curve lists the rows of backbone.csv.
check_consistent() {
  "$PYTHON" - "$1" "$2" <<'PY'
import csv, json, math, sys
d, reason = sys.argv[1], sys.argv[2]
s = json.load(open(f"{d}/summary.json"))
rows = list(csv.DictReader(open(f"{d}/backbone.csv")))
b = s["backbones"][0]
assert b["stop_reason"] == reason, (b["stop_reason"], b["message"])
assert b["points"] == len(rows) == len(b["curve"]), (b["points"], len(rows), len(b["curve"]))
assert len(rows) > 0, "no points"
assert b["linear_omega"] and b["linear_omega"] > 0, b["linear_omega"]
for r, p in zip(rows, b["curve"]):
    assert abs(float(r["amplitude"]) - p["amplitude"]) <= 1e-12 * p["amplitude"], (r, p)
    # every value finite; an error-estimate column may be empty (not computed at the point)
    assert all(math.isfinite(float(v)) for k, v in r.items() if not ("_error_" in k and v == "")), r
assert s["status"] in ("ok", "failed"), s["status"]
print(f"ok: {d}: {len(rows)} rows = summary points, stop_reason {b['stop_reason']}, "
      f"last q = {float(rows[-1]['amplitude']):.3g}")
PY
}

sed 's/log10_amplitude: \[.*\]/log10_amplitude: [-8, 300]/' \
  "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" >"$WORK/overflow.yaml"
run_capture run "$WORK/overflow.yaml" -o "$WORK/overflow"
[ "$STATUS" -eq 1 ] || fail "log10_amplitude [-8, 300] exited $STATUS, expected 1 (a curve failed)"
grep -q "stick range" "$ERR" || fail "the stop message does not say what left the range: $(cat "$ERR")"
# A failed run ends on its error line, like an FE run, not on a "wrote" line.
tail -n 1 "$ERR" | grep -q "^jointhb run: .*overflow.yaml: failed: .*results so far in" ||
  fail "last line of the failed run: $(tail -n 1 "$ERR")"
grep -q "; wrote " "$ERR" && fail "a failed run printed the 'wrote' line: $(cat "$ERR")"
check_consistent "$WORK/overflow" out_of_range || fail "[-8, 300]: summary.json does not match backbone.csv"

sed 's/log10_amplitude: \[.*\]/log10_amplitude: [-300, -3.5]/' \
  "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" >"$WORK/tiny.yaml"
run_capture run "$WORK/tiny.yaml" -o "$WORK/tiny"
check_consistent "$WORK/tiny" reached_end || fail "[-300, -3.5]: summary.json does not match backbone.csv ($(cat "$ERR"))"
finish

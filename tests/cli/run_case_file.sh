# jointhb run on the shipped case cases/01-contact-loop/case.yaml.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/01-contact-loop/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
grep -q "case.yaml" "$ERR" || fail "summary line does not name the case: $(cat "$ERR")"
"$PYTHON" - "$WORK/out/wd_sweep.csv" "$WORK/out/summary.json" "$CASE" <<'PY' || fail "outputs"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
assert s["status"] == "ok" and s["case"] == sys.argv[3], s
assert len(rows) == s["inputs"]["points"] == s["points_completed"], (len(rows), s)
# The general-n formula holds to round-off along the whole sweep (docs/theory.md).
assert s["max_rel_err_general"] < 1e-9, s["max_rel_err_general"]
print(f"ok: {len(rows)} points, max rel. err. general {s['max_rel_err_general']:.2e}, "
      f"paper {s['max_rel_err_paper']:.2e}")
PY
finish

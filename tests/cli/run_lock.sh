# One run per output directory (docs/cli.md "One run per output directory"): a second run on a
# directory that another run is using is refused (exit 2, one line naming the directory and the
# other run's PID) and writes nothing; the first completes with intact files. Two runs on the same
# -o used to interleave rows and tear lines in frf.csv with exit 0 (issue 20).
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
FAST="$SOURCE_DIR/cases/01-contact-loop/case.yaml"

# ---- a lock held by another process (flock(1)): refused, with its PID -------------------------
HELD="$WORK/held"
mkdir -p "$HELD"
(exec 9>"$HELD/.jointhb.lock"; flock -x 9; echo "$BASHPID" >&9; exec sleep 60) &
HOLDER=$!
for _ in $(seq 1 500); do [ -s "$HELD/.jointhb.lock" ] && break; sleep 0.01; done
expect_bad_input run "$FAST" -o "$HELD"
grep -q "output directory '$HELD' is in use by another jointhb run (PID $HOLDER;" "$ERR" ||
  fail "the refusal does not name the directory and PID $HOLDER: $(cat "$ERR")"
[ -e "$HELD/summary.json" ] || [ -e "$HELD/wd_sweep.csv" ] && fail "the refused run wrote into $HELD"
expect_bad_input fit "$SOURCE_DIR/cases/10-fit-one-dof/case.yaml" -o "$HELD" --quiet
grep -q "is in use by another jointhb run (PID $HOLDER;" "$ERR" || fail "fit was not refused: $(cat "$ERR")"
kill "$HOLDER"; wait "$HOLDER" 2>/dev/null
run_capture run "$FAST" -o "$HELD"
[ "$STATUS" -eq 0 ] || fail "the run after the lock was released exited $STATUS: $(cat "$ERR")"

# ---- two runs on one directory -----------------------------------------------------------------
slow_frf_case "$WORK/slow.yaml"
OUTDIR="$WORK/out"
"$JOINTHB" run "$WORK/slow.yaml" -o "$OUTDIR" >"$WORK/first.out" 2>"$WORK/first.err" &
FIRST=$!
wait_for_rows "$OUTDIR/frf.csv" 2 "$FIRST" || fail "the first run ended before its third row"
[ "$(summary_status "$OUTDIR/summary.json")" = running ] ||
  fail "summary.json of the run in progress says '$(summary_status "$OUTDIR/summary.json")', not running"
run_capture run "$WORK/slow.yaml" -o "$OUTDIR"
SECOND_STATUS=$STATUS
BEFORE=$FAILURES
kill -0 "$FIRST" 2>/dev/null || echo "note: the first run ended while the second was refused"
[ "$SECOND_STATUS" -eq 2 ] || fail "the second run exited $SECOND_STATUS, expected 2"
[ "$(wc -l <"$ERR")" -eq 1 ] || fail "the second run printed more than one line: $(cat "$ERR")"
grep -q "^jointhb run: output directory '$OUTDIR' is in use by another jointhb run (PID $FIRST;" "$ERR" ||
  fail "the second run's error: $(cat "$ERR")"
[ "$FAILURES" -eq "$BEFORE" ] && echo "ok: second run -> $(cat "$ERR")"
wait "$FIRST"
FIRST_STATUS=$?
[ "$FIRST_STATUS" -eq 0 ] || fail "the first run exited $FIRST_STATUS: $(cat "$WORK/first.err")"
"$PYTHON" - "$OUTDIR/frf.csv" "$OUTDIR/summary.json" <<'PY' || fail "the first run's files"
import json, sys
lines = open(sys.argv[1]).read().split("\n")
assert lines[-1] == "", "frf.csv does not end with a newline"
header, rows = lines[0], lines[1:-1]
width = len(header.split(","))
assert header.startswith("level,") and all(len(r.split(",")) == width for r in rows), "torn line"
assert not any(r == header for r in rows), "a second header"
s = json.load(open(sys.argv[2]))
assert s["status"] == "ok", s["status"]
points = [c["points"] for c in s["curves"]]
assert sum(points) == len(rows), (points, len(rows))
levels = [int(float(r.split(",")[0])) for r in rows]
assert levels == sorted(levels), "rows of the levels interleave"
print(f"ok: first run intact, {len(rows)} rows in {len(points)} curves")
PY
[ "$(cat "$OUTDIR/.jointhb.lock")" = "$FIRST" ] || fail "the lock file does not hold the first run's PID"
finish

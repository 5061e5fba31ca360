# Issue 20, item 10: with stderr not a terminal (a pipe, a log, CI) a run prints a plain progress
# line every JOINTHB_PROGRESS_INTERVAL seconds (default 10), naming what it does, and none when it
# is shorter than that, so stderr of short runs is unchanged.
source "$(dirname "$0")/common.inc" "$@"

# A short run at the default interval: no progress line, exactly the final line.
run_capture run "$SOURCE_DIR/cases/01-contact-loop/case.yaml" -o "$WORK/sweep"
[ "$STATUS" -eq 0 ] || fail "case 01 exited $STATUS: $(cat "$ERR")"
grep -q "running for" "$ERR" && fail "a short run printed a progress line: $(cat "$ERR")"
[ "$(wc -l <"$ERR")" -eq 1 ] || fail "case 01 stderr: $(cat "$ERR")"

# A discrete FRF of a few seconds with a 0.3 s interval: plain lines naming the curve and point.
slow_frf_case "$WORK/slow.yaml"
JOINTHB_PROGRESS_INTERVAL=0.3 "$JOINTHB" run "$WORK/slow.yaml" -o "$WORK/slow" >/dev/null 2>"$WORK/slow.err"
STATUS=$?
[ "$STATUS" -eq 0 ] || fail "slow FRF exited $STATUS: $(cat "$WORK/slow.err")"
lines=$(grep -c "^jointhb run: running for [0-9.]* s: frf level [12]/2: omega = " "$WORK/slow.err")
[ "$lines" -ge 2 ] || fail "expected progress lines of the FRF: $(cat "$WORK/slow.err")"
grep -q $'\r' "$WORK/slow.err" && fail "carriage returns in a log"
echo "ok: slow FRF: $lines progress lines, e.g. $(grep -m1 'running for' "$WORK/slow.err")"

# The FE default case: the stages and the damping curve; none after the run's last line.
JOINTHB_PROGRESS_INTERVAL=0.2 "$JOINTHB" run -o "$WORK/fe" >/dev/null 2>"$WORK/fe.err"
STATUS=$?
[ "$STATUS" -eq 0 ] || fail "default case exited $STATUS: $(cat "$WORK/fe.err")"
grep -q "^jointhb run: running for [0-9.]* s: \(assembly of the model\|preload\|modes\|condensation\|damping curve of mode 1\)" \
  "$WORK/fe.err" || fail "no progress line of the FE stages: $(cat "$WORK/fe.err")"
sed -n '/^done in/,$p' "$WORK/fe.err" | grep -q "running for" && fail "progress after 'done': $(cat "$WORK/fe.err")"
echo "ok: FE default case: $(grep -c 'running for' "$WORK/fe.err") progress lines"

# A bad interval is bad input, named, before anything is written.
JOINTHB_PROGRESS_INTERVAL=abc run_capture run "$SOURCE_DIR/cases/01-contact-loop/case.yaml" -o "$WORK/bad"
[ "$STATUS" -eq 2 ] || fail "bad interval exited $STATUS"
grep -q "key 'JOINTHB_PROGRESS_INTERVAL': must be a number of seconds > 0, got 'abc'" "$ERR" || fail "message: $(cat "$ERR")"
[ ! -e "$WORK/bad" ] || fail "a bad interval created the output directory"
finish

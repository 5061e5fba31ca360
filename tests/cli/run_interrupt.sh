# summary.json tells a finished run from one that is not (docs/cli.md "summary.json while the run
# goes on"): "running" from the start, "interrupted" with exit code 130/143 after SIGINT/SIGTERM,
# and "running" left behind by SIGKILL, which cannot be caught. An interrupted run used to leave an
# intermediate summary.json that looked like a finished one (issue 20). Rows flushed before the
# signal stay whole.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
set -m  # background jobs get the default SIGINT action (a script's would ignore it)
slow_frf_case "$WORK/slow.yaml"

# start_run DIR: the slow run in the background (PID in RUN), once it has written 3 rows.
start_run() {
  "$JOINTHB" run "$WORK/slow.yaml" -o "$1" >"$1.out" 2>"$1.err" &
  RUN=$!
  wait_for_rows "$1/frf.csv" 2 "$RUN" || fail "$1: the run ended before its third row: $(cat "$1.err")"
  [ "$(summary_status "$1/summary.json")" = running ] ||
    fail "$1: summary.json of the run in progress says '$(summary_status "$1/summary.json")'"
}

# check_rows DIR: frf.csv has whole lines only.
check_rows() {
  "$PYTHON" - "$1/frf.csv" <<'PY' || fail "$1/frf.csv"
import sys
lines = open(sys.argv[1]).read().split("\n")
assert lines[-1] == "" and all(len(l.split(",")) == len(lines[0].split(",")) for l in lines[1:-1])
PY
}

for signal in INT TERM; do
  BEFORE=$FAILURES
  DIR="$WORK/$signal"
  start_run "$DIR"
  kill -"$signal" "$RUN"
  wait "$RUN" 2>/dev/null
  CODE=$?
  expected=$([ "$signal" = INT ] && echo 130 || echo 143)
  [ "$CODE" -eq "$expected" ] || fail "SIG$signal: exit code $CODE, expected $expected"
  "$PYTHON" - "$DIR/summary.json" "SIG$signal" <<'PY' || fail "SIG$signal: summary.json"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["status"] == "interrupted", s["status"]
assert s["termination"] == "stopped_by_user" and s["ok"] is False, s
assert s["message"] == "interrupted by " + sys.argv[2], s["message"]
assert list(s)[:4] == ["jointhb_version", "status", "termination", "ok"], list(s)[:4]
assert s["case"].endswith("slow.yaml") and s["analyses"] == ["frf"]
PY
  grep -q "^jointhb run: interrupted by SIG$signal (.*summary.json: \"status\": \"interrupted\")$" "$DIR.err" ||
    fail "SIG$signal: stderr: $(cat "$DIR.err")"
  grep -q '^$' "$DIR.err" && fail "SIG$signal: a blank line on stderr (not a terminal)"
  check_rows "$DIR"
  [ "$FAILURES" -eq "$BEFORE" ] && echo "ok: SIG$signal -> exit $CODE, $(($(wc -l <"$DIR/frf.csv") - 1)) rows kept, status interrupted"
done

# SIGKILL: nothing can run; "running" stays, and the kernel released the lock.
BEFORE=$FAILURES
DIR="$WORK/KILL"
start_run "$DIR"
kill -KILL "$RUN"
wait "$RUN" 2>/dev/null
[ "$(summary_status "$DIR/summary.json")" = running ] ||
  fail "SIGKILL: summary.json says '$(summary_status "$DIR/summary.json")', not running"
check_rows "$DIR"
run_capture run "$SOURCE_DIR/cases/01-contact-loop/case.yaml" -o "$DIR"
[ "$STATUS" -eq 0 ] || fail "a run after SIGKILL on the same directory exited $STATUS: $(cat "$ERR")"
[ "$(summary_status "$DIR/summary.json")" = ok ] || fail "the next run's summary.json is not ok"
[ "$FAILURES" -eq "$BEFORE" ] && echo "ok: SIGKILL -> summary.json stays running; the next run on the directory is not refused"
finish

# jointhb fit interrupted part-way (SIGTERM once the history has 15 rows: a background job of a
# script ignores SIGINT, and the default actions of both end the process alike) keeps its history, and
# --resume then gives exactly the result of an uninterrupted run. The two runs use different
# OpenMP thread counts: the fit does not depend on it. (If the machine is so fast that the fit
# ends before the signal, the resume replays everything; the checks hold all the same.)
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/10-fit-one-dof/case.yaml"

OMP_NUM_THREADS=1 "$JOINTHB" fit "$CASE" -o "$WORK/reference" --quiet >/dev/null 2>"$WORK/ref.err" ||
  fail "reference run: $(cat "$WORK/ref.err")"

OMP_NUM_THREADS=2 "$JOINTHB" fit "$CASE" -o "$WORK/cut" --quiet >/dev/null 2>/dev/null &
PID=$!
for _ in $(seq 1 3000); do  # poll for up to ~30 s
  rows=$( (wc -l <"$WORK/cut/fit_history.csv") 2>/dev/null || echo 0)
  [ "$rows" -ge 16 ] && break
  kill -0 "$PID" 2>/dev/null || break
  sleep 0.01
done
kill -TERM "$PID" 2>/dev/null
wait "$PID"
KEPT=$(($(wc -l <"$WORK/cut/fit_history.csv") - 1))
[ "$KEPT" -ge 15 ] || fail "the interrupted run kept $KEPT rows"
[ -e "$WORK/cut/fit.json" ] && echo "note: the fit ended before the signal"

OMP_NUM_THREADS=2 "$JOINTHB" fit "$CASE" -o "$WORK/cut" --resume --quiet >/dev/null 2>"$WORK/resume.err" ||
  fail "resume: $(cat "$WORK/resume.err")"
"$PYTHON" - "$WORK/reference/fit.json" "$WORK/cut/fit.json" "$KEPT" <<'PY' || fail "resumed result"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
kept = int(sys.argv[3])
assert [p["value"] for p in a["parameters"]] == [p["value"] for p in b["parameters"]], (a, b)
assert [p["standard_error"] for p in a["parameters"]] == [p["standard_error"] for p in b["parameters"]]
assert a["objective"] == b["objective"] and a["evaluations"] == b["evaluations"]
assert kept <= b["replayed_evaluations"] <= kept + 1, (kept, b["replayed_evaluations"])
assert b["model_evaluations"] == a["evaluations"] - b["replayed_evaluations"]
print(f"ok: interrupted after {kept} evaluations, resumed to the reference optimum "
      f"({b['model_evaluations']} new of {a['evaluations']})")
PY
finish

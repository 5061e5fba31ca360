# jointhb fit with parallel starts: a four-start fit of case 10's synthetic backbone gives the same
# fit.json (but for its times and the parallel section) and the same fit_history.csv on one and two
# local worker processes and on two MPI ranks, and so do direct and mlsl (their batches spread); a history cut short resumes on two workers to the
# same result; -j with a single start says that the search itself runs in one process.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
cp "$SOURCE_DIR/cases/10-fit-one-dof/measured_backbone.csv" "$WORK/"

source "$(dirname "$0")/fit_common.inc"
PARAMETERS='    - {name: "contacts[0].normal_force", lower: 0.5, upper: 50.0, start: 20.0, log_scale: true}
    - {name: "contacts[0].kt0", lower: 3.0e3, upper: 3.0e5, start: 1.0e4, log_scale: true}'
write_case "$WORK/fit.yaml" "$PARAMETERS" "  multistart: {starts: 4, seed: 2}"

# same_fit A B: fit.json equal but for seconds and parallel (and, with a third argument, the
# replayed/new split of the evaluations); fit_history.csv and fit_curves.csv byte for byte.
same_fit() {
  "$PYTHON" - "$1/fit.json" "$2/fit.json" "${3:-}" <<'PY' || fail "fit.json differs between $1 and $2"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
drop = ["seconds", "parallel"] + (["replayed_evaluations", "model_evaluations"] if sys.argv[3] else [])
for k in drop:
    a.pop(k, None); b.pop(k, None)
if a != b:
    for k in a:
        if a.get(k) != b.get(k):
            print(f"{k}: {a.get(k)} != {b.get(k)}", file=sys.stderr)
    sys.exit(1)
PY
  [ -n "${3:-}" ] && return
  cmp -s "$1/fit_history.csv" "$2/fit_history.csv" || fail "fit_history.csv differs between $1 and $2"
  cmp -s "$1/fit_curves.csv" "$2/fit_curves.csv" || fail "fit_curves.csv differs between $1 and $2"
}

run_capture fit "$WORK/fit.yaml" -o "$WORK/one" -j 1
[ "$STATUS" -eq 0 ] || fail "fit -j 1 exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/one" <<'PY' || fail "fit -j 1 outputs"
import csv, json, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "fit.json")))
assert [t["start"] for t in s["starts"]] == [0, 1, 2, 3], s["starts"]
assert s["parallel"] == {"jobs": 1, "ranks": 1}, s["parallel"]
rows = list(csv.DictReader(open(os.path.join(d, "fit_history.csv"))))
assert len(rows) == s["evaluations"], (len(rows), s["evaluations"])
assert [int(r["eval"]) for r in rows] == list(range(1, len(rows) + 1))
starts = [int(r["start"]) for r in rows]
order = [k for i, k in enumerate(starts) if i == 0 or starts[i - 1] != k]
assert order == [0, 1, 2, 3, -1], order  # by start, then the Jacobian
for t in s["starts"]:
    assert t["evaluations"] == starts.count(t["start"]), t
PY
run_capture fit "$WORK/fit.yaml" -o "$WORK/two" -j 2
[ "$STATUS" -eq 0 ] || fail "fit -j 2 exited $STATUS: $(cat "$ERR")"
grep -q "note:" "$ERR" && fail "-j 2 with four starts printed a note: $(cat "$ERR")"
same_fit "$WORK/one" "$WORK/two"
if command -v mpirun >/dev/null; then
  mpirun --allow-run-as-root --oversubscribe -np 2 "$JOINTHB" fit "$WORK/fit.yaml" -o "$WORK/mpi" >"$WORK/mpi.out" 2>"$WORK/mpi.err"
  [ $? -eq 0 ] || fail "mpirun -np 2 fit failed: $(tail -3 "$WORK/mpi.err")"
  grep -q '"ranks": 2' "$WORK/mpi/fit.json" || fail "mpirun -np 2: fit.json does not say 2 ranks"
  same_fit "$WORK/one" "$WORK/mpi"
else
  echo "note: no mpirun, the two-rank run is not tested"
fi

# Interrupted after 30 rows (the last line half written), resumed on two workers.
mkdir -p "$WORK/cut"
head -n 31 "$WORK/one/fit_history.csv" >"$WORK/cut/fit_history.csv"
sed -n 32p "$WORK/one/fit_history.csv" | head -c 20 >>"$WORK/cut/fit_history.csv"
run_capture fit "$WORK/fit.yaml" -o "$WORK/cut" -j 2 --resume
[ "$STATUS" -eq 0 ] || fail "fit -j 2 --resume exited $STATUS: $(cat "$ERR")"
same_fit "$WORK/one" "$WORK/cut" resumed
"$PYTHON" - "$WORK/cut/fit.json" <<'PY' || fail "--resume counts"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["replayed_evaluations"] == 30, s["replayed_evaluations"]
assert s["model_evaluations"] == s["evaluations"] - 30
PY

# The global searches spread their batches (docs/identification.md §2): direct and mlsl give the
# same fit on one and two workers and on two MPI ranks, without a note.
for algorithm in direct mlsl; do
  write_case "$WORK/$algorithm.yaml" "$PARAMETERS" "  algorithm: $algorithm
  max_evaluations: 60"
  run_capture fit "$WORK/$algorithm.yaml" -o "$WORK/$algorithm-one" -j 1
  [ "$STATUS" -eq 0 ] || fail "$algorithm -j 1 exited $STATUS: $(cat "$ERR")"
  run_capture fit "$WORK/$algorithm.yaml" -o "$WORK/$algorithm-two" -j 2
  [ "$STATUS" -eq 0 ] || fail "$algorithm -j 2 exited $STATUS: $(cat "$ERR")"
  grep -q "note:" "$ERR" && fail "$algorithm -j 2 printed a note: $(cat "$ERR")"
  same_fit "$WORK/$algorithm-one" "$WORK/$algorithm-two"
  if command -v mpirun >/dev/null; then
    mpirun --allow-run-as-root --oversubscribe -np 2 "$JOINTHB" fit "$WORK/$algorithm.yaml" \
      -o "$WORK/$algorithm-mpi" >"$WORK/mpi.out" 2>"$WORK/mpi.err"
    [ $? -eq 0 ] || fail "$algorithm: mpirun -np 2 fit failed: $(tail -3 "$WORK/mpi.err")"
    same_fit "$WORK/$algorithm-one" "$WORK/$algorithm-mpi"
  fi
done

# One start: -j 2 cannot spread the search, and says so.
write_case "$WORK/single.yaml" "$PARAMETERS"
run_capture fit "$WORK/single.yaml" -o "$WORK/single" -j 2
[ "$STATUS" -eq 0 ] || fail "single start -j 2 exited $STATUS: $(cat "$ERR")"
grep -q "note: 2 workers, but a single start" "$ERR" || fail "-j 2 with one start: no note: $(cat "$ERR")"
expect_bad_input fit "$WORK/fit.yaml" -o "$WORK/bad" -j 0

[ "$FAILURES" -eq 0 ] || exit 1
echo "fit_parallel: ok"

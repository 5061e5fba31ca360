# jointhb study on the lap (case 16): 100 damping curves on a 10 x 10 grid of friction coefficient
# and damping ratio, on one process with two local workers (interrupted by SIGINT and resumed) and
# on two MPI ranks: the same table bit for bit; the linear limit of every curve (q = 1e-8) has the sample's damping ratio and a
# frequency that does not depend on it. To keep the test short the curves are traced to
# q = 3.8e-7 only (the outputs end there) with at least 4 points per decade (the case has 8).
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
sed -e 's/^  amplitudes: .*/  amplitudes: [1.0e-8, 1.0e-7, 3.0e-7]/' -e 's/^    points_per_decade: 8/    points_per_decade: 4/' \
  "$SOURCE_DIR/cases/16-study-lap/case.yaml" >"$WORK/case.yaml"
grep -q "amplitudes: \[1.0e-8, 1.0e-7, 3.0e-7\]" "$WORK/case.yaml" || fail "the amplitudes were not replaced"
grep -q "points_per_decade: 4" "$WORK/case.yaml" || fail "points_per_decade was not replaced"
# Interrupted after its first sample (SIGINT): the running samples finish, the files say
# stopped_by_user, exit 130; then --resume computes the rest. The resumed table must equal the
# uninterrupted two-rank run's below.
set -m  # the background job gets the default SIGINT action (a script's would ignore it)
"$JOINTHB" study "$WORK/case.yaml" -o "$WORK/local" -j 2 >"$WORK/int.out" 2>"$WORK/int.err" &
pid=$!
set +m
for _ in $(seq 1 600); do
  ls "$WORK/local/samples/"sample_*.json >/dev/null 2>&1 && break
  sleep 0.05
done
kill -INT "$pid"
wait "$pid" 2>/dev/null
STATUS=$?
[ "$STATUS" -eq 130 ] || fail "interrupted study exited $STATUS, expected 130: $(tail -2 "$WORK/int.err")"
grep -q "interrupted by SIGINT" "$WORK/int.err" || fail "no interrupt line: $(tail -2 "$WORK/int.err")"
"$PYTHON" - "$WORK/local" <<'PY' || fail "interrupted study outputs"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "study.json")))
assert s["status"] == "stopped_by_user" and s["counts"]["not_run"] > 0, (s["status"], s["counts"])
assert s["counts"]["computed"] == len(os.listdir(os.path.join(sys.argv[1], "samples"))), s["counts"]
PY
run_capture study "$WORK/case.yaml" -o "$WORK/local" -j 2 --resume --quiet
[ "$STATUS" -le 1 ] || fail "study -j 2 --resume exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/local" <<'PY' || fail "lap study outputs"
import csv, json, os, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(d, "study.csv"))))
assert len(rows) == 100, len(rows)
s = json.load(open(os.path.join(d, "study.json")))
assert s["counts"]["computed"] + s["counts"]["reused"] == 100 and s["counts"]["reused"] > 0, s["counts"]
# Known (issue 23): at one or two friction values the curves stop at the slip onset (q ~ 2.4e-7,
# step below min_step), all ten damping ratios alike; which values depends on the end of the curve
# (mu = 0.28 with outputs to 1e-5, mu = 0.26 with outputs to 3e-7, as case 08 with that mu).
# Every failure must be that stop, and at least 80 samples converge.
bad = [r for r in rows if r["termination"] != "converged"]
assert len(bad) <= 20, len(bad)
for f in s["failed_samples"]:
    assert "below min_step" in f["message"], f
print("failed at mu:", sorted({r["interfaces.lap.mu"] for r in bad}))
by_mu = {}
for r in rows:
    zeta, ratio = float(r["mode1_damping_ratio_q1e-08"]), float(r["damping.ratio"])
    assert abs(zeta / ratio - 1) < 2e-3, (r["sample"], zeta, ratio)  # the linear limit: the modal damping
    by_mu.setdefault(r["interfaces.lap.mu"], []).append(float(r["mode1_frequency_hz_q1e-08"]))
for mu, f in by_mu.items():  # the stuck frequency does not depend on the damping ratio
    assert max(f) - min(f) < 1e-6 * max(f), (mu, min(f), max(f))
    assert 950 < min(f) < 970, (mu, f)
PY
if command -v mpirun >/dev/null; then
  mpirun --allow-run-as-root --oversubscribe -np 2 "$JOINTHB" study "$WORK/case.yaml" -o "$WORK/mpi" --quiet >"$WORK/mpi.out" 2>"$WORK/mpi.err"
  for f in study.csv study_statistics.csv study_curves.csv; do
    cmp -s "$WORK/local/$f" "$WORK/mpi/$f" || fail "$f differs between one process (2 workers) and 2 ranks"
  done
  grep -q '"ranks": 2' "$WORK/mpi/study.json" || fail "mpirun -np 2: study.json does not say 2 ranks"
else
  fail "mpirun not found (bash .ci/setup installs openmpi-bin)"
fi
[ "$FAILURES" -eq 0 ] || exit 1
echo "all lap study checks passed"

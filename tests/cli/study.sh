# jointhb study on a 1-DOF Jenkins oscillator: the outputs and their columns, the same table from
# one and two local workers and from two MPI ranks, a restart that reuses the sample files, a
# failed sample, and bad study sections (one line naming FILE:LINE:COL and the key, exit code 2).
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

write_case() {  # write_case FILE STUDY_BLOCK
  cat >"$1" <<YAML
model: {type: discrete, mass: 1.0, stiffness: 1.0e4, damping: {modal: [0.002]}}
contacts:
  - {law: jenkins, dofs: [0], kt0: 1.0e4, mu: 0.2, normal_force: 20.0}
analysis:
  nonlinear_modes: {mode: 1, log10_amplitude: [-5, -2], harmonics: 3}
study:
$2
YAML
}

GOOD='  sampling: latin_hypercube
  samples: 16
  seed: 3
  parameters:
    - {name: "contacts[0].kt0", lower: 3.0e3, upper: 3.0e4, log_scale: true}
    - {name: "contacts[0].normal_force", lower: 5, upper: 50}
  amplitudes: [1.0e-5, 1.0e-4, 1.0e-3, 3.0e-3]
  quantiles: [0.1, 0.5, 0.9]'
write_case "$WORK/study.yaml" "$GOOD"
run_capture study "$WORK/study.yaml" -o "$WORK/one" -j 1
[ "$STATUS" -eq 0 ] || fail "study -j 1 exited $STATUS: $(cat "$ERR")"
for f in study.csv study_statistics.csv study_curves.csv study.json samples/sample_000015.json; do
  [ -s "$WORK/one/$f" ] || fail "missing $f"
done
"$PYTHON" - "$WORK/one" <<'PY' || fail "study outputs"
import csv, json, os, sys
d = sys.argv[1]
s = json.load(open(os.path.join(d, "study.json")))
assert s["status"] == "converged", s["status"]
assert s["counts"] == {"computed": 16, "reused": 0, "failed": 0, "not_run": 0}, s["counts"]
rows = list(csv.DictReader(open(os.path.join(d, "study.csv"))))
assert len(rows) == 16
cols = list(rows[0].keys())
assert cols[:3] == ["sample", "contacts[0].kt0", "contacts[0].normal_force"], cols
assert cols[3:5] == ["mode1_frequency_hz_q1e-05", "mode1_damping_ratio_q1e-05"], cols
assert cols[-1] == "termination" and all(r["termination"] == "converged" for r in rows)
for r in rows:  # the stuck limit: f = sqrt(k + kt0) / 2 pi at q = 1e-5 when it is below the slip amplitude
    kt, fn = float(r["contacts[0].kt0"]), float(r["contacts[0].normal_force"])
    if 1e-5 < 0.2 * fn / kt / 2:
        f = float(r["mode1_frequency_hz_q1e-05"])
        assert abs(f / ((1e4 + kt) ** 0.5 / (2 * 3.141592653589793)) - 1) < 1e-6, (r, f)
stats = list(csv.DictReader(open(os.path.join(d, "study_statistics.csv"))))
assert len(stats) == 8 and list(stats[0].keys())[-5:] == ["q0.1", "q0.5", "q0.9", "curve", "quantity"], stats[0].keys()
for st in stats:  # the statistics of the table's own column
    col = [float(r[f"mode1_{st['quantity']}_q{float(st['abscissa']):g}"]) for r in rows]
    assert abs(float(st["mean"]) - sum(col) / len(col)) <= 1e-12 * abs(sum(col) / len(col)), st
    assert float(st["min"]) == min(col) and float(st["max"]) == max(col)
curves = list(csv.DictReader(open(os.path.join(d, "study_curves.csv"))))
assert {r["sample"] for r in curves} == {str(i) for i in range(16)}
PY
run_capture study "$WORK/study.yaml" -o "$WORK/two" -j 2
[ "$STATUS" -eq 0 ] || fail "study -j 2 exited $STATUS: $(cat "$ERR")"
for f in study.csv study_statistics.csv study_curves.csv; do
  cmp -s "$WORK/one/$f" "$WORK/two/$f" || fail "$f differs between -j 1 and -j 2"
done
if command -v mpirun >/dev/null; then
  mpirun --allow-run-as-root --oversubscribe -np 2 "$JOINTHB" study "$WORK/study.yaml" -o "$WORK/mpi" >"$WORK/mpi.out" 2>"$WORK/mpi.err"
  [ $? -eq 0 ] || fail "mpirun -np 2 study failed: $(tail -3 "$WORK/mpi.err")"
  grep -q "on 2 ranks" "$WORK/mpi.err" || fail "mpirun -np 2: not run on 2 ranks: $(tail -2 "$WORK/mpi.err")"
  for f in study.csv study_statistics.csv study_curves.csv; do
    cmp -s "$WORK/one/$f" "$WORK/mpi/$f" || fail "$f differs between one process and two ranks"
  done
else
  echo "note: no mpirun, the two-rank run is not tested"
fi

# A restart: every sample reused, the same table; a removed sample file is computed again.
rm "$WORK/two/samples/sample_000003.json"
run_capture study "$WORK/study.yaml" -o "$WORK/two" -j 2 --resume
[ "$STATUS" -eq 0 ] || fail "--resume exited $STATUS: $(cat "$ERR")"
grep -q "1 computed, 15 reused" "$ERR" || fail "--resume: $(tail -1 "$ERR")"
cmp -s "$WORK/one/study.csv" "$WORK/two/study.csv" || fail "study.csv differs after --resume"

# A sample the model rejects fails alone: exit 1, the table says which, study.json why.
write_case "$WORK/fails.yaml" '  sampling: list
  parameters:
    - {name: "contacts[0].kt0", values: [1.0e4, 0.0, 2.0e4]}
  amplitudes: [1.0e-5]'
run_capture study "$WORK/fails.yaml" -o "$WORK/fails" -j 2
[ "$STATUS" -eq 1 ] || fail "a failed sample: exit $STATUS, expected 1"
"$PYTHON" - "$WORK/fails" <<'PY' || fail "failed-sample outputs"
import csv, json, os, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(d, "study.csv"))))
assert [r["termination"] for r in rows] == ["converged", "failed", "converged"], rows
assert rows[1]["mode1_frequency_hz_q1e-05"] == "", rows[1]
s = json.load(open(os.path.join(d, "study.json")))
assert s["status"] == "no_convergence" and s["failed_samples"][0]["sample"] == 1, s
assert "kt0" in s["failed_samples"][0]["message"], s["failed_samples"]
PY

# Bad study sections: FILE:LINE:COL, the key, the constraint.
bad() {  # bad NAME PATTERN STUDY_BLOCK
  write_case "$WORK/$1.yaml" "$3"
  expect_bad_input study "$WORK/$1.yaml" -o "$WORK/$1"
  grep -q -- "$2" "$ERR" || fail "$1: message does not match '$2': $(cat "$ERR")"
}
bad unknown_name "study.parameters\[0\].name.*unknown parameter 'contacts\[0\].k'" '  sampling: sobol
  samples: 4
  parameters: [{name: "contacts[0].k", lower: 1, upper: 2}]'
bad no_samples "study.samples.*required by latin_hypercube" '  sampling: latin_hypercube
  parameters: [{name: "contacts[0].mu", lower: 0.1, upper: 0.2}]'
bad values_in_sobol "study.parameters\[0\].values.*not used by sobol" '  sampling: sobol
  samples: 4
  parameters: [{name: "contacts[0].mu", values: [0.1, 0.2]}]'
bad list_lengths "study.parameters\[1\].values.*as many values" '  sampling: list
  parameters:
    - {name: "contacts[0].mu", values: [0.1, 0.2]}
    - {name: "contacts[0].kt0", values: [1.0e4]}'
bad amplitude_range "study.amplitudes\[1\].*must lie in \[1e-05, 0.01)" '  sampling: grid
  parameters: [{name: "contacts[0].mu", values: [0.1, 0.2]}]
  amplitudes: [1.0e-4, 0.5]'
bad quantile_order "study.quantiles\[1\].*larger than the one before" '  sampling: grid
  parameters: [{name: "contacts[0].mu", values: [0.1]}]
  quantiles: [0.5, 0.5]'
bad kind "study.sampling.*one of" '  sampling: monte_carlo
  parameters: [{name: "contacts[0].mu", values: [0.1]}]'
bad seed_sobol "study.seed.*only latin_hypercube" '  sampling: sobol
  samples: 4
  seed: 2
  parameters: [{name: "contacts[0].mu", lower: 0.1, upper: 0.2}]'
expect_bad_input study "$WORK/study.yaml" -o "$WORK/j0" -j 0
write_case "$WORK/nostudy.yaml" '  sampling: grid
  parameters: [{name: "contacts[0].mu", values: [0.1]}]'
sed -i '/^study:/,$d' "$WORK/nostudy.yaml"
expect_bad_input study "$WORK/nostudy.yaml" -o "$WORK/nostudy"
grep -q "no study section" "$ERR" || fail "no study section: $(cat "$ERR")"

[ "$FAILURES" -eq 0 ] || exit 1
echo "all study checks passed"

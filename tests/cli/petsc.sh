# The PETSc path of the FE stages (docs/distributed.md): the damping curve of the lap (case 08:
# preload, modes, condensation, harmonic balance) with MUMPS factorisations and SLEPc modes on two
# MPI ranks and on one, against the CHOLMOD/ARPACK path: contact pressures, elastic frequencies and
# the curve agree to round-off amplified by the solves (bounds below, measured values ~1e-14, 1e-10,
# 1e-11). The same on two ranks with no factor at all (--linear-algebra petsc-gamg: CG with GAMG to
# 1e-10, SLEPc with the rigid-body modes deflated), to the iterative tolerance (measured ~1e-14 for the
# pressures, 3e-11 for the frequencies and the curve). Then the refusals: a discrete case, an unknown
# value, --cg-tolerance without an iterative path, `mpirun -np 2` without the PETSc path.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
MPIRUN=(mpirun --allow-run-as-root --oversubscribe)
CASE="$SOURCE_DIR/cases/08-lap-damping/case.yaml"
run_capture run "$CASE" -o "$WORK/serial" --no-cache
[ "$STATUS" -eq 0 ] || fail "serial run exited $STATUS: $(tail -2 "$ERR")"
"${MPIRUN[@]}" -np 2 "$JOINTHB" run "$CASE" -o "$WORK/two" --no-cache --linear-algebra petsc \
  >"$WORK/two.out" 2>"$WORK/two.err"
STATUS=$?
[ "$STATUS" -eq 0 ] || fail "mpirun -np 2 --linear-algebra petsc exited $STATUS: $(tail -3 "$WORK/two.err")"
run_capture run "$CASE" -o "$WORK/one" --no-cache --linear-algebra petsc
[ "$STATUS" -eq 0 ] || fail "--linear-algebra petsc on one process exited $STATUS: $(tail -2 "$ERR")"
"${MPIRUN[@]}" -np 2 "$JOINTHB" run "$CASE" -o "$WORK/gamg_two" --no-cache --linear-algebra petsc-gamg \
  >"$WORK/gamg.out" 2>"$WORK/gamg.err"
STATUS=$?
[ "$STATUS" -eq 0 ] || fail "mpirun -np 2 --linear-algebra petsc-gamg exited $STATUS: $(tail -3 "$WORK/gamg.err")"
for d in two one gamg_two; do
  "$PYTHON" - "$WORK/serial" "$WORK/$d" <<'PY' || fail "PETSc path ($d) differs from the serial one"
import csv, json, sys
ref, d = sys.argv[1:]
def column(directory, name, key):
    return [float(r[key]) for r in csv.DictReader(open(f"{directory}/{name}"))]
def worst(name, key, bound, skip=0, relative_to_max=False):
    a, b = column(ref, name, key)[skip:], column(d, name, key)[skip:]
    assert len(a) == len(b) and a, (name, len(a), len(b))
    if relative_to_max:
        e = max(abs(x - y) for x, y in zip(a, b)) / max(abs(x) for x in a)
    else:
        e = max(abs(x - y) / abs(x) for x, y in zip(a, b))
    print(f"{d}: {name} {key}: {e:.2e} (bound {bound:g})")
    assert e <= bound, (name, key, e)
worst("contact_lap.csv", "pressure", 1e-10, relative_to_max=True)
worst("contact_lap.csv", "gap", 1e-9, relative_to_max=True)
worst("modes.csv", "frequency_hz", 1e-8, skip=6)  # the 6 rigid-body modes sit at round-off, ~1e-3 Hz
worst("backbone.csv", "frequency_hz", 1e-8)
worst("backbone.csv", "damping_ratio", 1e-8)
s = json.load(open(f"{d}/summary.json"))
ranks = 2 if d.endswith("two") else 1
if d.endswith("gamg_two"):
    assert s["solvers"] == {"linear": "cg", "eigen": "slepc", "ranks": 2, "preconditioner": "gamg",
                            "relative_tolerance": 1e-10}, s["solvers"]
    assert "CG/GAMG on 2 ranks" in s["preload"]["factor"], s["preload"]["factor"]
else:
    assert s["solvers"] == {"linear": "mumps", "eigen": "slepc", "ranks": ranks}, s["solvers"]
assert s["status"] == json.load(open(f"{ref}/summary.json"))["status"] == "ok", s["status"]
assert all(float(r["backward_error"]) < 1e-12 for r in csv.DictReader(open(f"{d}/modes.csv")))
PY
done
# Ctrl-C on mpirun (which sends SIGTERM to every rank): rank 0 marks summary.json "interrupted"
# (MPI's own threads must not take the signal), the serving rank ends, nothing is left running.
sed -e 's/divisions: \[40, 12, 2\]/divisions: [80, 24, 2]/' "$SOURCE_DIR/cases/05-bolted-lap/case.yaml" >"$WORK/lap20k.yaml"
grep -q "divisions: \[80, 24, 2\]" "$WORK/lap20k.yaml" || fail "the divisions were not replaced"
"${MPIRUN[@]}" -np 2 "$JOINTHB" run "$WORK/lap20k.yaml" -o "$WORK/interrupted" --no-cache --linear-algebra petsc \
  >"$WORK/int.out" 2>"$WORK/int.err" &
for _ in $(seq 1 200); do
  [ -f "$WORK/interrupted/summary.json" ] && break
  sleep 0.05
done
sleep 1
kill -INT "$(jobs -p)" 2>/dev/null
wait
grep -q '"status": "interrupted"' "$WORK/interrupted/summary.json" || fail "no interrupted summary: $(tail -2 "$WORK/int.err")"
grep -q "interrupted by SIG" "$WORK/int.err" || fail "no interrupt line: $(tail -2 "$WORK/int.err")"
pgrep -f "$WORK/lap20k.yaml" >/dev/null && fail "a rank is still running after the interrupt"
# Refusals: one line, exit 2.
expect_bad_input run "$SOURCE_DIR/cases/02-two-dof-frf/case.yaml" -o "$WORK/discrete" --linear-algebra petsc
grep -q "finite-element cases only" "$ERR" || fail "discrete case: $(cat "$ERR")"
expect_bad_input run "$CASE" -o "$WORK/bad" --linear-algebra mpi
expect_bad_input run "$CASE" -o "$WORK/bad" --linear-algebra petsc --cg-tolerance 1e-8
grep -q "petsc-gamg or petsc-hypre only" "$ERR" || fail "--cg-tolerance with petsc: $(cat "$ERR")"
expect_bad_input run "$CASE" -o "$WORK/bad" --linear-algebra petsc-gamg --cg-tolerance 0.5
"${MPIRUN[@]}" -np 2 "$JOINTHB" run "$CASE" -o "$WORK/plain" --no-cache >"$WORK/plain.out" 2>"$WORK/plain.err"
STATUS=$?
[ "$STATUS" -ne 0 ] || fail "mpirun -np 2 without --linear-algebra petsc exited 0"
grep -q "only --linear-algebra petsc uses several ranks" "$WORK/plain.err" || fail "no refusal line: $(cat "$WORK/plain.err")"
[ ! -e "$WORK/plain/summary.json" ] || fail "the refused run wrote summary.json"
finish

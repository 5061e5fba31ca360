# jointhb run on cases/15-normal-contact-fold: the preloaded exponential normal contact (N-3)
# folds the FRF from 2 N on; frf.csv agrees with summary.json's folds and stability counts, the
# unstable rows lie between the folds; the reader's one-line errors for the law's keys and for
# odd harmonics only.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/15-normal-contact-fold/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
grep -q "level 3 (force 8 N): 2 folds" "$ERR" || fail "no fold line for 8 N: $(cat "$ERR")"
"$PYTHON" - "$WORK/out/frf.csv" "$WORK/out/summary.json" <<'PY' || fail "fold outputs"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
assert s["status"] == "ok", s["status"]
folds = [len(c["fold_points"]) for c in s["curves"]]
assert folds == [0, 2, 2, 2], folds
for c in s["curves"]:
    mine = [r for r in rows if int(float(r["level"])) == c["level"]]
    unstable = [float(r["omega"]) for r in mine if r["stable"] == "0"]
    assert len(unstable) == c["stability"]["unstable_points"], (len(unstable), c["stability"])
    marked = [r for r in mine if r["bifurcation"] == "fold"]
    assert len(marked) == len(c["fold_points"]), (len(marked), c["fold_points"])
    assert not [r for r in mine if r["bifurcation"] in ("reversal", "branch_point")], c["level"]
    if c["fold_points"]:
        lo = min(f["omega"] for f in c["fold_points"])
        hi = max(f["omega"] for f in c["fold_points"])
        assert all(lo - 1e-6 * hi <= w <= hi * (1 + 1e-6) for w in unstable), (lo, hi, unstable)
        assert all(f["refined"] and f["omega_error_bound"] < 1e-4 for f in c["fold_points"]), c["fold_points"]
# Softening: the peaks move down as the force grows.
peaks = [c["peak"]["omega"] for c in s["curves"]]
assert peaks == sorted(peaks, reverse=True), peaks
print(f"ok: folds {folds}, peaks {[round(p, 1) for p in peaks]} rad/s")
PY

# The law's own keys: a friction key on it, or kn on a friction law, is a one-line error.
sed 's/kn: 1.0e9}/kn: 1.0e9, mu: 0.3}/' "$CASE" >"$WORK/mu.yaml"
expect_bad_input run "$WORK/mu.yaml" -o "$WORK/mu"
grep -q "contacts\[0\].mu.*not a parameter of law normal-exponential" "$ERR" || fail "mu: $(cat "$ERR")"
sed 's/kn: 1.0e9}/kn: -1.0}/' "$CASE" >"$WORK/kn.yaml"
expect_bad_input run "$WORK/kn.yaml" -o "$WORK/kn"
grep -q "contacts\[0\].kn" "$ERR" || fail "kn: $(cat "$ERR")"
sed 's/law: normal-exponential, dofs: \[0\], normal_force: 2000.0, kn: 1.0e9/law: jenkins, dofs: [0], normal_force: 2000.0, kn: 1.0e9, mu: 0.3/' "$CASE" >"$WORK/jk.yaml"
expect_bad_input run "$WORK/jk.yaml" -o "$WORK/jk"
grep -q "contacts\[0\].kn.*normal-exponential only" "$ERR" || fail "jenkins kn: $(cat "$ERR")"
# Odd harmonics only: the law is not odd, the reader says so at the key.
sed 's/output_dof: 0/output_dof: 0\n    harmonic_selection: odd/' "$CASE" >"$WORK/odd.yaml"
expect_bad_input run "$WORK/odd.yaml" -o "$WORK/odd"
grep -q "analysis.frf.harmonic_selection.*contacts\[0\] is a normal element" "$ERR" || fail "odd: $(cat "$ERR")"
finish

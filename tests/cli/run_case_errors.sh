# jointhb run with a bad case file: exit code 2, one line naming the file, line and key.
source "$(dirname "$0")/common.inc" "$@"

cat >"$WORK/typo.yaml" <<'YAML'
analysis:
  loop_sweep:
    law: gaul-mayer
    mu: 0.3
    normal_forse: 100.0
YAML
expect_bad_input run "$WORK/typo.yaml" -o "$WORK/out"
grep -q "typo.yaml:5:5: key 'analysis.loop_sweep.normal_forse'" "$ERR" ||
  fail "message does not name file:line:column and key: $(cat "$ERR")"
[ -e "$WORK/out" ] && fail "a rejected case created the output directory"

cat >"$WORK/negative.yaml" <<'YAML'
analysis:
  loop_sweep:
    mu: -1
YAML
expect_bad_input run "$WORK/negative.yaml" -o "$WORK/out"
grep -q "negative.yaml:3:9: key 'analysis.loop_sweep.mu': must be > 0, got -1" "$ERR" ||
  fail "negative mu message: $(cat "$ERR")"

printf 'analysis:\n  loop_sweep:\n    kt0: .nan\n' >"$WORK/nan.yaml"
expect_bad_input run "$WORK/nan.yaml" -o "$WORK/out"
grep -q "nan.yaml:3:10: .*must be finite" "$ERR" || fail "nan message: $(cat "$ERR")"

printf 'analysis:\n  loop_sweep: [\n' >"$WORK/syntax.yaml"
expect_bad_input run "$WORK/syntax.yaml" -o "$WORK/out"
grep -q "syntax.yaml:[0-9]*:[0-9]*: invalid YAML" "$ERR" || fail "syntax message: $(cat "$ERR")"

expect_bad_input run "$WORK/missing.yaml" -o "$WORK/out"
grep -q "missing.yaml: cannot open case file" "$ERR" || fail "missing file message: $(cat "$ERR")"

expect_bad_input run "$WORK" -o "$WORK/out"
finish

# jointhb --help, --version and COMMAND --help describe the program; no command is bad input.
source "$(dirname "$0")/common.inc" "$@"

run_capture --help
[ "$STATUS" -eq 0 ] || fail "--help exited $STATUS"
grep -q 'loop' "$OUT" || fail "--help does not mention loop"
grep -q 'run' "$OUT" || fail "--help does not mention run"
grep -q 'Exit codes' "$OUT" || fail "--help does not state the exit codes"

run_capture --version
[ "$STATUS" -eq 0 ] || fail "--version exited $STATUS"
grep -Eq '^jointhb [0-9]+\.[0-9]+\.[0-9]+$' "$OUT" || fail "--version printed '$(cat "$OUT")'"

run_capture loop --help
[ "$STATUS" -eq 0 ] || fail "loop --help exited $STATUS"
for option in --law --n --mu --normal-force --kt0 --amplitude --time-samples --harmonic \
              --normal-amplitude --normal-phase --lambda --kt-follows-normal --json --csv; do
  grep -q -- "$option" "$OUT" || fail "loop --help does not describe $option"
done
grep -q '\[N\]' "$OUT" || fail "loop --help gives no units"

run_capture run --help
[ "$STATUS" -eq 0 ] || fail "run --help exited $STATUS"
grep -q -- '-o' "$OUT" || fail "run --help does not describe -o"
grep -q 'jointhb-out' "$OUT" || fail "run --help does not give the default output directory"

expect_bad_input
expect_bad_input frobnicate
expect_bad_input loop --no-such-option
finish

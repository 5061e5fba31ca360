# Issue 20, item 6: an error is one printable line (bytes echoed from a binary file escaped), and a
# failed FE run ends with one "jointhb run: ..." error line instead of "done".
source "$(dirname "$0")/common.inc" "$@"
LAP="$SOURCE_DIR/cases/08-lap-damping/case.yaml"

# A binary target file: the echoed header stays one printable line (control bytes escaped).
mkdir -p "$WORK/fit"
cp "$SOURCE_DIR/cases/10-fit-one-dof/case.yaml" "$WORK/fit/"
printf 'amp\x0bli\x0ctude\x1b[31m,freq\xc2\x85uency_hz\xe2\x80\xa8x\x00y\n1,2\n' >"$WORK/fit/measured_backbone.csv"
refused fitbin "measured_backbone.csv:1:1: key 'fit.targets\[0\].file': the header must name" fit "$WORK/fit/case.yaml"
if LC_ALL=C grep -q -P '[\x00-\x08\x0b-\x1f\x7f\x80-\xff]' "$ERR"; then
  fail "the message holds control or non-ASCII bytes: $(od -c "$ERR" | head -5)"
fi
grep -q 'amp\\x0Bli\\x0Ctude\\x1B\[31m,freq\\xC2\\x85uency_hz\\xE2\\x80\\xA8x\\x00y' "$ERR" ||
  fail "escaped header: $(cat "$ERR")"

# A preload that does not converge: one error line with the prefix, last, and no "done" line.
sed 's/preload: {load_steps: 4, tolerance: 1.0e-9}/preload: {load_steps: 1, max_iterations: 1, tolerance: 1.0e-12}/' \
  "$LAP" >"$WORK/preload.yaml"
run_capture run "$WORK/preload.yaml" -o "$WORK/preload"
[ "$STATUS" -eq 1 ] || fail "failed preload exited $STATUS, expected 1"
grep -q "done in" "$ERR" && fail "a failed run printed the 'done' line: $(cat "$ERR")"
[ "$(grep -c '^jointhb run: ' "$ERR")" -eq 1 ] || fail "expected one 'jointhb run:' line: $(cat "$ERR")"
tail -n 1 "$ERR" | grep -q "^jointhb run: .*preload.yaml: failed: preload: preload step 1/1 (load factor 1): no convergence" ||
  fail "last line: $(tail -n 1 "$ERR")"
[ "$(summary_status "$WORK/preload/summary.json")" = failed ] || fail "summary.json status of the failed preload"
echo "ok: failed preload -> $(tail -n 1 "$ERR")"
# p_N0 = 1e300 Pa is refused at its key (issue 20, item 3: its products leave the range of
# doubles; before the bound it ended in a non-finite preload residual). At the edge of the range,
# 1e100 Pa, the preload fails numerically as a stage, named as such, with its files and
# summary.json written (item 5), and no nan anywhere.
sed 's/pressure: 1.0e6 /pressure: 1.0e300 /' "$SOURCE_DIR/cases/05-bolted-lap/case.yaml" >"$WORK/huge_pressure.yaml"
refused huge_pressure "contact.pressure': magnitude must lie in \[1e-100, 1e+100\]" run "$WORK/huge_pressure.yaml" --no-cache
sed 's/pressure: 1.0e6 /pressure: 1.0e100 /' "$SOURCE_DIR/cases/05-bolted-lap/case.yaml" >"$WORK/edge_pressure.yaml"
run_capture run "$WORK/edge_pressure.yaml" -o "$WORK/edge_pressure" --no-cache
[ "$STATUS" -eq 1 ] || fail "pressure 1e100 exited $STATUS, expected 1"
tail -n 1 "$ERR" | grep -q "failed: preload: preload step 1/4" || fail "pressure 1e100: $(tail -n 1 "$ERR")"
[ "$(summary_status "$WORK/edge_pressure/summary.json")" = failed ] || fail "summary.json status of the failed preload"
grep -q '^1,0.25,0,0,[0-9.e+]*,0$' "$WORK/edge_pressure/preload_steps.csv" || fail "preload_steps.csv: $(cat "$WORK/edge_pressure/preload_steps.csv")"
grep -qi nan "$WORK/edge_pressure"/*.csv "$WORK/edge_pressure/summary.json" "$ERR" && fail "nan in the outputs of pressure 1e100"
echo "ok: pressure 1e100 -> $(tail -n 1 "$ERR" | cut -c1-120)"
finish

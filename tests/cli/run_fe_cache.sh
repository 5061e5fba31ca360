# The stage cache of jointhb run on a finite-element case (cases/05-bolted-lap): a second run into
# the same directory reads the preload and the modes from DIR/.cache and writes byte-identical
# outputs; --no-cache recomputes; a corrupted cache file is a warning and a miss with the same
# results (and is replaced); --cache-dir puts the cache elsewhere. Timings are printed, not checked.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/05-bolted-lap/case.yaml"
OUTPUTS="preload_steps.csv contact_lap.csv contact_lap.vtu preload.vtu modes.csv modes.vtu"

# check_cache DIR PRELOAD MODES: summary.json says the preload and the modes were a hit or a miss.
check_cache() {
  "$PYTHON" - "$1" "$2" "$3" <<'PY' || fail "cache status in $1 (expected preload $2, modes $3)"
import json, sys
d, want_p, want_m = sys.argv[1:4]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "ok", s["status"]
p, m = s["preload"], s["modes"]
assert p["cache"] == want_p and m["cache"] == want_m, (p["cache"], m["cache"])
assert p["termination"] == "converged" and m["termination"] == "converged"
print(f"  preload {p['cache']}: solve {p['seconds']['total']:.3f} s, cache {p['cache_seconds']:.3f} s;"
      f" modes {m['cache']}: solve {m['seconds']:.3f} s, cache {m['cache_seconds']:.3f} s; run {s['seconds']:.2f} s")
PY
}

# same_outputs A B: every output file of run A is byte-identical to run B's.
same_outputs() {
  for f in $OUTPUTS; do
    cmp -s "$1/$f" "$2/$f" || fail "$f differs between $1 and $2"
  done
}

# 1. First run: both stages computed and stored.
run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "first run exited $STATUS: $(cat "$ERR")"
echo "first run:"; check_cache "$WORK/out" miss miss
ls "$WORK/out/.cache"/preload-*.bin "$WORK/out/.cache"/modes-*.bin >/dev/null 2>&1 || fail "no cache files in $WORK/out/.cache"
mkdir -p "$WORK/first" && for f in $OUTPUTS; do cp "$WORK/out/$f" "$WORK/first/$f"; done

# 2. Second run into the same directory: both stages from the cache, the same files.
rm -f "$WORK/out/contact_lap.csv" "$WORK/out/modes.csv"
run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "second run exited $STATUS: $(cat "$ERR")"
grep -q "^preload: from cache (.*/preload-[0-9a-f]*\.bin)" "$ERR" || fail "no 'preload: from cache' line: $(cat "$ERR")"
grep -q "^modes: from cache (" "$ERR" || fail "no 'modes: from cache' line: $(cat "$ERR")"
grep -q "^warning" "$ERR" && fail "warnings on the second run: $(cat "$ERR")"
echo "second run:"; check_cache "$WORK/out" hit hit
same_outputs "$WORK/first" "$WORK/out"

# 3. --no-cache: computed again, nothing read.
run_capture run "$CASE" -o "$WORK/out" --no-cache
[ "$STATUS" -eq 0 ] || fail "--no-cache exited $STATUS: $(cat "$ERR")"
grep -q "from cache" "$ERR" && fail "--no-cache read the cache: $(cat "$ERR")"
echo "--no-cache:"; check_cache "$WORK/out" miss miss
same_outputs "$WORK/first" "$WORK/out"

# 4. A corrupted preload file (one byte in the middle flipped): a one-line warning, a miss, the
#    same results, and the file is replaced so that the next run hits again.
PRELOAD_FILE=$(ls "$WORK/out/.cache"/preload-*.bin)
"$PYTHON" - "$PRELOAD_FILE" <<'PY'
import sys
b = bytearray(open(sys.argv[1], "rb").read())
b[len(b) // 2] ^= 0xFF
open(sys.argv[1], "wb").write(b)
PY
run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run with a corrupted cache exited $STATUS: $(cat "$ERR")"
[ "$(grep -c "^warning: stage cache: .*preload-.*corrupted" "$ERR")" -eq 1 ] || fail "no corruption warning: $(cat "$ERR")"
echo "corrupted preload file: $(grep '^warning' "$ERR")"
# The preload is recomputed; the modes key is the same, so the modes still come from the cache.
check_cache "$WORK/out" miss hit
same_outputs "$WORK/first" "$WORK/out"
run_capture run "$CASE" -o "$WORK/out"
check_cache "$WORK/out" hit hit

# 5. A truncated modes file: a miss with a warning.
MODES_FILE=$(ls "$WORK/out/.cache"/modes-*.bin)
head -c 1000 "$MODES_FILE" > "$WORK/truncated" && mv "$WORK/truncated" "$MODES_FILE"
run_capture run "$CASE" -o "$WORK/out"
grep -q "^warning: stage cache: .*modes-.*truncated" "$ERR" || fail "no truncation warning: $(cat "$ERR")"
check_cache "$WORK/out" hit miss
same_outputs "$WORK/first" "$WORK/out"

# 6. --cache-dir: the cache goes there; a changed mode count misses the modes only.
run_capture run "$CASE" -o "$WORK/out2" --cache-dir "$WORK/shared-cache"
[ "$STATUS" -eq 0 ] || fail "--cache-dir exited $STATUS: $(cat "$ERR")"
[ -e "$WORK/out2/.cache" ] && fail "--cache-dir still wrote DIR/.cache"
ls "$WORK/shared-cache"/preload-*.bin >/dev/null 2>&1 || fail "no preload file in --cache-dir"
sed 's/modes: {count: 20,/modes: {count: 12,/' "$CASE" > "$WORK/twelve.yaml"
run_capture run "$WORK/twelve.yaml" -o "$WORK/out3" --cache-dir "$WORK/shared-cache"
[ "$STATUS" -eq 0 ] || fail "12 modes exited $STATUS: $(cat "$ERR")"
echo "12 modes, shared cache:"; check_cache "$WORK/out3" hit miss
cmp -s "$WORK/first/contact_lap.csv" "$WORK/out3/contact_lap.csv" || fail "contact_lap.csv differs with 12 modes"

# 7. An unwritable cache directory: a warning, the run goes on.
touch "$WORK/not-a-dir"
run_capture run "$CASE" -o "$WORK/out4" --cache-dir "$WORK/not-a-dir/cache"
[ "$STATUS" -eq 0 ] || fail "unwritable cache exited $STATUS: $(cat "$ERR")"
grep -q "^warning: stage cache: cannot create" "$ERR" || fail "no warning for an unwritable cache: $(cat "$ERR")"
same_outputs "$WORK/first" "$WORK/out4"
finish

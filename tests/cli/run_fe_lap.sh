# jointhb run on cases/05-bolted-lap: the preloaded state of two plates clamped by two bolts and
# the modes about it. Checks equilibrium (clamping force = bolt forces), the pressure field (high
# under the bolts, open away from them), the free-free spectrum, the files for ParaView, and that a
# bad FE case stops with FILE:LINE and exit code 2.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/05-bolted-lap/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
for f in summary.json preload_steps.csv contact_lap.csv contact_lap.vtu preload.vtu modes.csv modes.vtu; do
  [ -s "$WORK/out/$f" ] || fail "missing $f"
done
"$PYTHON" - "$WORK/out" <<'PY' || fail "outputs"
import csv, json, math, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "ok" and s["kind"] == "fe", s["status"]
p = s["preload"]
assert p["termination"] == "converged" and p["ok"] is True and p["load_factor"] == 1.0
assert p["support_reaction_relative"] < 1e-9, p["support_reaction_relative"]
i = p["interfaces"][0]
assert abs(i["clamping_force"] / 10000.0 - 1) < 1e-7, i["clamping_force"]
assert 0.3 < i["closed_area_fraction"] < 0.99, i["closed_area_fraction"]
assert i["max_pressure"] > 3 * i["mean_pressure"]
rows = list(csv.DictReader(open(f"{d}/contact_lap.csv")))
assert len(rows) == i["points"]
near = [float(r["pressure"]) for r in rows if min(math.hypot(float(r["x"]) - bx, float(r["y"]) - 0.015) for bx in (0.07, 0.09)) < 0.003]
far = [float(r["pressure"]) for r in rows if float(r["x"]) < 0.0615 or float(r["x"]) > 0.0985]
assert min(near) > max(far), (min(near), max(far))       # pressure concentrates under the bolts
assert max(float(r["gap"]) for r in rows) > 0.0           # and the interface opens at its ends
m = [float(r["frequency_hz"]) for r in csv.DictReader(open(f"{d}/modes.csv"))]
assert len(m) == 20 and all(abs(f) < 1.0 for f in m[:6]), m[:7]   # six rigid-body modes
assert 300.0 < m[6] < 3000.0 and all(b >= a for a, b in zip(m, m[1:])), m[6]
for f in ("contact_lap.vtu", "preload.vtu", "modes.vtu"):
    head = open(f"{d}/{f}", "rb").read(4096)   # raw appended data follows the XML header
    assert b'<VTKFile type="UnstructuredGrid"' in head, f
print(f"ok: clamping {i['clamping_force']:.6g} N, closed {i['closed_area_fraction']:.3f}, first elastic mode {m[6]:.1f} Hz")
PY

# A bolt footprint away from every face: FILE:LINE, the key, exit 2, nothing written.
sed 's/point: \[0.070, 0.015, 0.0\]/point: [0.5, 0.5, 0.0]/' "$CASE" > "$WORK/bad.yaml"
run_capture run "$WORK/bad.yaml" -o "$WORK/bad"
[ "$STATUS" -eq 2 ] || fail "bad case exited $STATUS"
grep -q "bad.yaml:[0-9]*:[0-9]*: key 'model.bolts\[0\]'.*no face has its centre within" "$ERR" || fail "message: $(cat "$ERR")"
[ ! -e "$WORK/bad/summary.json" ] || fail "bad case wrote output"
# An interface between surfaces that do not match.
sed 's/top: upper.zmin/top: upper.zmax/' "$CASE" > "$WORK/bad2.yaml"
run_capture run "$WORK/bad2.yaml" -o "$WORK/bad2"
[ "$STATUS" -eq 2 ] || fail "bad2 exited $STATUS"
grep -q "bad2.yaml:[0-9]*:[0-9]*: key 'model.interfaces\[0\]" "$ERR" || fail "message: $(cat "$ERR")"
finish

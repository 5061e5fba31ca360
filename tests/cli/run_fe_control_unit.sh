# jointhb run on cases/06-control-unit: the paper's test structure, three plates stacked and
# clamped by four through bolts. Checks the preload (each interface carries the sum of the four
# bolt forces, pressure concentrated under the bolts, the doubly symmetric structure gives a
# doubly symmetric pressure field, the middles open), the free-free spectrum (six rigid-body
# modes, then several elastic modes below 2 kHz as in the paper's Table 1), and the output files.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/06-control-unit/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
for f in summary.json preload_steps.csv preload.vtu modes.csv modes.vtu \
         contact_base-plate.csv contact_base-plate.vtu contact_plate-cover.csv contact_plate-cover.vtu; do
  [ -s "$WORK/out/$f" ] || fail "missing $f"
done
"$PYTHON" - "$WORK/out" <<'PY' || fail "outputs"
import csv, json, math, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "ok" and s["kind"] == "fe", s["status"]
assert s["model"]["parts"] == ["base", "plate", "cover"], s["model"]["parts"]
p = s["preload"]
assert p["termination"] == "converged" and p["load_factor"] == 1.0, p["message"]
assert p["support_reaction_relative"] < 1e-9, p["support_reaction_relative"]
assert len(p["bolts"]) == 4 and all(abs(b["force"] / 5000.0 - 1) < 1e-12 for b in p["bolts"]), p["bolts"]
total = sum(b["force"] for b in p["bolts"])          # every bolt passes through both interfaces
assert [i["name"] for i in p["interfaces"]] == ["base-plate", "plate-cover"]
bolts = [(0.006, 0.006), (0.106, 0.006), (0.006, 0.082), (0.106, 0.082)]
for i in p["interfaces"]:
    assert abs(i["clamping_force"] / total - 1) < 1e-7, (i["name"], i["clamping_force"], total)
    assert 0.05 < i["closed_area_fraction"] < 0.6, (i["name"], i["closed_area_fraction"])
    assert i["max_pressure"] > 5 * i["mean_pressure"], i["name"]
    rows = list(csv.DictReader(open(f"{d}/contact_{i['name']}.csv")))
    assert len(rows) == i["points"] == 28 * 22 * 4, (i["name"], len(rows))
    pres = {(round(float(r["x"]) * 1e4), round(float(r["y"]) * 1e4)): float(r["pressure"]) for r in rows}
    pmax = max(pres.values())
    # doubly symmetric structure, doubly symmetric pressure (the 3-2-1 support carries nothing)
    asym = max(abs(v - pres[(1120 - x, y)]) + abs(v - pres[(x, 880 - y)]) for (x, y), v in pres.items())
    assert asym < 1e-6 * pmax, (i["name"], asym / pmax)
    near = [v for (x, y), v in pres.items() if min(math.hypot(x / 1e4 - bx, y / 1e4 - by) for bx, by in bolts) < 0.003]
    mid = [v for (x, y), v in pres.items() if abs(x - 560) <= 200 and abs(y - 440) <= 200]
    assert min(near) > 100 * max(mid), (i["name"], min(near), max(mid))   # clamped at the bolts
    assert max(float(r["gap"]) for r in rows) > 1e-6, i["name"]            # open between them
m = [float(r["frequency_hz"]) for r in csv.DictReader(open(f"{d}/modes.csv"))]
assert len(m) == 20 and all(abs(f) < 1.0 for f in m[:6]), m[:7]           # six rigid-body modes
assert all(b >= a for a, b in zip(m, m[1:])), m
elastic = [f for f in m[6:] if f < 2000.0]
assert 500.0 < m[6] and len(elastic) >= 6, m[6:14]                        # Table 1: 8 below 2 kHz
for f in ("contact_base-plate.vtu", "contact_plate-cover.vtu", "preload.vtu", "modes.vtu"):
    head = open(f"{d}/{f}", "rb").read(4096)   # raw appended data follows the XML header
    assert b'<VTKFile type="UnstructuredGrid"' in head, f
print(f"ok: clamping {[round(i['clamping_force'], 3) for i in p['interfaces']]} N, "
      f"{len(elastic)} elastic modes below 2 kHz: {', '.join(f'{f:.0f}' for f in elastic)} Hz")
PY

# The case's plotting script (paper Figs 7 and 8 as PNG), where matplotlib is installed.
if "$PYTHON" -c "import matplotlib, numpy" 2>/dev/null; then
  "$PYTHON" "$SOURCE_DIR/cases/06-control-unit/plot_contact.py" "$WORK/out" >"$WORK/plot.log" 2>&1 \
    || fail "plot_contact.py: $(cat "$WORK/plot.log")"
  for f in contact_base-plate.png contact_plate-cover.png; do
    head -c 8 "$WORK/out/$f" 2>/dev/null | grep -q PNG || fail "plot_contact.py wrote no $f"
  done
else
  echo "skip: plot_contact.py (no matplotlib for $PYTHON)"
fi
finish

# cases/14-brake-reuss-beam: the mesh generator writes the shipped deck byte for byte (and the same
# bytes twice), and a coarse version of the case (the same generator with a 4.2 mm seed) runs its
# preload and modes: the bolts' annular footprints, the clamping force, the interface area of the
# lap less the holes, the mass of the drawing and the first elastic modes. The full case (46k DOFs,
# damping curves at H = 3) is not run here: its figures are in the case's README.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE_DIR="$SOURCE_DIR/cases/14-brake-reuss-beam"

cp "$CASE_DIR/make_mesh.py" "$WORK/"
"$PYTHON" "$WORK/make_mesh.py" >/dev/null || fail "make_mesh.py failed"
cmp -s "$WORK/brb.inp" "$CASE_DIR/brb.inp" || fail "brb.inp differs from what make_mesh.py writes"
"$PYTHON" "$WORK/make_mesh.py" --out "$WORK/again.inp" >/dev/null
cmp -s "$WORK/brb.inp" "$WORK/again.inp" || fail "make_mesh.py wrote different bytes on a second run"

# The coarse case: 24-gon holes (the square's sides carry 25.4/6 = 4.23 mm), two elements through
# each half-thickness, 12 mm along the arms; the case file of the case with only preload and modes.
"$PYTHON" "$WORK/make_mesh.py" --out "$WORK/coarse.inp" --seed 4.2333 --hole-segments 24 \
  --polar-layers 2 --blend-layers 2 --layers 2 --arm-max 12 >/dev/null || fail "coarse mesh"
sed -e 's/mesh: brb.inp/mesh: coarse.inp/' -e '/^  damping:/,$d' "$CASE_DIR/case.yaml" >"$WORK/coarse.yaml"
run_capture run "$WORK/coarse.yaml" -o "$WORK/out" --no-cache
[ "$STATUS" -eq 0 ] || fail "coarse run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/out" <<'PY' || fail "outputs of the coarse case"
import csv, json, math, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "ok", s["status"]
# Mass: two half-beams of 420 x 25.4 x 25.4 mm less the lap's cut (120 x 25.4 x 12.7 mm) and three
# 24-gon holes (r = 4.25 mm) through its 12.7 mm, steel 7800 kg/m^3.
poly = 0.5 * 24 * 4.25e-3 ** 2 * math.sin(2 * math.pi / 24)
volume = 0.42 * 0.0254 ** 2 - 0.12 * 0.0254 * 0.0127 - 3 * 0.0127 * poly
assert abs(s["model"]["mass_kg"] / (2 * 7800 * volume) - 1) < 1e-9, (s["model"]["mass_kg"], 2 * 7800 * volume)
p = s["preload"]
assert p["termination"] == "converged", p["termination"]
lap = p["interfaces"][0]
assert abs(lap["area"] / (0.12 * 0.0254 - 3 * poly) - 1) < 1e-9, lap["area"]
assert abs(lap["clamping_force"] / 36000.0 - 1) < 1e-7, lap["clamping_force"]
assert lap["closed_area_fraction"] > 0.5, lap["closed_area_fraction"]
# Each footprint is the meshed annulus between the hole and the ring at the washer's radius:
# 3 rings of 24 nodes (hole, one between, washer radius).
for b in p["bolts"]:
    assert b["force"] == 12000.0 and b["head_nodes"] == 72 and b["nut_nodes"] == 72, b
# The washers press where the bolts are: every contact point within 8.73 mm of an axis is closed
# and above the mean pressure.
rows = list(csv.DictReader(open(f"{d}/contact_lap.csv")))
under = [float(r["pressure"]) for r in rows
         if min(math.hypot(float(r["x"]) - x, float(r["y"])) for x in (-0.03, 0.0, 0.03)) < 8.73e-3]
assert under and min(under) > lap["mean_pressure"], (min(under), lap["mean_pressure"])
# Free-free: six rigid-body modes near 0 Hz, then the first out-of-plane bending. The monolithic
# 720 mm beam has 22.37/(2 pi L^2) sqrt(E I/(rho A)) = 255 Hz; the joint's compliance brings it
# down (170 Hz on the case's 2.54 mm mesh, README.md).
f = [float(r["frequency_hz"]) for r in csv.DictReader(open(f"{d}/modes.csv"))]
assert max(abs(x) for x in f[:6]) < 1.0, f[:6]
assert 150.0 < f[6] < 200.0 and f[6] < f[7] < 255.0, f[6:8]
print(f"ok: mass {s['model']['mass_kg']:.4f} kg, area {lap['area'] * 1e6:.2f} mm^2, closed {lap['closed_area_fraction']:.3f}, "
      f"modes 7, 8: {f[6]:.1f}, {f[7]:.1f} Hz, run {s['seconds']:.1f} s")
PY
finish

# jointhb run on an Abaqus deck that carries its own physics: the *BOUNDARY clamp, the *SOLID
# SECTION material and a *CLOAD reach the run (clamped frequencies, the load's resultant in
# summary.json), and a card that changes the physics stops the run with FILE:LINE unless the case
# lists it under ignore_cards.
source "$(dirname "$0")/common.inc" "$@"

# A steel cantilever 100 × 10 × 10 mm, 10 C3D8I elements, clamped at x = 0, 4 × 25 N down at the tip.
python3 - "$WORK/beam.inp" <<'PY'
import sys
nx, L, h = 10, 0.1, 0.01
nodes = {}
for k in range(2):
    for j in range(2):
        for i in range(nx + 1):
            nodes[(i, j, k)] = len(nodes) + 1
with open(sys.argv[1], "w") as f:
    f.write("*HEADING\ncantilever\n*NODE\n")
    for (i, j, k), n in nodes.items():
        f.write(f"{n}, {L * i / nx!r}, {h * j!r}, {h * k!r}\n")
    f.write("*ELEMENT, TYPE=C3D8I, ELSET=BEAM\n")
    for i in range(nx):
        c = [nodes[(i, 0, 0)], nodes[(i + 1, 0, 0)], nodes[(i + 1, 1, 0)], nodes[(i, 1, 0)],
             nodes[(i, 0, 1)], nodes[(i + 1, 0, 1)], nodes[(i + 1, 1, 1)], nodes[(i, 1, 1)]]
        f.write(f"{i + 1}, " + ", ".join(map(str, c)) + "\n")
    f.write("*NSET, NSET=ROOT\n" + ", ".join(str(nodes[(0, j, k)]) for j in range(2) for k in range(2)) + "\n")
    f.write("*NSET, NSET=TIP\n" + ", ".join(str(nodes[(nx, j, k)]) for j in range(2) for k in range(2)) + "\n")
    f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n")
    f.write("*SOLID SECTION, ELSET=BEAM, MATERIAL=STEEL\n*STEP\n*STATIC\n")
    f.write("*BOUNDARY\nROOT, ENCASTRE\n*CLOAD\nTIP, 3, -25.\n*END STEP\n")
PY
cat >"$WORK/beam.yaml" <<'YAML'
model:
  type: fe
  parts:
    - {mesh: beam.inp}
analysis:
  preload: {}
  modes: {count: 4, shift_hz: -1.0}
YAML
run_capture run "$WORK/beam.yaml" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "deck case exited $STATUS: $(cat "$ERR")"
grep -q "cards without effect on the results skipped (the analysis comes from the case): \*HEADING (1), \*STEP" "$ERR" ||
  fail "the no-effect cards are not listed once: $(cat "$ERR")"
python3 - "$WORK/out" <<'PY' || fail "clamped frequencies or load resultant wrong"
import csv, json, math, sys
out = sys.argv[1]
with open(f"{out}/modes.csv") as f:
    f1 = float(next(csv.DictReader(f))["frequency_hz"])
# Euler-Bernoulli clamped-free: (1.8751^2 / 2 pi) sqrt(E I / (rho A L^4)) = 835.5 Hz
exact = 1.8751040687 ** 2 / (2 * math.pi) * math.sqrt(210e9 * 1e-8 / 12 / (7850 * 1e-4 * 1e-4))
print(f"f1 = {f1:.2f} Hz, Euler-Bernoulli {exact:.2f} Hz")
assert abs(f1 / exact - 1) < 0.03, (f1, exact)
s = json.load(open(f"{out}/summary.json"))
loads = s["preload"]["static_loads"]
assert len(loads) == 1 and loads[0]["kind"] == "nodal forces", loads
assert abs(loads[0]["resultant"][2] + 100.0) < 1e-9, loads
assert s["preload"]["support"] == "user constraints", s["preload"]["support"]
PY

printf '*EQUATION\n2\n1, 1, 1., 2, 1, -1.\n' >>"$WORK/beam.inp"
expect_bad_input run "$WORK/beam.yaml" -o "$WORK/out2"
grep -q "beam.inp:[0-9]*:1: key .model.parts.0..mesh.: card \*EQUATION changes the physics and is not supported" "$ERR" ||
  fail "*EQUATION message: $(cat "$ERR")"
sed -i 's|- {mesh: beam.inp}|- {mesh: beam.inp, ignore_cards: ["*EQUATION"]}|' "$WORK/beam.yaml"
run_capture run "$WORK/beam.yaml" -o "$WORK/out3"
[ "$STATUS" -eq 0 ] || fail "ignore_cards run exited $STATUS: $(cat "$ERR")"
grep -q "\*EQUATION skipped as the case asks (ignore_cards)" "$ERR" || fail "skipped card not reported: $(cat "$ERR")"
finish

# jointhb run on cases/07-angle-bracket: a part imported from an Abaqus .inp mesh (an L-section
# bracket) bolted onto a generated, clamped plate. Checks the skipped-card warnings, equilibrium,
# the modes of the constrained assembly, and that bad meshes and bad models stop with a one-line
# message naming the file, line, key and entity (exit 2, nothing written).
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE_DIR="$SOURCE_DIR/cases/07-angle-bracket"

# The shipped mesh is the one its generator writes.
cp "$CASE_DIR/make_mesh.py" "$WORK/" && "$PYTHON" "$WORK/make_mesh.py" >/dev/null
cmp -s "$WORK/bracket.inp" "$CASE_DIR/bracket.inp" || fail "bracket.inp differs from what make_mesh.py writes"

run_capture run "$CASE_DIR/case.yaml" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run exited $STATUS: $(cat "$ERR")"
# The deck's material cards are read now (the case's materials override them); only the heading
# has no effect, and it is listed once.
grep -q "bracket.inp: cards without effect on the results skipped (the analysis comes from the case): \*HEADING (2)" "$ERR" ||
  fail "no single warning for the deck's no-effect cards: $(cat "$ERR")"
grep -q "MATERIAL skipped\|SOLID SECTION skipped" "$ERR" && fail "the deck's material cards are reported as skipped: $(cat "$ERR")"
"$PYTHON" - "$WORK/out" <<'PY' || fail "outputs"
import csv, json, math, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "ok" and s["model"]["parts"] == ["plate", "BRACKET"], s["model"]["parts"]
# mass: plate 100 × 50 × 4 mm aluminium + bracket (60 × 30 × 5 + 5 × 30 × 55 mm) steel
mass = 0.1 * 0.05 * 0.004 * 2700 + (0.06 * 0.03 * 0.005 + 0.005 * 0.03 * 0.055) * 7850
assert abs(s["model"]["mass_kg"] / mass - 1) < 1e-12, (s["model"]["mass_kg"], mass)
p = s["preload"]
assert p["termination"] == "converged" and p["support"] == "user constraints", p["support"]
i = p["interfaces"][0]
assert abs(i["clamping_force"] / 8000.0 - 1) < 1e-7, i["clamping_force"]
assert abs(i["area"] / (0.06 * 0.03) - 1) < 1e-12, i["area"]
assert 0.2 < i["closed_area_fraction"] < 0.95 and i["max_gap"] > 0, i
rows = list(csv.DictReader(open(f"{d}/contact_foot.csv")))
near = [float(r["pressure"]) for r in rows if min(math.hypot(float(r["x"]) - 0.035, float(r["y"]) - y) for y in (0.0075, 0.0225)) < 0.003]
assert min(near) > 2 * i["mean_pressure"], (min(near), i["mean_pressure"])
m = [float(r["frequency_hz"]) for r in csv.DictReader(open(f"{d}/modes.csv"))]
# Clamped plate: no rigid-body modes. The bracket's flange (55 mm, 5 mm steel) is the soft part:
# as a clamped steel cantilever 1.875² √(EI/ρA)/(2π L²) = 1.38 kHz on a rigid base; the rocking
# foot and the plate's bending bring the first mode down to a few hundred Hz.
assert len(m) == 10 and 200.0 < m[0] < 1380.0 and all(b > a for a, b in zip(m, m[1:])), m
print(f"ok: clamping {i['clamping_force']:.6g} N, closed {i['closed_area_fraction']:.3f}, modes {m[0]:.1f}, {m[1]:.1f}, {m[2]:.1f} Hz")
PY

# Bad meshes and models: copy the case, break one thing, expect one line and exit 2.
bad_case() {  # bad_case NAME: a fresh copy of the case in $WORK/NAME
  rm -rf "$WORK/$1" && mkdir "$WORK/$1" && cp "$CASE_DIR/case.yaml" "$CASE_DIR/bracket.inp" "$WORK/$1/"
}
expect_message() {  # expect_message DIR REGEX
  expect_bad_input run "$WORK/$1/case.yaml" -o "$WORK/$1/out"
  grep -q "$2" "$ERR" || fail "$1: message '$(cat "$ERR")' does not match '$2'"
  [ ! -e "$WORK/$1/out/summary.json" ] || fail "$1 wrote output"
}
# An inverted element: element 17's bottom and top node rows swapped.
bad_case inverted
"$PYTHON" - "$WORK/inverted/bracket.inp" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
k = lines.index("*ELEMENT, TYPE=C3D8I, ELSET=BRACKET") + 17
f = lines[k].split(", ")
assert f[0] == "17"
lines[k] = ", ".join([f[0]] + f[5:9] + f[1:5])
open(sys.argv[1], "w").write("\n".join(lines))
PY
expect_message inverted "case.yaml:[0-9]*:[0-9]*: key 'model.parts': element 17 of part BRACKET (C3D8I): inverted"
# An element type jointhb does not have: the mesh file's line.
bad_case tet
sed -i 's/TYPE=C3D8I/TYPE=C3D10M/' "$WORK/tet/bracket.inp"
expect_message tet "bracket.inp:[0-9]*:[0-9]*: key 'model.parts\[1\].mesh': element type C3D10M is not supported"
# An element that references a node the file does not define.
bad_case node
sed -i '0,/^17, [0-9]*,/s//17, 999999,/' "$WORK/node/bracket.inp"
expect_message node "bracket.inp:[0-9]*:[0-9]*: key 'model.parts\[1\].mesh': element 17: unknown node 999999"
# A surface the mesh does not define.
bad_case surface
sed -i 's/top: FOOT_UNDERSIDE/top: FOOT_BOTTOM/' "$WORK/surface/case.yaml"
expect_message surface "key 'model.interfaces\[0\].top': unknown surface 'FOOT_BOTTOM'; defined: .*FOOT_UNDERSIDE"
# Surfaces that do not face each other (the foot's top is 5 mm above the plate).
bad_case facing
sed -i -e 's/top: FOOT_UNDERSIDE/top: FOOT_TOP/' -e '/region:/d' "$WORK/facing/case.yaml"
expect_message facing "key 'model.interfaces\[0\]': .*FOOT_TOP"
# An unknown node set in a constraint.
bad_case nodeset
sed -i 's/node_set: plate.xmax/node_set: plate.xmx/' "$WORK/nodeset/case.yaml"
expect_message nodeset "key 'model.constraints\[1\].node_set': unknown node set 'plate.xmx'"
# The bracket neither joined nor constrained: no interface and no bolts.
bad_case floating
"$PYTHON" - "$WORK/floating/case.yaml" <<'PY'
import sys
s = open(sys.argv[1]).read()
open(sys.argv[1], "w").write(s[:s.index("  interfaces:")] + s[s.index("  constraints:"):])
PY
expect_message floating "key 'model.parts': part 'BRACKET' is neither constrained nor connected"
finish

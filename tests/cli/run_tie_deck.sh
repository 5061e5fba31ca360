# jointhb run on an Abaqus deck whose two instances are bonded by a *TIE (docs/ties.md): the
# cantilever cut in two halves and tied runs through preload and modes end to end with the
# frequencies of the uncut cantilever (the tie's error at the default penalty factor, 1e3, is
# O(1e-4)), summary.json lists the tie, and a bad *TIE stops the run with one FILE:LINE line.
source "$(dirname "$0")/common.inc" "$@"

# A steel cantilever 100 × 10 × 10 mm of C3D8I, clamped at x = 0, 4 × 25 N down at the tip: as one
# instance of 10 elements (whole.inp), and as two instances of a 5-element half tied at x = 50 mm
# (tied.inp).
python3 - "$WORK" <<'PY'
import sys
work = sys.argv[1]
def part(nx, L, h=0.01):
    nodes = {}
    for k in range(2):
        for j in range(2):
            for i in range(nx + 1):
                nodes[(i, j, k)] = len(nodes) + 1
    s = "*PART, NAME=BEAM\n*NODE\n"
    for (i, j, k), n in nodes.items():
        s += f"{n}, {L * i / nx!r}, {h * j!r}, {h * k!r}\n"
    s += "*ELEMENT, TYPE=C3D8I, ELSET=BEAM\n"
    for i in range(nx):
        c = [nodes[(i, 0, 0)], nodes[(i + 1, 0, 0)], nodes[(i + 1, 1, 0)], nodes[(i, 1, 0)],
             nodes[(i, 0, 1)], nodes[(i + 1, 0, 1)], nodes[(i + 1, 1, 1)], nodes[(i, 1, 1)]]
        s += f"{i + 1}, " + ", ".join(map(str, c)) + "\n"
    s += "*NSET, NSET=ROOT\n" + ", ".join(str(nodes[(0, j, k)]) for j in range(2) for k in range(2)) + "\n"
    s += "*NSET, NSET=TIP\n" + ", ".join(str(nodes[(nx, j, k)]) for j in range(2) for k in range(2)) + "\n"
    # S6 is the face x = 0 of element 1, S4 the face x = L of the last element.
    s += f"*SURFACE, NAME=LEFT\n1, S6\n*SURFACE, NAME=RIGHT\n{nx}, S4\n"
    s += "*SOLID SECTION, ELSET=BEAM, MATERIAL=STEEL\n*END PART\n"
    return s
material = "*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n7850.\n"
with open(f"{work}/whole.inp", "w") as f:
    f.write("*HEADING\nwhole\n" + part(10, 0.1) + "*ASSEMBLY, NAME=A\n*INSTANCE, NAME=W, PART=BEAM\n*END INSTANCE\n*END ASSEMBLY\n")
    f.write(material + "*STEP\n*STATIC\n*BOUNDARY\nW.ROOT, ENCASTRE\n*CLOAD\nW.TIP, 3, -25.\n*END STEP\n")
with open(f"{work}/tied.inp", "w") as f:
    f.write("*HEADING\ntied halves\n" + part(5, 0.05) + "*ASSEMBLY, NAME=A\n")
    f.write("*INSTANCE, NAME=H1, PART=BEAM\n*END INSTANCE\n*INSTANCE, NAME=H2, PART=BEAM\n0.05, 0., 0.\n*END INSTANCE\n")
    f.write("*TIE, NAME=GLUE, ADJUST=YES\nH2.LEFT, H1.RIGHT\n*END ASSEMBLY\n")
    f.write(material + "*STEP\n*STATIC\n*BOUNDARY\nH1.ROOT, ENCASTRE\n*CLOAD\nH2.TIP, 3, -25.\n*END STEP\n")
PY
for deck in whole tied; do
  cat >"$WORK/$deck.yaml" <<YAML
model:
  type: fe
  parts:
    - {mesh: $deck.inp}
analysis:
  preload: {}
  modes: {count: 4, shift_hz: -1.0}
YAML
  run_capture run "$WORK/$deck.yaml" -o "$WORK/out-$deck"
  [ "$STATUS" -eq 0 ] || fail "$deck deck exited $STATUS: $(cat "$ERR")"
done
grep -q "tie GLUE: slave H2.LEFT, master H1.RIGHT, 4 points" "$ERR" || fail "the tie is not reported on stderr: $(cat "$ERR")"
python3 - "$WORK" <<'PY' || fail "tied frequencies or summary wrong"
import csv, json, math, sys
work = sys.argv[1]
def freqs(out):
    with open(f"{work}/{out}/modes.csv") as f:
        return [float(r["frequency_hz"]) for r in csv.DictReader(f)]
whole, tied = freqs("out-whole"), freqs("out-tied")
for w, t in zip(whole, tied):
    print(f"whole {w:.4f} Hz, tied {t:.4f} Hz, {t / w - 1:+.2e}")
    assert abs(t / w - 1) < 1e-3, (w, t)
exact = 1.8751040687 ** 2 / (2 * math.pi) * math.sqrt(210e9 * 1e-8 / 12 / (7850 * 1e-4 * 1e-4))
assert abs(tied[0] / exact - 1) < 0.03, (tied[0], exact)
s = json.load(open(f"{work}/out-tied/summary.json"))
ties = s["model"]["ties"]
assert len(ties) == 1, ties
t = ties[0]
assert (t["name"], t["slave"], t["master"], t["points"]) == ("GLUE", "H2.LEFT", "H1.RIGHT", 4), t
assert abs(t["area"] - 1e-4) < 1e-18, t
assert abs(t["penalty"] / (1e3 * 210e9 / 0.01) - 1) < 1e-12, t
assert t["where"].endswith("tied.inp:51"), t
assert s["preload"]["ok"] and s["modes"]["ok"], (s["preload"], s["modes"])
assert "ties" not in json.load(open(f"{work}/out-whole/summary.json"))["model"]
PY

sed -i 's/^H2.LEFT, H1.RIGHT$/H2.LEFT, H1.RIGTH/' "$WORK/tied.inp"
expect_bad_input run "$WORK/tied.yaml" -o "$WORK/out-bad"
grep -q "tied.inp:52:1: key .model.parts.0..mesh.: \*TIE 'GLUE': unknown master surface 'H1.RIGTH'" "$ERR" ||
  fail "bad *TIE message: $(cat "$ERR")"
finish

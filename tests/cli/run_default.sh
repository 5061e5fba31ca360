# jointhb run without a case runs the built-in default case (cases/08-lap-damping): the bolted
# lap's preload, modes, condensation and the first mode's damping curve, with its plot. Checks the
# curve against what is known independently (linear limit = the modes stage's first elastic
# frequency and the imposed 0.5 % damping; softening and rising damping into macroslip), and that
# a second run which changes only dynamic settings reads preload, modes and the condensed model
# from the stage cache and reproduces the curve.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

run_capture run -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run exited $STATUS: $(cat "$ERR")"
[ -s "$OUT" ] && fail "run printed on stdout: $(cat "$OUT")"
grep -q 'damping curve of mode 1' "$ERR" || fail "stderr has no damping-curve line: $(cat "$ERR")"
grep -q 'time of the curve: .*GMRES iterations' "$ERR" || fail "stderr has no time breakdown of the curve: $(cat "$ERR")"
for f in summary.json preload_steps.csv contact_lap.csv contact_lap.vtu modes.csv interface_model.csv backbone.csv; do
  [ -s "$WORK/out/$f" ] || fail "missing $f"
done
if "$PYTHON" -c 'import matplotlib' 2>/dev/null; then
  [ -s "$WORK/out/backbone.png" ] || fail "no backbone.png although matplotlib is installed"
fi
grep -qi 'nan\|inf' "$WORK/out/backbone.csv" && fail "non-finite value in backbone.csv"
[ "$(head -1 "$WORK/out/backbone.csv")" = "$BACKBONE_COLUMNS" ] ||
  fail "backbone.csv header is not the one schema: $(head -1 "$WORK/out/backbone.csv")"
"$PYTHON" - "$WORK/out" <<'PY' || fail "default-case outputs"
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "ok" and s["kind"] == "fe" and s["case"] == "built-in default case", (s["status"], s["case"])
b = s["backbones"][0]
assert b["mode"] == 1, b
# The status convention (docs/cli.md "Status blocks"): every stage and curve block has
# "termination", "ok" and "message" together, and no older "status" of its own; the run's block
# has "status" ("ok", as the exit code) followed by the worst of them.
p, m = s["preload"], s["modes"]
assert (p["termination"], p["ok"]) == ("converged", True) and p["message"], p
assert (m["termination"], m["ok"]) == ("converged", True) and m["message"], m
assert b["termination"] == "reached_end" and b["ok"] is True and b["message"], b["message"]
for block in (p, m, b):
    assert "status" not in block and "converged" not in block, list(block)
    k = list(block).index("termination")
    assert list(block)[k:k + 3] == ["termination", "ok", "message"], list(block)
assert list(s)[list(s).index("status"):list(s).index("status") + 4] == ["status", "termination", "ok", "message"], list(s)
assert (s["termination"], s["ok"]) == ("reached_end", True), s["message"]  # worst of converged, reached_end
assert s["message"].startswith("nonlinear mode 1: "), s["message"]
modes = [float(r["frequency_hz"]) for r in csv.DictReader(open(f"{d}/modes.csv"))]
f1 = [f for f in modes if abs(f) >= 1.0][0]                  # first elastic mode of K_t
rows = list(csv.DictReader(open(f"{d}/backbone.csv")))
f = [float(r["frequency_hz"]) for r in rows]
z = [float(r["damping_ratio"]) for r in rows]
q = [float(r["amplitude"]) for r in rows]
u = [float(r["output_amplitude"]) for r in rows]
assert abs(b["linear_frequency_hz"] / f1 - 1) < 1e-9, (b["linear_frequency_hz"], f1)
assert abs(f[0] / f1 - 1) < 1e-5, (f[0], f1)                  # linear limit (q = 1e-8)
assert abs(z[0] / 0.005 - 1) < 1e-3, z[0]                     # imposed Rayleigh damping
assert all(b2 > a2 for a2, b2 in zip(q, q[1:])), "amplitude not increasing"
assert all(b2 <= a2 * (1 + 1e-9) for a2, b2 in zip(f, f[1:])), "frequency not softening"
assert f[-1] < 0.97 * f[0] * (1 + 1e-3), (f[0], f[-1])        # the 3 % drop was reached
assert max(z) > 2.5 * z[0], (z[0], max(z))                    # friction damping
# the output amplitude is linear in q at small amplitude (a fixed mode-shape entry)
assert abs((u[1] / q[1]) / (u[0] / q[0]) - 1) < 1e-3, (u[0] / q[0], u[1] / q[1])
im = s["interface_model"]
assert im["contact_points"] == 63 and im["contact_patch"]["points_before"] == 192 and im["rigid_modes"] == 6, im
assert im["cache"] == "miss" and s["preload"]["cache"] == "miss"
# FE curves are solved matrix-free (GMRES on Jacobian products), never by the dense LU (issue 16)
t = b["seconds"]
assert t["gmres_iterations"] > 0 and t["product_calls"] > 0 and t["preconditioner_builds"] > 0, t
print(f"ok: f {f[0]:.3f} -> {f[-1]:.3f} Hz, zeta {z[0]:.4g} -> {z[-1]:.4g} over {len(rows)} points "
      f"in {b['seconds']['total']:.1f} s (linear solves {b['seconds']['linear_solve']:.1f} s)")
PY

# The damping curve's ParaView fields (docs/case-files.md "fields"): the contact surface's W_D adds
# up to the curve's W_D at the same point, and the recovered volume field (eq. T-33) at the drive
# node matches the output amplitude the balance reports (which adds the R1 term: cutoff-sized).
for f in mode1_contact_lap.pvd mode1_volume.pvd mode1_contact_points.csv; do
  [ -s "$WORK/out/$f" ] || fail "missing $f"
done
"$PYTHON" - "$WORK/out" <<'PY' || fail "damping-curve fields"
import csv, json, math, sys, xml.etree.ElementTree as ET
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
fl = s["backbones"][0]["fields"]
assert fl["snapshots"] >= 2 and fl["volume"], fl
rows = list(csv.DictReader(open(f"{d}/backbone.csv")))
pts = list(csv.DictReader(open(f"{d}/mode1_contact_points.csv")))
last = max(int(r["snapshot"]) for r in pts)
def w_of(snap):
    return sum(float(r["area"]) * float(r["dissipation"]) for r in pts if int(r["snapshot"]) == snap)
q_last = float([r for r in pts if int(r["snapshot"]) == last][0]["amplitude"])
b = min(rows, key=lambda r: abs(float(r["amplitude"]) / q_last - 1))
assert abs(float(b["amplitude"]) / q_last - 1) < 1e-12, (b["amplitude"], q_last)
assert abs(w_of(last) / float(b["W_D"]) - 1) < 1e-9, (w_of(last), b["W_D"])
assert w_of(0) < 1e-6 * w_of(last), (w_of(0), w_of(last))          # linear limit: no slip
# Contact states (docs/theory.md §14): in the linear limit almost every point is stuck; the others
# are the node pairs between the bolts whose preload left a static shear of 1-2 % of μp_N (force
# ratio above the stuck-like 1 %, below 5 %). Along the curve the points reach gross slip one
# region after another (never fewer), and at the last snapshot points slip (codes 1, 2).
first = [r for r in pts if int(r["snapshot"]) == 0]
assert sum(float(r["state"]) == 0 for r in first) >= 0.85 * len(first), [r["state"] for r in first]  # 172 of 192
assert all(float(r["state"]) == 0 or (float(r["state"]) == 1 and float(r["limit_ratio"]) < 0.05) for r in first)
assert any(float(r["state"]) in (1, 2) for r in pts if int(r["snapshot"]) == last), "no slipping point at the end"
states = ["stuck_points", "microslip_points", "gross_slip_points", "gapping_points", "open_points"]
for r in rows:
    assert sum(int(float(r[k])) for k in states) == s["interface_model"]["contact_points"], (r, s["interface_model"])
gross = [int(float(r["gross_slip_points"])) for r in rows]
assert gross[0] == 0 and gross[-1] > 0 and all(b2 >= a2 for a2, b2 in zip(gross, gross[1:])), gross
# points_per_decade: 8 (the case file): consecutive points at most 1/8 decade of q apart (up to the
# corrector's move beyond the predictor).
lq = [math.log10(float(r["amplitude"])) for r in rows]
assert max(b2 - a2 for a2, b2 in zip(lq, lq[1:])) <= 1.1 / 8, lq
cs = s["backbones"][0]["contact_states"]
assert len(cs["amplitude"]) == len(rows) and cs["stuck"][0] == int(float(rows[0]["stuck_points"])), cs
def arrays(path):
    root = ET.parse(path).getroot()
    out = {}
    for a in root.iter("DataArray"):
        if a.get("format") == "ascii" and a.text:
            out[a.get("Name")] = [float(v) for v in a.text.split()]
    return out
pvd = ET.parse(f"{d}/mode1_volume.pvd").getroot()
sets = [(float(x.get("timestep")), x.get("file")) for x in pvd.iter("DataSet")]
assert abs(sets[-1][0] - math.log10(q_last)) < 1e-12, (sets[-1], q_last)
v = arrays(f"{d}/{sets[-1][1]}")
xyz = v["Points"]
node = min(range(len(xyz) // 3), key=lambda i: (xyz[3*i]-0.160)**2 + (xyz[3*i+1]-0.015)**2 + (xyz[3*i+2]-0.008)**2)
amp = v["amplitude_1"][3 * node + 2]
assert abs(amp / float(b["output_amplitude"]) - 1) < 1e-2, (amp, b["output_amplitude"])
print(f"ok: fields: {fl['snapshots']} snapshots; surface W_D {w_of(last):.4e} J = curve's; drive amplitude "
      f"recovered {amp:.5e} m vs balance {float(b['output_amplitude']):.5e} m ({abs(amp/float(b['output_amplitude'])-1):.1e})")
PY

# Only dynamic settings changed (a 1 % drop instead of 3 %): preload, modes and the condensed
# model come from the cache, and the curve repeats the first run's points.
sed 's/frequency_drop: 0.03 /frequency_drop: 0.01 /' "$SOURCE_DIR/cases/08-lap-damping/case.yaml" >"$WORK/short.yaml"
grep -q 'frequency_drop: 0.01 ' "$WORK/short.yaml" || fail "could not edit the default case's frequency_drop"
run_capture run "$WORK/short.yaml" -o "$WORK/out2" --cache-dir "$WORK/out/.cache"
[ "$STATUS" -eq 0 ] || fail "second run exited $STATUS: $(cat "$ERR")"
grep -q 'interface model: from cache' "$ERR" || fail "the condensed model was not read from the cache: $(cat "$ERR")"
"$PYTHON" - "$WORK/out" "$WORK/out2" <<'PY' || fail "cached second run"
import csv, json, sys
a, b = sys.argv[1], sys.argv[2]
s = json.load(open(f"{b}/summary.json"))
assert s["preload"]["cache"] == "hit" and s["modes"]["cache"] == "hit" and s["interface_model"]["cache"] == "hit", s
first = list(csv.DictReader(open(f"{a}/backbone.csv")))
second = list(csv.DictReader(open(f"{b}/backbone.csv")))
assert 2 <= len(second) < len(first), (len(first), len(second))
for r1, r2 in zip(first, second):
    for k in ("amplitude", "frequency_hz", "damping_ratio"):
        assert abs(float(r1[k]) - float(r2[k])) <= 1e-12 * abs(float(r1[k])), (k, r1[k], r2[k])
s1 = json.load(open(f"{a}/summary.json"))
stages = lambda j: j["preload"]["seconds"]["total"] + j["modes"]["seconds"] + j["interface_model"]["seconds"]["total"]
print(f"ok: stages from the cache: {s['preload']['cache_seconds'] + s['modes']['cache_seconds'] + s['interface_model']['cache_seconds']:.3f} s "
      f"read instead of {stages(s1):.2f} s computed; {len(second)} points, identical to the first run")
PY

# Only the damping changed: the condensation only copies the Rayleigh coefficients, so all three
# stages still come from the cache, and the linear limit carries the new ratio. The error
# estimates (off by default for FE curves) are switched on: every row carries them, and
# summary.json's worst estimates are the columns' largest magnitudes.
sed -e 's/damping: {ratio: 0.005}/damping: {ratio: 0.01}/' -e 's/frequency_drop: 0.03 /frequency_drop: 0.005 /' \
  -e 's/^    harmonics: 1/    harmonics: 1\n    error_estimate: true/' \
  "$SOURCE_DIR/cases/08-lap-damping/case.yaml" >"$WORK/damped.yaml"
grep -q 'ratio: 0.01}' "$WORK/damped.yaml" || fail "could not edit the default case's damping"
grep -q 'error_estimate: true' "$WORK/damped.yaml" || fail "could not switch the error estimates on"
run_capture run "$WORK/damped.yaml" -o "$WORK/out3" --cache-dir "$WORK/out/.cache"
[ "$STATUS" -eq 0 ] || fail "damped run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/out3" <<'PY' || fail "damping-only change"
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["interface_model"]["cache"] == "hit" and s["interface_model"]["rayleigh"]["beta"] > 0, s["interface_model"]
z0 = float(next(csv.DictReader(open(f"{d}/backbone.csv")))["damping_ratio"])
assert abs(z0 / 0.01 - 1) < 1e-3, z0
rows = list(csv.DictReader(open(f"{d}/backbone.csv")))
e = s["backbones"][0]["error_estimate"]
assert e["points_known"] == len(rows) >= 2, (e, len(rows))
for out, col in (("omega", "omega_error"), ("damping", "damping_error")):
    for src in ("truncation", "aliasing"):
        worst = max(abs(float(r[f"{col}_{src}"])) for r in rows)
        assert abs(e[out][src] - worst) <= 1e-12 * worst + 1e-300, (out, src, e[out][src], worst)
# H = 1 in microslip: the change to H = 3 is real but small; 32 samples resolve the loops
assert 0 < e["damping"]["truncation"] < 0.2 and e["damping"]["aliasing"] < 0.05, e
assert e["seconds"] > 0, e
print(f"ok: damping 1 %: condensed model from the cache, linear zeta {z0:.6f}; error estimates on {len(rows)} "
      f"points, worst zeta truncation {e['damping']['truncation']:.2e}, aliasing {e['damping']['aliasing']:.2e}")
PY

# The default output directory is ./jointhb-out (checked with a file case: the same code path).
(cd "$WORK" && "$JOINTHB" run "$SOURCE_DIR/cases/01-contact-loop/case.yaml" 2>/dev/null) || fail "run in $WORK exited $?"
[ -f "$WORK/jointhb-out/summary.json" ] || fail "no jointhb-out/summary.json by default"

# An output path that is a file is bad input.
touch "$WORK/a-file"
expect_bad_input run -o "$WORK/a-file"

# A failure after the output directory exists still leaves a summary.json with status "failed".
mkdir -p "$WORK/blocked/wd_sweep.csv"
run_capture run "$SOURCE_DIR/cases/01-contact-loop/case.yaml" -o "$WORK/blocked"
[ "$STATUS" -eq 1 ] || fail "run into a blocked wd_sweep.csv exited $STATUS, expected 1"
"$PYTHON" -c 'import json,sys; s=json.load(open(sys.argv[1])); assert s["status"]=="failed" and "wd_sweep.csv" in s["message"], s' \
  "$WORK/blocked/summary.json" || fail "summary.json of a failed run"
finish

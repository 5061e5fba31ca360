# jointhb run on cases/03-one-dof-gaul-mayer: a damping curve (EPMC, backbone.csv) and FRFs in one
# case. Checks the linear limit, the trends, and that the FRF peaks lie on the backbone.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
[ "$(head -1 "$WORK/out/backbone.csv")" = "$BACKBONE_COLUMNS" ] ||
  fail "backbone.csv header is not the one schema: $(head -1 "$WORK/out/backbone.csv")"
"$PYTHON" - "$WORK/out/backbone.csv" "$WORK/out/summary.json" "$WORK/out/frf.csv" <<'PY' || fail "outputs"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
assert s["status"] == "ok" and s["analyses"] == ["frf", "nonlinear_modes"], s["analyses"]
assert len(s["backbones"]) == 1 and s["backbones"][0]["mode"] == 1
b = s["backbones"][0]
need = ["mode", "amplitude", "omega", "frequency_hz", "damping_ratio", "W_D", "damping_ratio_energy",
        "slip_fraction"]
assert all(c in rows[0] for c in need), rows[0].keys()
assert len(rows) == b["points"] == len(b["curve"]) > 10
q = [float(r["amplitude"]) for r in rows]
om = [float(r["omega"]) for r in rows]
zeta = [float(r["damping_ratio"]) for r in rows]
# Linear limit: the stuck mode (200 rad/s) with its modal damping (0.2 % of K's mode at 100 rad/s: 0.1 % here), to the microslip that
# q = 1e-8 already has (W_D ∝ q³: ~1e-5 relative).
assert abs(om[0] - b["linear_omega"]) < 1e-4 * b["linear_omega"], (om[0], b["linear_omega"])
assert abs(zeta[0] - b["linear_damping_ratio"]) < 0.02 * b["linear_damping_ratio"], zeta[0]
assert abs(q[0] - 1e-8) < 1e-20 and abs(q[-1] - 10 ** -3.5) < 1e-12 * q[-1]
# Softening all the way towards the slipped system (100 rad/s); damping rises then falls.
assert all(b2 <= a2 * (1 + 1e-9) for a2, b2 in zip(om, om[1:])), "frequency must not rise"
assert om[-1] < 0.6 * om[0] and om[-1] > 100.0
# One DOF of unit mass: the output DOF's fundamental is q; the energy balance's ζ_E (contacts and
# viscous work) equals ζ up to the higher harmonics' share of the EPMC work (E counts the
# fundamental only); no discrete contact is ever open.
for r in rows:
    assert abs(float(r["output_amplitude"]) - float(r["amplitude"])) <= 1e-9 * float(r["amplitude"]), r
    assert abs(float(r["damping_ratio_energy"]) / float(r["damping_ratio"]) - 1) < 5e-3, r  # 2.9e-3 at H = 7
    assert float(r["open_points"]) == 0 and float(r["slipping_points"]) in (0.0, 1.0), r
    assert float(r["slip_fraction"]) == float(r["slipping_points"]), r
# Contact states (docs/theory.md §14): the one Gaul–Mayer contact is stuck(-like) in the linear
# limit, in microslip on the way, and at its slip limit (gross slip) where the curve ends near the
# slipped system; the states never go back, and the counts match the point and slipping_points.
order = ["stuck_points", "microslip_points", "gross_slip_points", "gapping_points"]
state = []
for r in rows:
    c = [int(float(r[k])) for k in order] + [int(float(r["open_points"]))]
    assert sum(c) == 1 and c[3] == c[4] == 0, r
    assert c[1] + c[2] == int(float(r["slipping_points"])), r
    state.append(c.index(1))
assert state[0] == 0 and state[-1] == 2 and 1 in state, state
assert all(b2 >= a2 for a2, b2 in zip(state, state[1:])), state
for p in b["curve"]:
    assert sum(p["contact_states"].values()) == 1, p
print(f"ok: contact states stuck -> microslip at q = {q[state.index(1)]:.2e} -> gross slip at q = {q[state.index(2)]:.2e}")
peak = max(zeta)
assert 0.1 < peak < 0.4 and zeta[-1] < peak and zeta[0] < 0.01 * peak * 10
# FRF peaks lie on the backbone (interpolated in log q; m = 1 kg so q = amplitude).
for c in s["curves"]:
    a, w = c["peak"]["amplitude_h1"], c["peak"]["omega"]
    i = max(k for k in range(len(q) - 1) if q[k] <= a)
    t = (math.log(a) - math.log(q[i])) / (math.log(q[i + 1]) - math.log(q[i]))
    wb = om[i] + t * (om[i + 1] - om[i])
    assert abs(w - wb) < 0.01 * wb, (a, w, wb)
    print(f"ok: FRF peak at {w:.3f} rad/s, backbone {wb:.3f} rad/s ({(w - wb) / wb:+.1e})")
# Error estimates (docs/theory.md §13): a number in every row, the worst in summary.json; H = 7,
# N_t = 128: below 1 % everywhere, and not zero once the joint slips.
cols = ["omega_error_truncation", "omega_error_aliasing", "damping_error_truncation", "damping_error_aliasing"]
e = b["error_estimate"]
assert e["points_known"] == len(rows), e
for out, (t, a) in (("omega", cols[:2]), ("damping", cols[2:])):
    vt = [abs(float(r[t])) for r in rows]
    va = [abs(float(r[a])) for r in rows]
    assert e[out]["truncation"] == max(vt) and e[out]["aliasing"] == max(va), (out, e[out])
    assert 1e-8 < max(vt) < 1e-2 and 1e-8 < max(va) < 1e-2, (out, max(vt), max(va))
print(f"ok: {len(rows)} backbone points, f {om[0] / 2 / math.pi:.3f} -> "
      f"{om[-1] / 2 / math.pi:.3f} Hz, peak damping {peak:.3f}")
PY

# Two modes in one case, with --plot: one curve per mode, and the PNGs when matplotlib exists.
run_capture run "$SOURCE_DIR/cases/04-two-dof-two-joints/case.yaml" -o "$WORK/two" --plot
[ "$STATUS" -eq 0 ] || fail "case 04 exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/two/summary.json" <<'PY' || fail "case 04 outputs"
import json, sys
s = json.load(open(sys.argv[1]))
b = s["backbones"]
assert [x["mode"] for x in b] == [1, 2] and all(x["ok"] is True and x["termination"] == "reached_end" for x in b), b
f1, f2 = (x["linear_frequency_hz"] for x in b)
assert f2 > f1 and all(p["frequency_hz"] <= x["linear_frequency_hz"] * (1 + 1e-9)
                       for x in b for p in x["curve"])
print(f"ok: modes at {f1:.2f} and {f2:.2f} Hz")
PY
if "$PYTHON" -c 'import matplotlib' 2>/dev/null; then
  [ -s "$WORK/two/backbone.png" ] && [ -s "$WORK/two/frf.png" ] || fail "--plot drew nothing"
fi

# max_output_change: every step of the damping curve changes f and ζ by at most 5 % (relative);
# without it the curve strides across the rise of ζ at the onset of slip.
sed 's/^\(    log10_amplitude: .*\)$/\1\n    max_output_change: 0.05/' "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" >"$WORK/smooth.yaml"
grep -q 'max_output_change: 0.05' "$WORK/smooth.yaml" || fail "could not set max_output_change"
run_capture run "$WORK/smooth.yaml" -o "$WORK/smooth"
[ "$STATUS" -eq 0 ] || fail "max_output_change run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/smooth" "$WORK/out" <<'PY' || fail "max_output_change"
import csv, sys
def largest(d):
    r = list(csv.DictReader(open(f"{d}/backbone.csv")))
    w = max(abs(float(b[k]) / float(a[k]) - 1) for a, b in zip(r, r[1:]) for k in ("frequency_hz", "damping_ratio"))
    return len(r), w
(n, w), (n0, w0) = largest(sys.argv[1]), largest(sys.argv[2])
assert w <= 0.05 * (1 + 1e-9) and w0 > 0.05 and n > n0, (n, w, n0, w0)
print(f"ok: max_output_change 0.05: {n} points, largest change {w:.4f} (without: {n0} points, {w0:.3f})")
PY
bad="$WORK/bad_change.yaml"
sed 's/^\(    log10_amplitude: .*\)$/\1\n    max_output_change: 2/' "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" >"$bad"
expect_bad_input run "$bad" -o "$WORK/none"
grep -q "key 'analysis.nonlinear_modes.max_output_change'.*must be in (0, 1]" "$ERR" || fail "max_output_change 2: $(cat "$ERR")"

# accuracy: H and N_t chosen per point. Case 03 from H = 1: the stuck limit stays at H = 1, slip
# raises it; every point's estimates are within the request or the point is counted short of it.
sed '/nonlinear_modes:/,/frf:/ { s/^\(    log10_amplitude: .*\)$/\1\n    accuracy: {damping: 1.0e-3, frequency: 1.0e-5, max_harmonics: 21}/; s/^    harmonics: 7$/    harmonics: 1/; s/^    time_samples: 128$/    time_samples: 32/ }; /^  frf:/,$ { s/^    harmonics: 7$/    harmonics: 1\n    accuracy: {amplitude: 1.0e-4}/; s/^    time_samples: 128$/    time_samples: 32/ }' \
  "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" >"$WORK/accuracy.yaml"
grep -q 'accuracy: {damping' "$WORK/accuracy.yaml" || fail "could not set accuracy"
run_capture run "$WORK/accuracy.yaml" -o "$WORK/accuracy"
[ "$STATUS" -eq 0 ] || fail "accuracy run exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$WORK/accuracy" <<'PY' || fail "accuracy"
import csv, json, sys
rows = list(csv.DictReader(open(f"{sys.argv[1]}/backbone.csv")))
h = [int(float(r["harmonics"])) for r in rows]
acc = json.load(open(f"{sys.argv[1]}/summary.json"))["backbones"][0]["accuracy"]
assert h[0] == 1 and max(h) >= 5, h
assert acc["harmonics_used"] == [min(h), max(h)] and acc["level_changes"] > 0, acc
short = 0
for r in rows:
    over = abs(float(r["damping_error_truncation"])) > 1e-3 or abs(float(r["omega_error_truncation"])) > 1e-5 \
        or abs(float(r["damping_error_aliasing"])) > 1e-3 or abs(float(r["omega_error_aliasing"])) > 1e-5
    short += over
assert short == acc["points_short_of_request"], (short, acc)
print(f"ok: accuracy: {len(rows)} points, H {min(h)}..{max(h)}, {acc['level_changes']} level changes, {short} short")
# The FRFs with accuracy: {amplitude: 1e-4}: H per point, every curve complete with its peak.
frf = list(csv.DictReader(open(f"{sys.argv[1]}/frf.csv")))
curves = json.load(open(f"{sys.argv[1]}/summary.json"))["curves"]
for c in curves:
    mine = [int(float(r["harmonics"])) for r in frf if int(float(r["level"])) == c["level"]]
    assert c["ok"] and c["accuracy"]["harmonics_used"] == [min(mine), max(mine)], (c["accuracy"], mine)
    assert c["accuracy"]["amplitude"] == 1e-4 and "peak" in c, c
assert max(c["accuracy"]["harmonics_used"][1] for c in curves) >= 3, [c["accuracy"] for c in curves]
print("ok: FRFs with accuracy: H " + ", ".join(f"{c['accuracy']['harmonics_used']}" for c in curves))
PY
sed 's/^\(    log10_amplitude: .*\)$/\1\n    accuracy: {damping: 2}/' "$SOURCE_DIR/cases/03-one-dof-gaul-mayer/case.yaml" >"$bad"
expect_bad_input run "$bad" -o "$WORK/none"
grep -q "key 'analysis.nonlinear_modes.accuracy.damping'.*relative tolerance in \[0, 1)" "$ERR" || fail "accuracy damping 2: $(cat "$ERR")"

# nonlinear_modes with a static force is refused at the key, before anything is written.
sed 's/- {dof: 0, amplitude: \[0.02, 0.1, 0.4\]}.*/- {dof: 0, amplitude: [0.02, 0.1, 0.4]}\n  - {dof: 0, static: 1.0}/' "$CASE" >"$WORK/static.yaml"
expect_bad_input run "$WORK/static.yaml" -o "$WORK/none"
grep -q "key 'analysis.nonlinear_modes'" "$ERR" || fail "static force: $(cat "$ERR")"
[ ! -e "$WORK/none" ] || fail "an input error left output behind"
finish

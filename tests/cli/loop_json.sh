# jointhb loop --json prints one JSON object whose W_D matches the general-n closed form.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3

run_capture loop --json
[ "$STATUS" -eq 0 ] || fail "loop --json exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$OUT" <<'PY' || fail "loop --json output (gaul-mayer defaults)"
import json, math, sys
d = json.load(open(sys.argv[1]))
keys = ["W_D", "F_hat", "loading_span", "W_D_paper", "W_D_general", "W_D_paper_amplitude_reading",
        "W_D_jenkins", "g_max", "regime", "inputs", "iterations", "residual", "termination", "ok", "message", "seconds"]
missing = [k for k in keys if k not in d]
assert not missing, f"missing keys {missing}"
assert d["W_D"] > 0, d["W_D"]
rel = abs(d["W_D_general"] - d["W_D"]) / d["W_D"]
assert rel <= 1e-9, f"W_D_general differs from W_D by {rel:g}"
assert d["W_D_jenkins"] is None
assert (d["termination"], d["ok"]) == ("converged", True) and "converged" not in d, d["message"]
assert d["regime"] == "microslip", d["regime"]
assert d["inputs"]["law"] == "gaul-mayer" and d["inputs"]["mu"] == 0.3
assert abs(d["g_max"] - 0.3 * 100 / ((1 - 1 / 3) * 1e6)) <= 1e-12 * d["g_max"]
print(f"ok: W_D = {d['W_D']:.10g} J, general formula rel. diff. {rel:.2e}")
PY

# Gross slip: far beyond g_max the force saturates at mu F_N.
run_capture loop --json --amplitude 1e-3
[ "$STATUS" -eq 0 ] || fail "loop --amplitude 1e-3 exited $STATUS: $(cat "$ERR")"
"$PYTHON" -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["regime"]=="gross slip", d["regime"]' \
  "$OUT" || fail "regime at a = 1e-3 m"

# Jenkins: only its own closed form.
run_capture loop --json --law jenkins --amplitude 1e-4
[ "$STATUS" -eq 0 ] || fail "loop --law jenkins exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$OUT" <<'PY' || fail "loop --json output (jenkins)"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["W_D_general"] is None and d["W_D_paper"] is None, d
assert d["W_D_paper_amplitude_reading"] is None
assert d["W_D_jenkins"] is not None
# 4 F_s (a - F_s/k) with F_s = 30 N, k = 1e6 N/m, a = 1e-4 m
expected = 4 * 30 * (1e-4 - 30 / 1e6)
assert abs(d["W_D_jenkins"] - expected) <= 1e-9 * expected, d["W_D_jenkins"]
assert abs(d["W_D"] - expected) <= 1e-9 * expected, d["W_D"]
PY

# With a harmonic the closed forms do not apply.
run_capture loop --json --harmonic 3,2e-6,30 --harmonic 5,1e-6
[ "$STATUS" -eq 0 ] || fail "loop --harmonic exited $STATUS: $(cat "$ERR")"
"$PYTHON" - "$OUT" <<'PY' || fail "loop --json output (harmonics)"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["W_D_general"] is None and d["W_D_paper"] is None, d
h = d["inputs"]["harmonics"]
assert [x["order"] for x in h] == [3, 5] and h[0]["phase_deg"] == 30, h
assert d["W_D"] > 0
PY

# --csv writes one row per sample; the table output names the file.
run_capture loop --time-samples 64 --csv "$WORK/loop.csv"
[ "$STATUS" -eq 0 ] || fail "loop --csv exited $STATUS: $(cat "$ERR")"
[ "$(head -1 "$WORK/loop.csv")" = "phase_rad,slip_m,force_N,normal_force_N" ] ||
  fail "loop.csv header: $(head -1 "$WORK/loop.csv")"
[ "$(wc -l <"$WORK/loop.csv")" -eq 65 ] || fail "loop.csv has $(wc -l <"$WORK/loop.csv") lines"
grep -qi 'nan' "$WORK/loop.csv" "$OUT" && fail "NaN in the output"
grep -q 'W_D' "$OUT" || fail "the table does not show W_D"
finish

# jointhb run on cases/17-chain-internal-resonance: the damping curve of the 30-DOF chain through its
# 7:1 internal resonance is completed from both ends (docs/continuation.md, "A curve traced from
# both ends"): status ok, the message says so, backbone.csv holds the joined curve from log10 q = −3
# to 1 in the summary's order, and every located turn names the row after it.
source "$(dirname "$0")/common.inc" "$@"
PYTHON=/usr/bin/python3
CASE="$SOURCE_DIR/cases/17-chain-internal-resonance/case.yaml"

run_capture run "$CASE" -o "$WORK/out"
[ "$STATUS" -eq 0 ] || fail "run $CASE exited $STATUS: $(cat "$ERR")"
grep -q "the curve turns back in amplitude" "$ERR" || fail "no turns line: $(cat "$ERR")"
"$PYTHON" - "$WORK/out/backbone.csv" "$WORK/out/summary.json" <<'PY' || fail "joined curve outputs"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
s = json.load(open(sys.argv[2]))
assert s["status"] == "ok", s["status"]
b = s["backbones"][0]
assert b["termination"] == "reached_end", b["message"]
assert "from both ends" in b["message"] and "7:1 internal resonance" in b["message"], b["message"]
assert b["points"] == len(rows) == len(b["curve"]), (b["points"], len(rows))
lq = [math.log10(float(r["amplitude"])) for r in rows]
assert abs(lq[0] + 3.0) < 1e-12 and abs(lq[-1] - 1.0) < 1e-12, (lq[0], lq[-1])
# The CSV and the summary's curve are the same points in the same (joined) order.
assert all(abs(float(r["amplitude"]) / p["amplitude"] - 1.0) < 1e-12 for r, p in zip(rows, b["curve"]))
after = [t["after_point"] for t in b["turn_points"]]
assert len(after) > 100 and all(0 < a < len(rows) for a in after), after[:5]
assert after == sorted(after), "turns not in the curve's order"
# A turn is an extremum of log10 q: the rows either side of it lie on one side of the turn.
t = b["turn_points"][0]
i = t["after_point"]
assert abs(t["log10_amplitude"] + 0.376) < 0.01, t
assert t["log10_amplitude"] >= max(lq[i - 1], lq[i]) - t["log10_amplitude_error_bound"], (t, lq[i - 1], lq[i])
print(f"ok: {len(rows)} points, {len(after)} turns")
PY
finish

# Issue 20, item 7: nonsense is refused before any stage runs (exit 2, one line naming the file,
# line, key and constraint, nothing written).
source "$(dirname "$0")/common.inc" "$@"
LAP="$SOURCE_DIR/cases/08-lap-damping/case.yaml"

# An excitation 176 m from the nearest node (the lap's elements are 5 mm long).
sed 's/excitation: {point: \[0.160, 0.015, 0.008\]/excitation: {point: [100.0, 145.0, 0.008]/' "$LAP" >"$WORK/far.yaml"
refused far "far.yaml:[0-9]*:[0-9]*: key 'analysis.excitation.point': must lie on the model .* but lies 176 m from the nearest node" \
  run "$WORK/far.yaml"

# A damping curve of elastic mode 50 when 12 modes are computed, 6 of them rigid.
sed 's/^    mode: 1 .*/    mode: 50/' "$LAP" >"$WORK/mode50.yaml"
refused mode50 "mode50.yaml:[0-9]*:[0-9]*: key 'analysis.nonlinear_modes.mode': elastic mode 50 cannot exist: analysis.modes.count = 12" \
  run "$WORK/mode50.yaml"

# A second YAML document would be ignored.
{ cat "$LAP"; printf -- '---\nanalysis: {preload: {}}\n'; } >"$WORK/twodoc.yaml"
refused twodoc "twodoc.yaml:[0-9]*:1: a second YAML document" run "$WORK/twodoc.yaml"

# Two bolts with one name (refused since f3ed76f; kept here with the others of the issue).
sed 's/name: bolt-2/name: bolt-1/' "$LAP" >"$WORK/bolts.yaml"
refused bolts "bolts.yaml:[0-9]*:[0-9]*: key 'model.bolts\[1\].name': 'bolt-1' is used twice" run "$WORK/bolts.yaml"

# A cache directory that --no-cache would neither read nor write.
refused cache "option '--cache-dir': cannot be combined with --no-cache" run "$LAP" --no-cache --cache-dir "$WORK/cache"

finish

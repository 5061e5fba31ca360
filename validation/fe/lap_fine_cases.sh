#!/usr/bin/env bash
# Issue 16 benchmark: `jointhb run` on refined copies of the built-in default case (cases/08, the
# bolted lap) and on case 09 at H = 3, one process each, with the curve's time breakdown and the
# peak memory gathered into one CSV:
#   validation/fe/lap_fine_cases.sh BUILD_DIR OUTPUT_DIR [CONFIG ...]
# CONFIG: lap60_H3 lap60_H7 lap60_frf_H3 lap120_H3 cu_H3 (default: all but lap120_H3, which needs
# ~12 GB and about 8 minutes). lapNN: NN x (NN * 0.3) x 1 elements per plate (60: 475 node pairs,
# 120: 1 813); frf: three force levels (2, 10, 40 N) over 870-935 Hz. Writes OUTPUT_DIR/<config>/
# (the run's outputs) and OUTPUT_DIR/lap_fine_cases.csv; a benchmark, not a test (no bound on a time).
set -uo pipefail
build=$(cd "$1" && pwd)
out=$2
shift 2
configs=("$@")
if [ ${#configs[@]} -eq 0 ]; then configs=(lap60_H3 lap60_H7 lap60_frf_H3 cu_H3); fi
here=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
csv="$out/lap_fine_cases.csv"
echo "config,curve,points,unknowns,harmonics,curve_s,aft_s,products_s,preconditioner_build_s,preconditioner_apply_s,gmres_iterations,newton_iterations,run_s,peak_rss_MiB,status" > "$csv"

make_case() {  # config -> case file on stdout
  local config=$1 base divisions harmonics
  case $config in
    lap60*) divisions="[60, 18, 1]" ;;
    lap120*) divisions="[120, 36, 1]" ;;
  esac
  harmonics=${config##*_H}
  case $config in
    lap*_frf_*)
      sed -e "s/divisions: \[20, 6, 1\]/divisions: $divisions/g" "$here/cases/08-lap-damping/case.yaml" |
        awk -v h="$harmonics" '/^  nonlinear_modes:/ {print "  frf:\n    frequency_hz: [870.0, 935.0]\n    force: [2.0, 10.0, 40.0]\n    harmonics: " h; skip=1; next}
                               skip && /^    / {next} {skip=0; print}' ;;
    lap*)
      sed -e "s/divisions: \[20, 6, 1\]/divisions: $divisions/g" -e "s/^    harmonics: 1/    harmonics: $harmonics/" \
        "$here/cases/08-lap-damping/case.yaml" ;;
    cu_*)
      sed -e "s/^    harmonics: 1/    harmonics: $harmonics/" "$here/cases/09-control-unit-damping/case.yaml" ;;
  esac
}

status=0
for config in "${configs[@]}"; do
  dir="$out/$config"
  mkdir -p "$dir"
  make_case "$config" > "$dir/case.yaml"
  start=$(date +%s.%N)
  /usr/bin/time -f "%M" -o "$dir/peak_kib" "$build/jointhb" run "$dir/case.yaml" -o "$dir/out" --no-cache \
    > "$dir/stdout.log" 2> "$dir/stderr.log"
  rc=$?
  [ $rc -eq 0 ] || status=1
  end=$(date +%s.%N)
  grep -E "damping curve|frf F|time of the curve|done in" "$dir/stderr.log"
  /usr/bin/python3 - "$dir" "$config" "$start" "$end" "$rc" >> "$csv" <<'EOF'
import json, sys
d, config, run_s, rc = sys.argv[1], sys.argv[2], float(sys.argv[4]) - float(sys.argv[3]), int(sys.argv[5])
peak = int(open(d + "/peak_kib").read().split()[-1]) / 1024.0
try:
    s = json.load(open(d + "/out/summary.json"))
except Exception:
    print(f"{config},,,,,,,,,,,,{run_s:.2f},{peak:.0f},failed (no summary; exit {rc})")
    sys.exit(0)
for kind in ("backbones", "frfs"):
    for i, c in enumerate(s.get(kind, [])):
        t = c["seconds"]
        print(f"{config},{kind[:-1]}{i},{c['points']},{c['unknowns']},{c['harmonics']},{t['total']:.2f},{t['aft']:.2f},"
              f"{t.get('products', 0):.2f},{t.get('preconditioner_build', 0):.2f},{t.get('preconditioner_apply', 0):.2f},"
              f"{t.get('gmres_iterations', 0)},{c['newton_iterations']},{run_s:.2f},{peak:.0f},{c['termination']}")
EOF
done
echo "table: $csv"
exit $status

#!/bin/bash
# Timed study of the parallel global searches (docs/identification.md §2, "Parallel global
# searches"): `jointhb fit` with algorithm direct / mlsl on one and two local worker processes,
# whole-process wall time alternated run by run (A B A B …), and the check that both give the same
# fit_history.csv byte for byte. Cases: case 10 (one DOF, ~20 ms an evaluation) and case 12 (FE lap,
# ~1.2 s an evaluation, direct with max_evaluations 60; skip with CASE12=0).
#   validation/fit/run_parallel_global.sh BUILD_DIR OUT_DIR [RUNS]
# Writes OUT_DIR/parallel_global.csv (case, algorithm, jobs, run, wall_s, evaluations, objective).
set -euo pipefail
BUILD=${1:?build directory}
OUT=${2:?output directory}
RUNS=${3:-3}
JOINTHB="$BUILD/jointhb"
SRC="$(cd "$(dirname "$0")/../.." && pwd)"
mkdir -p "$OUT"
CSV="$OUT/parallel_global.csv"
echo "case,algorithm,jobs,run,wall_s,evaluations,objective" >"$CSV"
echo "load before: $(uptime)"

make_case() {  # make_case CASE_DIR ALGORITHM MAX_EVALUATIONS DEST
  mkdir -p "$4"
  cp "$1"/measured_backbone.csv "$4/"
  sed -e "s/^  algorithm: .*/  algorithm: $2/" -e "s/^  max_evaluations: .*/  max_evaluations: $3/" \
    "$1/case.yaml" >"$4/case.yaml"
}

time_pair() {  # time_pair NAME ALGORITHM DIR
  for run in $(seq 1 "$RUNS"); do
    for jobs in 1 2; do
      rm -rf "$3/out-$jobs"
      t0=$(date +%s.%N)
      "$JOINTHB" fit "$3/case.yaml" -o "$3/out-$jobs" -j "$jobs" --quiet
      t1=$(date +%s.%N)
      /usr/bin/python3 - "$3/out-$jobs/fit.json" "$1" "$2" "$jobs" "$run" "$t0" "$t1" >>"$CSV" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{sys.argv[5]},{float(sys.argv[7]) - float(sys.argv[6]):.3f},{s['evaluations']},{s['objective']!r}")
PY
    done
    cmp -s "$3/out-1/fit_history.csv" "$3/out-2/fit_history.csv" ||
      { echo "$1 $2: fit_history.csv differs between -j 1 and -j 2" >&2; exit 1; }
  done
}

for algorithm in direct mlsl; do
  make_case "$SRC/cases/10-fit-one-dof" "$algorithm" 300 "$OUT/case10-$algorithm"
  time_pair case10 "$algorithm" "$OUT/case10-$algorithm"
done
if [ "${CASE12:-1}" != 0 ]; then
  make_case "$SRC/cases/12-fit-lap" direct 60 "$OUT/case12-direct"
  time_pair case12 direct "$OUT/case12-direct"
fi
echo "load after: $(uptime)"
/usr/bin/python3 - "$CSV" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for key in sorted({(r["case"], r["algorithm"]) for r in rows}):
    t = {j: statistics.median(float(r["wall_s"]) for r in rows if (r["case"], r["algorithm"], r["jobs"]) == (*key, j)) for j in ("1", "2")}
    print(f"{key[0]} {key[1]}: -j 1 {t['1']:.2f} s, -j 2 {t['2']:.2f} s, ratio {t['2'] / t['1']:.2f} (medians), same history")
PY

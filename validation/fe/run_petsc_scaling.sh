#!/usr/bin/env bash
# The FE stages (preload, 20 modes) of cases/05-bolted-lap refined to about 10k, 100k and 300k
# DOFs (docs/performance.md, "Finite-element preload and modes": plates 10m × 3m × n_z with
# m, n_z = 4, 2 / 10, 4 / 15, 6), on the serial path
# (CHOLMOD, ARPACK) and on the PETSc path (MUMPS, SLEPc) under mpirun -np 1 and 2: wall time,
# stage times and each rank's peak RSS, and the agreement of the two paths (contact pressure,
# elastic frequencies). docs/performance.md, "Finite-element stages on MPI ranks (PETSc)".
#   validation/fe/run_petsc_scaling.sh BUILD_DIR OUTPUT_DIR [M ...]     (default 4 10 15)
# RUNS="serial petsc1 petsc2 gamg1 gamg2 hypre1 hypre2" chooses the runs (default the first three;
# gamgR / hypreR: --linear-algebra petsc-gamg / petsc-hypre on R ranks, CG to 1e-10). The serial run
# is the reference of the differences and must come first for a size.
# One row per run is appended to OUTPUT_DIR/petsc_scaling.csv as soon as the run ends.
set -euo pipefail
if (($# < 2)); then
  echo "usage: $0 BUILD_DIR OUTPUT_DIR [M ...]" >&2
  exit 2
fi
jointhb="$(cd "$1" && pwd)/jointhb"
out="$2"
shift 2
sizes=("$@")
((${#sizes[@]})) || sizes=(4 10 15)
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
table="$out/petsc_scaling.csv"
[ -f "$table" ] || echo "m,dofs,path,ranks,wall_s,preload_s,modes_s,rss_rank0_mib,rss_rank1_mib,factor_entries,max_pressure_rel_diff,max_elastic_freq_rel_diff,load" >"$table"
mpirun=(mpirun --allow-run-as-root --oversubscribe)
for m in "${sizes[@]}"; do
  case_file="$out/case_m$m.yaml"
  sed -e "s/divisions: \[40, 12, 2\]/divisions: [$((10 * m)), $((3 * m)), $(((2 * m + 2) / 5))]/" \
    "$source_dir/cases/05-bolted-lap/case.yaml" >"$case_file"
  grep -q "divisions: \[$((10 * m)), " "$case_file" || { echo "divisions not replaced" >&2; exit 1; }
  for run in ${RUNS:-serial petsc1 petsc2}; do
    dir="$out/m${m}_$run"
    rm -rf "$dir" "$out"/rss_${m}_$run.*
    load=$(cut -d' ' -f1 /proc/loadavg)
    echo "== m = $m, $run, load $load" >&2
    start=$(date +%s.%N)
    case $run in
      serial) /usr/bin/time -f "%M" -o "$out/rss_${m}_$run.0" "$jointhb" run "$case_file" -o "$dir" --no-cache ;;
      *) ranks=${run: -1}
         path=petsc
         [ "${run%?}" = petsc ] || path="petsc-${run%?}"
         "${mpirun[@]}" -np "$ranks" bash -c "exec /usr/bin/time -f %M -o $out/rss_${m}_$run.\$OMPI_COMM_WORLD_RANK \
                $jointhb run $case_file -o $dir --no-cache --linear-algebra $path" ;;
    esac
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    rss0=$(($(tail -1 "$out/rss_${m}_$run.0") / 1024))
    rss1=""
    [ -f "$out/rss_${m}_$run.1" ] && rss1=$(($(tail -1 "$out/rss_${m}_$run.1") / 1024))
    /usr/bin/python3 - "$out/m${m}_serial" "$dir" "$m" "$run" "$wall" "$rss0" "$rss1" "$load" >>"$table" <<'PY'
import csv, json, sys
ref, d, m, run, wall, rss0, rss1, load = sys.argv[1:]
s = json.load(open(f"{d}/summary.json"))
p = s["preload"]
mo = s["modes"]
ranks = s.get("solvers", {}).get("ranks", 1)
factor = p.get("factor", "")
def column(directory, name, key):
    return [float(r[key]) for r in csv.DictReader(open(f"{directory}/{name}"))]
pa, pb = column(ref, "contact_lap.csv", "pressure"), column(d, "contact_lap.csv", "pressure")
dp = max(abs(x - y) for x, y in zip(pa, pb)) / max(abs(x) for x in pa)
fa, fb = column(ref, "modes.csv", "frequency_hz"), column(d, "modes.csv", "frequency_hz")
df = max(abs(x - y) / x for x, y in zip(fa[6:], fb[6:]))
path = {"serial": "serial", "petsc": "petsc"}.get(run[:-1] if run != "serial" else run, "petsc-" + run[:-1])
print(f"{m},{s['model']['dofs']},{path},{ranks},{float(wall):.2f},"
      f"{p['seconds']['total']:.2f},{mo['seconds']:.2f},{rss0},{rss1},\"{factor}\",{dp:.2e},{df:.2e},{load}")
PY
    tail -1 "$table" >&2
  done
done

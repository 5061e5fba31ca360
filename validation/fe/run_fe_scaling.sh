#!/usr/bin/env bash
# Runs validation/fe/fe_scaling.cpp at about 10k, 100k and 300k DOFs, one size per process (so
# each peak RSS is that size's own), and gathers the rows into PREFIX_table.csv.
#   validation/fe/run_fe_scaling.sh BUILD_DIR OUTPUT_PREFIX [DOFS ...]    (default 10000 100000 300000)
# BLAS=reference|openblas-serial|openblas-pthread picks the Debian BLAS + LAPACK through
# LD_LIBRARY_PATH (no rebuild); unset, libblas.so.3 is whatever update-alternatives selects.
# Thread counts come from the environment (OPENBLAS_NUM_THREADS, OMP_NUM_THREADS). The BLAS
# actually loaded and the thread variables are recorded in every row.
set -euo pipefail
if (($# < 2)); then
  echo "usage: $0 BUILD_DIR OUTPUT_PREFIX [DOFS ...]" >&2
  exit 2
fi
program="$1/validation/fe/jointhb_validate_fe_fe_scaling"
prefix="$2"
shift 2
sizes=("$@")
((${#sizes[@]})) || sizes=(10000 100000 300000)
case "${BLAS:-}" in
  "") ;;
  reference) export LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/blas:/usr/lib/x86_64-linux-gnu/lapack ;;
  openblas-serial | openblas-pthread) export LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/$BLAS ;;
  *) echo "BLAS must be reference, openblas-serial or openblas-pthread, got '$BLAS'" >&2; exit 2 ;;
esac
mkdir -p "$(dirname "$prefix")"
table="${prefix}_table.csv"
rm -f "$table"
for n in "${sizes[@]}"; do
  echo "== --dofs $n, load average $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "${prefix}_log.txt"
  "$program" "$prefix" --dofs "$n" ${EXTRA:-} | tee -a "${prefix}_log.txt"
  # The row just written: the newest PREFIX_<dofs>.csv.
  row=$(ls -t "${prefix}"_[0-9]*.csv | grep -v _modes | head -1)
  [ -f "$table" ] || head -1 "$row" >"$table"
  tail -n +2 "$row" >>"$table"
done
echo "table: $table"

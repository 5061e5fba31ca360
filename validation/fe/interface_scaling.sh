#!/usr/bin/env bash
# Runs validation/fe/interface_scaling one configuration per process (so that the peak resident
# set is that configuration's) and concatenates the tables:
#   validation/fe/interface_scaling.sh BUILD_DIR OUTPUT_PREFIX [LABEL ...]
# LABEL: P<points>_H<h> (default: all nine, P96/P400/P1600 x H1/H3/H7). EXTRA: more arguments for
# every run (e.g. EXTRA="--budget 1500", or EXTRA="--matrix-free-only" to re-measure only the
# matrix-free curves). A configuration that exceeds a bound is reported and the
# loop goes on (the exit status is then 1).
set -uo pipefail
build=$1
prefix=$2
shift 2
labels=("$@")
if [ ${#labels[@]} -eq 0 ]; then
  labels=(P96_H1 P96_H3 P96_H7 P400_H1 P400_H3 P400_H7 P1600_H1 P1600_H3 P1600_H7)
fi
exe="$build/validation/fe/jointhb_validate_fe_interface_scaling"
table="${prefix}_table.csv"
rm -f "$table"
status=0
for label in "${labels[@]}"; do
  # shellcheck disable=SC2086
  "$exe" --only "$label" ${EXTRA:-} "${prefix}_$label" | tee "${prefix}_$label.log" || status=1
  if [ ! -f "$table" ]; then head -1 "${prefix}_${label}_table.csv" > "$table"; fi
  tail -n +2 "${prefix}_${label}_table.csv" >> "$table"
done
echo "table: $table"
exit $status

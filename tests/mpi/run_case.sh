#!/usr/bin/env bash
# The scree executable under mpirun: the elastic column (shortened to 0.5 s) on N ranks, in
# a copy of the case, written as one case: exit status 0, one .pvd, the last frame a .pvtp
# of one piece per rank whose pieces hold every point, the log's decomposition line; then the same copy continued from
# its checkpoint on one rank (--restart with a later endTime) exits 0.
#
#   run_case.sh MPIEXEC NP SCREE SOURCE_DIR
set -euo pipefail
mpiexec=$1 np=$2 scree=$3 src=$4
work=$(mktemp -d /tmp/scree-mpi-case-XXXXXX)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 -c "import sys; sys.path.insert(0, '$src/tests/support'); import case_copy; case_copy.copy_case('$src/cases/elasticColumn', '$work/c')" 2>/dev/null ||
  { mkdir -p "$work/c"; cp -r "$src/cases/elasticColumn/system" "$src/cases/elasticColumn/constant" "$work/c/"; }
printf '\n#inputMode overwrite\nendTime 0.5;\n' >> "$work/c/system/controlDict"
"$mpiexec" -np "$np" --oversubscribe "$scree" --case "$work/c" --device cpu > "$work/log" 2>&1 ||
  { cat "$work/log"; echo "run_case: mpirun -np $np scree failed"; exit 1; }
grep -q "Decomposed over $np ranks" "$work/log" || { cat "$work/log"; echo "run_case: no decomposition line"; exit 1; }
[ "$(ls "$work/c/VTK"/*.pvd | wc -l)" -eq 1 ] || { echo "run_case: expected one .pvd"; exit 1; }
last=$(ls -v "$work/c/VTK"/particles_*.pvtp | tail -1)
[ "$(grep -c '<Piece Source=' "$last")" -eq "$np" ] || { echo "run_case: $last does not list $np pieces"; exit 1; }
held=$(cd "$work/c/VTK" && grep -o 'Source="[^"]*"' "$(basename "$last")" | cut -d'"' -f2 |
  xargs grep -aho 'NumberOfPoints="[0-9]*"' | tr -dc '0-9\n' | awk '{ n += $1 } END { print n }')
[ "$held" = 1280 ] || { echo "run_case: the pieces of $last hold $held points, not the 1280"; exit 1; }
printf '\n#inputMode overwrite\nendTime 0.75;\n' >> "$work/c/system/controlDict"
"$scree" --case "$work/c" --device cpu --restart > "$work/log1" 2>&1 ||
  { cat "$work/log1"; echo "run_case: the one-rank restart of the decomposed run failed"; exit 1; }
grep -q 'NumberOfPoints="1280"' "$(ls -v "$work/c/VTK"/particles_*.vtp | tail -1)" || { echo "run_case: restart lost points"; exit 1; }
echo "run_case: $np ranks wrote one case of 1280 points; one rank continued it"

#!/usr/bin/env bash
# The best a batched ensemble engine can do for the 5 mm column: N copies of the column in
# one body, side by side on one floor in one grid, run as one case (one launch per phase
# of the step over the points of all N, one clock), against one copy alone. A batched
# engine adds to this a member index per point, per-member parameters and a clock per
# member; it cannot take fewer launches or touch fewer points and nodes. So the ratio
# printed here is a lower bound on what 256 members sharing launches would cost over one.
#
#   measure/gpu-ensemble-bound.sh <endTime> <N...> <out-dir>
#
# e.g. measure/gpu-ensemble-bound.sh 0.4 1 16 64 256 OUT. Each copy is the column of
# cases/columnCollapseEnsemble (0.2 m x 0.1 m, 5 mm cells, 3,200 points, geostatic at
# rest) collapsing from t = 0 without its gate (both sides free), 0.6 m of floor each:
# copies never meet before 0.4 s. Without writers or function objects (--no-output).
# Prints, per N: steps, wall time [s], ms per step, ratio to N = 1, member-steps/s.
# SCREE_BUILD_DIR: the build (default build); SCREE_DEVICE: the backend (default cuda);
# SCREE_BOUND_SAND: entries added to the sand's dictionary (e.g. "integrationTolerance 1;",
# to see what a setting moves); SCREE_BOUND_ARGS: more scree options (e.g. --profile);
# SCREE_BOUND_WRAP: a command to run scree under (e.g. ncu and its options).
set -euo pipefail
end_time=$1
shift
out=${*: -1}
ns=("${@:1:$#-1}")
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${SCREE_BUILD_DIR:-build}/bin/scree
dev=${SCREE_DEVICE:-cuda}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

make_case() {  # make_case <dir> <N>
  local dir=$1 n=$2
  cp -r "$here/cases/columnCollapseEnsemble" "$dir"
  rm -rf "$dir/ensemble" "$dir/figures" "$dir/system/ensembleDict"
  sed -i "s/^endTime .*/endTime $end_time;/" "$dir/system/controlDict"
  [ -z "${SCREE_BOUND_SAND:-}" ] || sed -i "0,/^}/s//#inputMode overwrite\n$SCREE_BOUND_SAND\n}/" "$dir/constant/materialProperties"
  echo '_releaseTime 0;' >"$dir/system/stages"
  cat >"$dir/system/mpmSchemes" <<'EOF'
FoamFile { version 2.0; format ascii; class dictionary; object mpmSchemes; }
updateScheme    USF;
shapeFunction   linear;
transfer        FLIP;
picRate         10;
EOF
  cat >"$dir/system/gridDict" <<EOF
FoamFile { version 2.0; format ascii; class dictionary; object gridDict; }
dimension   2;
lower       (0 0);
upper       ($(awk "BEGIN { print 0.6 * $n }") 0.12);
cellSize    0.005;
EOF
  cat >"$dir/constant/boundaryConditions" <<'EOF'
FoamFile { version 2.0; format ascii; class dictionary; object boundaryConditions; }
floor       { type fixed;   face yMin; }
EOF
  # One polygon: N rectangles 0.2 m x 0.1 m, 0.2 m from the left of their 0.6 m each,
  # joined by edges on the floor (y = 0, where no point's cell centre lies).
  local pts
  pts=$(awk -v n="$n" 'BEGIN {
    for (i = 0; i < n; ++i) { x = 0.6 * i + 0.2; printf "(%g 0) (%g 0.1) (%g 0.1) (%g 0) ", x, x, x + 0.2, x + 0.2 } }')
  cat >"$dir/constant/bodies" <<EOF
FoamFile { version 2.0; format ascii; class dictionary; object bodies; }
column
{
    material            sand;
    region              { type polygon; points ($pts); }
    particlesPerCell    2;
    initialStress       { type geostatic; K0 0.5; }
}
EOF
}

printf "%-8s %10s %10s %10s %10s %16s\n" copies points steps "wall [s]" "ms/step" "member-steps/s"
base=""
for n in "${ns[@]}"; do
  make_case "$work/n$n" "$n"
  t0=$(date +%s.%N)
  ${SCREE_BOUND_WRAP:-} "$bin" --case "$work/n$n" --device "$dev" --no-output --overwrite ${SCREE_BOUND_ARGS:-} >"$out/copies-$n.log" 2>&1 ||
    { echo "N = $n failed:"; tail -5 "$out/copies-$n.log"; exit 1; }
  t1=$(date +%s.%N)
  wall=$(awk "BEGIN { print $t1 - $t0 }")
  steps=$(grep -o 'done: [0-9]* steps' "$out/copies-$n.log" | grep -o '[0-9]*')
  points=$(grep -o '[0-9]* particles,' "$out/copies-$n.log" | head -1 | grep -o '[0-9]*')
  [ -n "$base" ] || base=$wall
  printf "%-8s %10s %10s %10.2f %10.4f %16.0f   x%.2f of one\n" "$n" "$points" "$steps" "$wall" \
    "$(awk "BEGIN { print 1000 * $wall / $steps }")" "$(awk "BEGIN { print $n * $steps / $wall }")" \
    "$(awk "BEGIN { print $wall / $base }")"
done

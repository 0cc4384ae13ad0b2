#!/usr/bin/env bash
# The four readings of the seed's 1D infiltration (two permeabilities x two top conditions),
# run with scree (two-phase MPM) and with scree-richards (the 1D Richards reference), then
# compared: profiles of pore pressure at the Richards output times, and the wetting front.
#
#   cases/infiltration1D/run-comparison.sh [BUILD_DIR [WORK_DIR]] [-- scree options]
#
# Writes WORK_DIR/<variant>/{mpm,richards,richards_skeleton,richards_skeleton_noload}/ and
# WORK_DIR/comparison.csv; the figure cases/infiltration1D/comparison.png comes from compare.py.
# Three references per variant: `richards` the rigid skeleton (the classic Richards
# equation), `richards_skeleton` with the MPM's skeleton, oedometricModulus = E_oed =
# E (1 - nu)/((1 + nu)(1 - 2 nu)) of the case's materialProperties (its storage and the weight
# of the water; utilities/richards1d/README.md), `richards_skeleton_noload` the same without
# the weight (waterLoad no).
# SKIP_MPM=1 reruns only the references and the comparison, keeping WORK_DIR/<variant>/mpm.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
work=${2:-/tmp/scree-infiltration1D}
shift $(( $# > 2 ? 2 : $# )) || true
[ "${1:-}" = "--" ] && shift
mkdir -p "$work"
conf="$root/utilities/richards1d/infiltration1D"
# variant: permeability line, top condition, end time [s], write interval [s]
variants=(
  "kappa_ponding|intrinsicPermeability   2e-10;|pond|1|0.1"
  "kappa_rain|intrinsicPermeability   2e-10;|rain|5|0.5"
  "Ksat2e-4_ponding|hydraulicConductivity   2e-4;|pond|5|0.5"
  "Ksat2e-4_rain|hydraulicConductivity   2e-4;|rain|10|1"
)
# Each with two skeletons: Table A's (E = 5 MPa, `seed`) and a rigid one (E = 500 MPa,
# `rigid`), the Richards equation's own assumption (README: what the skeleton changes).
for v0 in "${variants[@]}"; do for skel in seed rigid; do
  IFS='|' read -r name perm top end every <<<"$v0"
  name="${name}_$skel"
  d="$work/$name"
  if [ -n "${SKIP_MPM:-}" ] && [ -d "$d/mpm/VTK" ]; then
    echo "== $name: keeping $d/mpm"
  else
    rm -rf "$d"; mkdir -p "$d"; cp -r "$here/system" "$here/constant" "$d/"
    mv "$d/system" "$d/mpm_system"; mkdir -p "$d/mpm"; mv "$d/mpm_system" "$d/mpm/system"; mv "$d/constant" "$d/mpm/"
    sed -i "s|^        intrinsicPermeability   2e-10;|        $perm|" "$d/mpm/constant/bodies"
    if [ "$top" = pond ]; then
      sed -i 's|^rain |// rain |; s|^// pond |pond |' "$d/mpm/constant/boundaryConditions"
    fi
    sed -i "s|^endTime .*|endTime         $end;|; s|^writeInterval .*|writeInterval   $every;|" "$d/mpm/system/controlDict"
    [ "$skel" = rigid ] && sed -i "s|E 5e6;|E 5e8;|" "$d/mpm/constant/materialProperties"
    echo "== $name: scree to $end s"
    /usr/bin/time -f "$name mpm wall %e s" "$build/bin/scree" --case "$d/mpm" --overwrite "$@" > "$d/mpm.log" 2>&1 || { tail "$d/mpm.log"; exit 1; }
    tail -1 "$d/mpm.log"
  fi
  times=$(awk -v e="$end" -v s="$every" 'BEGIN{for(t=s;t<=e+1e-9;t+=s) printf "%g ", t}')
  # The skeleton's oedometric modulus, from the copy of the case that ran (linearElastic E, nu).
  eoed=$(sed -n 's|^soil *{.*[^a-zA-Z]E  *\([-0-9.eE+]*\);.* nu  *\([-0-9.eE+]*\);.*|\1 \2|p' "$d/mpm/constant/materialProperties" |
    awk '{E = $1; nu = $2; printf "%.6g", E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))}')
  [ -n "$eoed" ] || { echo "no linearElastic E, nu in $d/mpm/constant/materialProperties"; exit 1; }
  rc=(--config "$conf/${name%_*}.conf" --set "profileTimes=$times" --set "endTime=$end" --quiet)
  "$build/bin/scree-richards" "${rc[@]}" --out "$d/richards"
  "$build/bin/scree-richards" "${rc[@]}" --out "$d/richards_skeleton" --set "oedometricModulus=$eoed"
  "$build/bin/scree-richards" "${rc[@]}" --out "$d/richards_skeleton_noload" --set "oedometricModulus=$eoed" \
    --set "waterLoad=no"
  echo "   references: rigid, and E_oed = $eoed Pa with and without the water's weight"
done; done
/usr/bin/python3 "$here/compare.py" "$work" "$here/comparison.png"

#!/usr/bin/env bash
# An ensemble's whole run against one of its members alone, on one GPU, one after the
# other: what the ensemble costs over running a single member, and its throughput in
# member-steps per second against running the members one after another.
#
#   measure/gpu-ensemble.sh <ensemble-case> <samples> <members-at-once...> <out-dir>
#
# e.g. measure/gpu-ensemble.sh cases/columnCollapseEnsemble 256 1 8 16 OUT: member 0 alone
# (its case ensemble/member_0000, written by an ensemble of one sample, run again by
# itself with plain scree), then the ensemble cut to <samples> members (the first of its
# members: a member's values do not depend on how many there are) at each membersAtOnce. Writes into
# <out-dir>: alone.log, ensemble-<k>.log (scree's output), ensemble-<k>-members.csv, and
# prints a table: wall time, the ratio to one member alone, member-steps/s.
# SCREE_BUILD_DIR: the build (default build); SCREE_DEVICE: the backend (default cuda).
set -euo pipefail
case_dir=$1 samples=$2
shift 2
out=${*: -1}
ks=("${@:1:$#-1}")
bin=${SCREE_BUILD_DIR:-build}/bin/scree
dev=${SCREE_DEVICE:-cuda}
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Member 0 alone: the ensemble of one sample writes its case; run that case by itself.
cp -r "$case_dir" "$work/one"
rm -rf "$work/one/ensemble"
sed -i "s/^\([[:space:]]*samples[[:space:]]*\)[0-9]*;/\11;/" "$work/one/system/ensembleDict"
sed -i "/^[[:space:]]*membersAtOnce/d" "$work/one/system/ensembleDict"
"$bin" --case "$work/one" --device "$dev" >"$out/prepare.log" 2>&1 || { tail -5 "$out/prepare.log"; exit 1; }
t0=$(date +%s.%N)
"$bin" --case "$work/one/ensemble/member_0000" --device "$dev" --overwrite >"$out/alone.log" 2>&1
t1=$(date +%s.%N)
alone=$(awk "BEGIN { print $t1 - $t0 }")
steps=$(grep -o 'done: [0-9]* steps' "$out/alone.log" | grep -o '[0-9]*')
printf "%-28s %10s %8s %16s\n" run "wall [s]" "x alone" "member-steps/s"
printf "%-28s %10.1f %8.2f %16.0f\n" "member 0 alone" "$alone" 1 "$(awk "BEGIN { print $steps / $alone }")"
for k in "${ks[@]}"; do
  rm -rf "$work/ens"
  cp -r "$case_dir" "$work/ens"
  rm -rf "$work/ens/ensemble"
  sed -i "s/^\([[:space:]]*samples[[:space:]]*\)[0-9]*;/\1$samples;/" "$work/ens/system/ensembleDict"
  sed -i "/^[[:space:]]*membersAtOnce/d" "$work/ens/system/ensembleDict"
  echo "membersAtOnce $k;" >>"$work/ens/system/ensembleDict"
  t0=$(date +%s.%N)
  "$bin" --case "$work/ens" --device "$dev" >"$out/ensemble-$k.log" 2>&1 || true
  t1=$(date +%s.%N)
  wall=$(awk "BEGIN { print $t1 - $t0 }")
  cp "$work/ens/ensemble/members.csv" "$out/ensemble-$k-members.csv" 2>/dev/null || true
  total=0
  for log in "$work"/ens/ensemble/member_*/log.scree; do
    s=$(grep -o 'done: [0-9]* steps' "$log" | grep -o '[0-9]*' || echo 0)
    total=$((total + s))
  done
  n=$(($(wc -l <"$work/ens/ensemble/members.csv") - 1))
  printf "%-28s %10.1f %8.2f %16.0f\n" "$n members, $k at once" "$wall" "$(awk "BEGIN { print $wall / $alone }")" \
    "$(awk "BEGIN { print $total / $wall }")"
done

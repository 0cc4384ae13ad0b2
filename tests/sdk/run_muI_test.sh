#!/usr/bin/env bash
# The mu(I) example of docs/writing-a-material.md, end to end as a user runs it: install
# Scree from the build tree into a temporary prefix, build examples/muIRheology (the
# plugin) and its check program against the installed package, validate and start the
# case examples/muIRheology/inclinedPlane with the installed scree (the case loads the
# plugin with libs ("libmuI.so"), found through SCREE_PLUGIN_PATH), then run the check:
# a point test through the registry's PointMaterial and the steady inclined-plane flow
# against Bagnold's profile; last, the same check with mu2 20 % too large must fail.
#   run_muI_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1; src=$2
work=$(mktemp -d /tmp/scree-muI-XXXXXX)
trap 'rm -rf "$work"' EXIT
start=$(date +%s)
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cuda_args=()
grep -q "SCREE_WITH_CUDA:BOOL=ON" "$build/CMakeCache.txt" && cuda_args=(-DCMAKE_CUDA_COMPILER=/usr/local/cuda/bin/nvcc)
for part in plugin check; do
  dir="$src/examples/muIRheology"; [ "$part" = check ] && dir="$dir/check"
  cmake -S "$dir" -B "$work/$part" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$work/prefix" "${cuda_args[@]}" >/dev/null
  cmake --build "$work/$part" >/dev/null
done
echo "built the plugin and the check against the installed Scree in $(( $(date +%s) - start )) s"
export SCREE_PLUGIN_PATH="$work/plugin/lib/scree/plugins"
ls "$SCREE_PLUGIN_PATH/libmuI.so" >/dev/null
# Copied without the results of any run of the example in the source tree (case_copy.py).
python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); from case_copy import copy_case; copy_case(*sys.argv[2:])' \
  "$src/tests/support" "$src/examples/muIRheology/inclinedPlane" "$work/case"
grep -q 'libs *("libmuI.so")' "$work/case/system/controlDict"
"$work/prefix/bin/scree" --case "$work/case" --check
# A few steps with the installed solver itself: the plugin's fields reach the output.
"$work/prefix/bin/scree" --case "$work/case" --device cpu --threads 2 --max-steps 5 >/dev/null
grep -q inertialNumber "$work/case/VTK/particles_0.vtp" || { echo "muI field missing in the output"; exit 1; }
"$work/check/muI-bagnold" "$work/case" --threads 2
"$work/check/muI-bagnold" "$work/case" --threads 2 --perturb-mu2 1.2
echo "muI example passed in $(( $(date +%s) - start )) s: plugin built out of tree, loaded by libs, Bagnold profile matched, a wrong mu2 detected"

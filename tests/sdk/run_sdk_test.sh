#!/usr/bin/env bash
# Install Scree from the build tree into a temporary prefix, build the out-of-tree
# neoHookean plugin against it as its author does while writing it (Debug: unoptimised, and
# loaded by the optimised core all the same), and run a small case with the installed scree
# loading the plugin through SCREE_PLUGIN_PATH; then a material from a shipped parameter set
# (#includeEtc) checked by the installed scree. Fails on any step. (The Release build of an
# out-of-tree material is run_muI_test.sh's.)
#   run_sdk_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1; src=$2
work=$(mktemp -d /tmp/scree-sdk-XXXXXX)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cuda_args=()
grep -q "SCREE_WITH_CUDA:BOOL=ON" "$build/CMakeCache.txt" && cuda_args=(-DCMAKE_CUDA_COMPILER=/usr/local/cuda/bin/nvcc)
cmake -S "$src/tests/sdk/neoHookean" -B "$work/plugin" -G Ninja -DCMAKE_BUILD_TYPE=Debug \
      -DCMAKE_PREFIX_PATH="$work/prefix" "${cuda_args[@]}" >/dev/null
cmake --build "$work/plugin" >/dev/null
plugin_dir="$work/plugin/lib/scree/plugins"
ls "$plugin_dir"/libneoHookean.so >/dev/null
export SCREE_PLUGIN_PATH="$plugin_dir"
listing=$("$work/prefix/bin/scree" --list-plugins material)
grep -q "neoHookean" <<<"$listing"
# A small block settling under gravity with the plugin's material.
case_dir="$work/case"
mkdir -p "$case_dir/system" "$case_dir/constant"
cat > "$case_dir/system/controlDict" <<'D'
endTime 0.05; deltaT 2e-4; writeInterval 0.05;
writers { particles { type vtk; } }
D
echo 'dimension 2; lower (0 0); upper (0.4 0.4); cellSize 0.05;' > "$case_dir/system/gridDict"
echo 'value (0 -9.81);' > "$case_dir/constant/g"
echo 'rubber { type neoHookean; shearModulus 1e5; lameLambda 2e5; rho 1000; }' > "$case_dir/constant/materialProperties"
echo 'block { material rubber; region { type rectangle; lower (0 0); upper (0.2 0.2); } }' > "$case_dir/constant/bodies"
echo 'floor { type fixed; face yMin; }' > "$case_dir/constant/boundaryConditions"
"$work/prefix/bin/scree" --case "$case_dir" --device cpu --threads 1
test -f "$case_dir/VTK/particles.pvd"
grep -q volumeRatio "$case_dir"/VTK/particles_1.vtp || { echo "plugin field missing in output"; exit 1; }
# The installed scree finds its shipped parameter sets (#includeEtc), away from the sources.
cat > "$case_dir/constant/materialProperties" <<'D'
rubber { type neoHookean; shearModulus 1e5; lameLambda 2e5; rho 1000; }
sand { #includeEtc "materials/feng2025/table3-columnCollapse" integrationTolerance 1e-2; }
D
"$work/prefix/bin/scree" --case "$case_dir" --check > "$work/check.log" 2>&1 || { cat "$work/check.log"; exit 1; }
test -f "$work/prefix/share/scree/etc/materials/feng2025/table3-columnCollapse"
echo "SDK test passed: installed Scree, out-of-tree plugin built, loaded and run; its parameter sets found"

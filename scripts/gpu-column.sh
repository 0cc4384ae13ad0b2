#!/usr/bin/env bash
# The column collapse of seed 001 (section 4.1) at the paper's resolution on a lent GPU, with
# the output the figures need, in one device call (issue 5).
#
#   scripts/gpu-column.sh [RUN...]      on the GPU machine, from the repository root
#
# RUN: pt (cases/columnCollapse, phaseTransition, 1 mm), frictional (the same with SIMSAND
# alone), C-1, C-2, C-3 (the Appendix C meshes, phaseTransition); default: pt frictional.
# Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda); device call: carry [".gpu-bundle"].
# The snapshots are written in single precision with the fields the plots and a ParaView
# picture need (the case files are the device's copy: the repository is not changed), and
# each run comes back as $OUT/<run>.tar.gz: VTK/ (the snapshots at release and 0.05, 0.25,
# 0.5, 1 s after it, with a .pvd listing them), postProcessing/ and the run's log.
# Unpack with: mkdir -p runs/<run> && tar -xzf <run>.tar.gz -C runs/<run>
set -uo pipefail
out=${OUT:-gpu-column-out}
mkdir -p "$out"
[ -f .gpu-bundle/env.sh ] && source .gpu-bundle/env.sh
bin=${SCREE_BIN:-build-cuda/bin}       # SCREE_BIN, SCREE_DEVICE: a local trial on the CPU
runs=${*:-pt frictional}
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv | tee "$out/device.txt"

# Lean snapshots: the fields of utilities/plot/column_collapse.py and the picture.
cc=cases/columnCollapse/system/controlDict
sed -i -e '/fields *(velocity/,/);/c\        fields  (velocity displacement stress pressure volume mass plasticStrain shearViscosity granularTemperature collisionalFraction);\n        precision single;\n        compressionLevel 6;' "$cc"
grep -A4 "type    vtk" "$cc"

declare -A dir=([pt]=cases/columnCollapse [frictional]=cases/columnCollapse/variants/frictional
  [C-1]=cases/columnCollapse/variants/C-1 [C-2]=cases/columnCollapse/variants/C-2
  [C-3]=cases/columnCollapse/variants/C-3)
declare -A limit=([pt]=240 [frictional]=240 [C-1]=60 [C-2]=90 [C-3]=150)
for r in $runs; do
  d=${dir[$r]}
  rm -rf "$d/VTK" "$d/postProcessing"
  echo "==== $r: $d"
  start=$(date +%s.%N)
  timeout "${limit[$r]}" $bin/scree --case "$d" --device "${SCREE_DEVICE:-cuda}" > "$out/$r.log" 2>&1
  rc=$?
  end=$(date +%s.%N)
  echo "$r exit $rc wall $(awk "BEGIN{printf \"%.1f\", $end - $start}") s" | tee -a "$out/walltimes.txt"
  tail -4 "$out/$r.log"
  # The snapshots at release (0.1 s) and 0.05, 0.25, 0.5, 1 s after it, and a .pvd of them.
  keep=()
  pvd=$d/VTK/particles.pvd
  if [ -f "$pvd" ]; then
    for t in 0.1 0.15 0.35 0.6 1.1; do
      f=$(grep -oE "timestep=\"$t[0-9]*\"[^>]*file=\"[^\"]+\"" "$pvd" | head -1 | sed -E 's/.*file="([^"]+)".*/\1/')
      [ -n "$f" ] && keep+=("$f")
    done
    { grep -v "<DataSet" "$pvd" | sed '/<\/Collection>/,$d'
      for f in "${keep[@]}"; do grep "file=\"$f\"" "$pvd"; done
      sed -n '/<\/Collection>/,$p' "$pvd"; } > "$d/VTK/selected.pvd"
    mv "$d/VTK/selected.pvd" "$pvd"
  fi
  cp "$out/$r.log" "$d/run.log"
  (cd "$d" && tar -czf - run.log postProcessing $(printf 'VTK/%s ' "${keep[@]}") $( [ -f VTK/particles.pvd ] && echo VTK/particles.pvd)) > "$out/$r.tar.gz"
  ls -la "$out/$r.tar.gz"
done
cat "$out/walltimes.txt"

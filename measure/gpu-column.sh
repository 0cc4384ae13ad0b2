#!/usr/bin/env bash
# The column collapse of Feng et al. 2025 (section 4.1) on a lent GPU machine: the paper's 1 mm
# runs, the Appendix C mesh study on the GPU and on the CPU cores, and the benchmark, run in
# the background so that they can outlast one device call.
#
#   measure/gpu-column.sh start [GPU_RUNS] [-- CPU_RUNS]   set up and launch (returns at once)
#   measure/gpu-column.sh status                           progress of every run
#   measure/gpu-column.sh wait SECONDS                     status every 60 s until all done
#   measure/gpu-column.sh collect                          pack the results into $OUT
#
# GPU_RUNS (one after another on the GPU, cores 0-1; processes sharing a GPU without MPS
# are time-sliced, so there is one queue): pt (cases/columnCollapse,
# phaseTransition, 1 mm), frictional (the same with SIMSAND alone), C-1, C-2, C-3 (Appendix
# C meshes), bench (scree-bench: paper cases and weak scaling). Default: pt frictional bench
# C-3 C-2 C-1. CPU_RUNS (one after another on cores 2-15, 14 threads): C-1 C-2 C-3 and
# C-4w (1 mm, two 2,000-step windows, at rest and flowing, for an estimate of the whole run).
# Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda; another build folder: SCREE_BUILD_DIR=...):
# carry [".gpu-bundle"]. `start`
# copies the executables and cases to /tmp/scree-session, so that later calls (on the same,
# still warm machine) do not disturb the runs. Snapshots are single precision with the fields
# the plots and a ParaView picture need; each run comes back as $OUT/<run>.tar.gz with its
# snapshots at the release and 0.05, 0.25, 0.5 and 1 s after it, postProcessing/ and the log.
# Here: mkdir -p runs/<run> && tar -xzf <run>.tar.gz -C runs/<run>
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/gpu-common.sh"
S=/tmp/scree-session
out=${OUT:-$PWD/gpu-column-out}

case_dir() {
  case $1 in
    pt) echo $S/cases/columnCollapse ;;
    frictional) echo $S/cases/columnCollapse/variants/frictional ;;
    C-4w) echo $S/cases/columnCollapse ;;
    *) echo $S/cases/columnCollapse/variants/$1 ;;
  esac
}

timed() {  # timed NAME LOG CMD...: run, append "NAME exit RC wall S s" to walltimes
  local name=$1 log=$2
  shift 2
  local t0 t1 rc
  t0=$(date +%s.%N)
  "$@" > "$log" 2>&1
  rc=$?
  t1=$(date +%s.%N)
  echo "$name exit $rc wall $(awk "BEGIN{printf \"%.1f\", $t1 - $t0}") s" >> $S/walltimes.txt
}

gpu_queue() {
  for r in "$@"; do
    if [ "$r" = bench ]; then
      timed gpu:bench $S/logs/gpu-bench.log taskset -c 0-1 $S/build/bin/scree-bench --device cuda \
        --cases column,flume,scaling --source-dir $S --materials phaseTransition,linearElastic --shapes linear \
        --schemes USL --max-particles 10000000 --steps 400 --column-steps 2000 --flume-steps 1000 \
        --csv $S/bench-gpu.csv --json /dev/null
      continue
    fi
    d=$(case_dir "$r")
    rm -rf "$d/VTK" "$d/postProcessing"
    timed "gpu:$r" $S/logs/gpu-$r.log taskset -c 0-1 $S/build/bin/scree --case "$d" --device "${SCREE_GPU_DEVICE:-cuda}"
  done
}

cpu_queue() {
  for r in "$@"; do
    if [ "$r" = C-4w ]; then  # windows of the 1 mm case on the CPU: at rest, then flowing
      timed cpu:C-4w-rest-2000 $S/logs/cpu-C-4w-a.log taskset -c 2-15 $S/build/bin/scree \
        --case $S/cases/cpu4/columnCollapse --device cpu --threads 14 --no-output --max-steps 2000
      timed cpu:C-4w-to-14000 $S/logs/cpu-C-4w-b.log taskset -c 2-15 $S/build/bin/scree \
        --case $S/cases/cpu4/columnCollapse --device cpu --threads 14 --no-output --max-steps 14000
      continue
    fi
    d=$S/cases/cpu/columnCollapse/variants/$r
    rm -rf "$d/VTK" "$d/postProcessing"
    timed "cpu:$r" $S/logs/cpu-$r.log taskset -c 2-15 $S/build/bin/scree --case "$d" --device cpu --threads 14
  done
}

start() {
  local gpu=() cpu=() side=gpu
  for a in "$@"; do
    if [ "$a" = -- ]; then side=cpu; continue; fi
    if [ $side = gpu ]; then gpu+=("$a"); else cpu+=("$a"); fi
  done
  [ ${#gpu[@]} -eq 0 ] && [ "$side" = gpu ] && gpu=(pt frictional bench C-3 C-2 C-1)
  [ ${#cpu[@]} -eq 0 ] && [ "$side" = gpu ] && cpu=(C-1 C-2 C-3 C-4w)
  rm -rf $S && mkdir -p $S/logs $S/cases/cpu $S/cases/cpu4
  source .gpu-bundle/env.sh
  cp -r "${SCREE_BUILD_DIR:-build-cuda}" $S/build && cp -r .gpu-bundle/lib $S/lib
  cp -r cases/columnCollapse cases/flume $S/cases/
  # Lean snapshots: the fields of utilities/plot/column_collapse.py and the picture.
  sed -i -e '/fields *(velocity/,/);/c\        fields  (velocity displacement stress pressure volume mass plasticStrain shearViscosity granularTemperature collisionalFraction);\n        precision single;\n        compressionLevel 6;' \
    $S/cases/columnCollapse/system/controlDict
  cp -r $S/cases/columnCollapse $S/cases/cpu/ && cp -r $S/cases/columnCollapse $S/cases/cpu4/
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv > $S/device.txt
  lscpu | grep -E "Model name|^CPU\(s\)" >> $S/device.txt
  cat > $S/run.sh <<EOF
export LD_LIBRARY_PATH=$S/lib:\${LD_LIBRARY_PATH:-}
source $PWD/measure/gpu-column.sh
( gpu_queue ${gpu[*]}; echo gpu > $S/gpu.done ) &
( cpu_queue ${cpu[*]}; echo cpu > $S/cpu.done ) &
wait
EOF
  [ ${#cpu[@]} -eq 0 ] && echo cpu > $S/cpu.done
  setsid nohup bash $S/run.sh > $S/logs/session.log 2>&1 < /dev/null &
  echo "started: GPU ${gpu[*]}; CPU ${cpu[*]}"
  cat $S/device.txt
}

status() { gpu_status 28; }

pack() {  # pack RUN TIMES...: the run's snapshots at these times (release at 0.1 s)
  local r=$1 d pvd keep=() t f
  shift
  d=$(case_dir "$r")
  [ "${r%%-*}" = cpu ] && d=$S/cases/cpu/columnCollapse/variants/${r#cpu-}
  pvd=$d/VTK/particles.pvd
  if [ -f "$pvd" ]; then
    for t in "$@"; do
      f=$(grep -oE "timestep=\"$t[0-9]*\"[^>]*file=\"[^\"]+\"" "$pvd" | head -1 | sed -E 's/.*file="([^"]+)".*/\1/')
      [ -n "$f" ] && keep+=("$f")
    done
    { grep -v "<DataSet" "$pvd" | sed '/<\/Collection>/,$d'
      for f in "${keep[@]}"; do grep "file=\"$f\"" "$pvd"; done
      sed -n '/<\/Collection>/,$p' "$pvd"; } > "$d/VTK/selected.pvd"
  fi
  (cd "$d" && tar -czf - --transform "s,VTK/selected.pvd,VTK/particles.pvd," postProcessing $(printf 'VTK/%s ' "${keep[@]}") \
     $([ -f VTK/selected.pvd ] && echo VTK/selected.pvd)) > "$out/$r.tar.gz"
  # what comes back from the device is at most 16 MiB a file: cat $r.tar.gz.* | tar -xz
  if [ "$(stat -c %s "$out/$r.tar.gz")" -gt 15000000 ]; then
    split -b 15000000 "$out/$r.tar.gz" "$out/$r.tar.gz." && rm "$out/$r.tar.gz"
  fi
}

collect() {
  mkdir -p "$out"
  status > "$out/status.txt"
  cp $S/device.txt $S/walltimes.txt "$out/" 2>/dev/null
  [ -f $S/bench-gpu.csv ] && cp $S/bench-gpu.csv "$out/"
  (cd $S/logs && tar -czf "$out/logs.tar.gz" *.log)
  # phase transition: release and 0.05, 0.25, 0.5, 1 s after it (Figs. 10-12); frictional:
  # 0.5 s after the release and the end (Figs. 15-17)
  local figs=(0.1 0.15 0.35 0.6 1.1) r
  [ -d "$(case_dir pt)/postProcessing" ] && pack pt "${figs[@]}"
  [ -d "$(case_dir frictional)/postProcessing" ] && pack frictional 0.6 1.1
  for r in C-3 frictional-C-3; do  # the 2.5 mm pair, on either backend
    [ -d "$(case_dir $r)/VTK" ] && pack $r "${figs[@]}"
    [ -d "$S/cases/cpu/columnCollapse/variants/$r/VTK" ] && pack cpu-$r "${figs[@]}"
  done
  # the mesh study: postProcessing only (run-out, height, energy)
  tar -czf "$out/mesh.tar.gz" -C $S/cases columnCollapse/variants/C-1/postProcessing \
    columnCollapse/variants/C-2/postProcessing columnCollapse/variants/C-3/postProcessing \
    cpu/columnCollapse/variants/C-1/postProcessing cpu/columnCollapse/variants/C-2/postProcessing \
    cpu/columnCollapse/variants/C-3/postProcessing 2>/dev/null
  ls -la "$out"
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  cmd=${1:-status}
  shift || true
  case $cmd in
    start) start "$@" ;;
    status) status ;;
    wait)
      end=$(($(date +%s) + ${1:-500}))
      while [ "$(date +%s)" -lt $end ]; do
        if [ -f $S/gpu.done ] && [ -f $S/cpu.done ]; then break; fi
        sleep 30
      done
      status ;;
    collect) collect ;;
    *) echo "usage: $0 start|status|wait SECONDS|collect" >&2; exit 2 ;;
  esac
fi

#!/usr/bin/env bash
# The flume of Feng et al. 2025 (section 4.2) and its variants on a lent GPU machine, in the
# background, so that the runs outlast one device call; a run continues from its newest
# checkpoint on the next machine (scree --restart).
#
#   scripts/gpu-flume.sh start RUN...     launch (returns at once)
#   scripts/gpu-flume.sh status           progress of every run
#   scripts/gpu-flume.sh wait SECONDS     until every run is done or SECONDS have passed
#   scripts/gpu-flume.sh collect          $OUT/<label>.tar.gz per run (postProcessing/, the
#                                         frames at the paper's times, the last frame, the
#                                         newest checkpoint, the log), status and wall times
#
# RUN is LABEL=CASE[,endTime=T][,deltaT=DT][,cellSize=H][,tstep=W][,cpu]: CASE is `flume`
# (cases/flume) or a variant (`variants/frictional`, `variants/S-1`, ...); endTime, deltaT and
# cellSize replace the case's (cellSize=0.01 with variants/frictional: the frictional model at
# S-2's cells), tstep the sand's timeStepTemperature (current, steady); `cpu` runs it on two of the machine's
# CPU cores instead of the GPU. A run that the health checks stop (exit 5) without tstep=steady
# continues once from its newest checkpoint with it (<label>-steady). Examples:
#
#   pt=flume  frictional=variants/frictional  S-4=variants/S-4,endTime=0.85  S-1=variants/S-1,cpu
#
# The GPU runs share the GPU through MPS (a CUDA MPS daemon of this script's own, in /tmp),
# which lets the small kernels of several processes run side by side; without MPS the GPU
# time-slices between processes and two runs each ran 3x slower (gpu-column.sh). SCREE_MPS=0:
# no daemon, one GPU run after another instead.
#
# A lent machine goes back about 30 s after a call returns, and with it a background run: make
# the calls back to back (start + wait 540, wait 570, ..., collect) with nothing in between, and
# collect before the machine's 30 minutes are up.
#
# Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda). Carry between machines: here,
#   mkdir -p flume-carry/<label> && tar -xzf <files_at>/<label>.tar.gz -C flume-carry/<label>
# (flume-carry/ is ignored by git: name it in `carry`); a run whose flume-carry/<label>/ holds
# checkpoints continues from the newest. Snapshots are single precision with the fields of
# utilities/plot/flume.py.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/gpu-common.sh"
S=/tmp/scree-flume
out=${OUT:-$PWD/gpu-flume-out}
here=$PWD
fields="velocity displacement stress pressure volume plasticStrain shearViscosity granularTemperature collisionalFraction voidRatio"

# prepare LABEL SPEC: the run's own copy of cases/flume with its endTime/deltaT; prints the case directory
prepare() {
  local label=$1 spec=$2 c opt
  IFS=, read -r c opts <<< "$spec"
  local root=$S/runs/$label/flume
  mkdir -p "$S/runs/$label" && cp -r "$here/cases/flume" "$root"
  local dir=$root
  [ "$c" = flume ] || dir=$root/$c
  local cd=$root/system/controlDict
  sed -i -e "s|particles { type vtk; }|particles { type vtk; precision single; compressionLevel 6; fields ($fields); }|" "$cd"
  grep -q "precision single" "$cd" || { echo "$label: controlDict: writer not found" >&2; return 1; }
  for opt in ${opts//,/ }; do
    case $opt in
      endTime=*) sed -i -E "s|^endTime( +)[^;]*;|endTime\1${opt#endTime=};|" "$cd" ;;
      deltaT=*) sed -i -E "s|^deltaT( +)[^;]*;|deltaT\1${opt#deltaT=};|" "$cd" ;;
      tstep=*)  # the phaseTransition sand's timeStepTemperature (current, steady)
        sed -i -E "s|^( +)type( +)phaseTransition;|&\n\1timeStepTemperature ${opt#tstep=};|" \
          "$root/constant/materialProperties" ;;
      cellSize=*) printf '\n#inputMode overwrite\ncellSize %s;\n' "${opt#cellSize=}" >> "$dir/system/gridDict" ;;
      cpu) ;;
      *) echo "$label: unknown option '$opt'" >&2; return 1 ;;
    esac
  done
  echo "$dir"
}

# launch LABEL SPEC CORES: run it (restarting from flume-carry/LABEL when that holds checkpoints)
launch() {
  local label=$1 spec=$2 cores=$3 d dev=cuda args t0 rc
  d=$(prepare "$label" "$spec") || return 1
  [[ ",$spec," == *",cpu,"* ]] && dev=cpu
  args=(--case "$d" --device $dev)
  [ $dev = cpu ] && args+=(--threads 2)
  if [ -d "$here/flume-carry/$label/checkpoints" ]; then
    cp -r "$here/flume-carry/$label/." "$d/"
    args+=(--restart)
  fi
  echo "$d" > $S/logs/$label.dir
  local ts=(taskset -c "$cores")
  taskset -c "$cores" true 2> /dev/null || ts=()  # fewer cores than that here
  t0=$(date +%s.%N)
  "${ts[@]}" $S/build/bin/scree "${args[@]}" > $S/logs/$label.log 2>&1
  rc=$?
  local wall
  wall=$(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}")
  if [ $rc = 5 ] && [[ ",$spec," != *",tstep=steady,"* ]] && ls "$d"/checkpoints/*.ckpt > /dev/null 2>&1; then
    # stopped by the health checks: once more from the newest checkpoint, the step from the
    # steady temperature (kinetic_theory.hpp, step_temperature)
    echo "$label exit 5 wall $wall s: continued as $label-steady" >> $S/logs/retries.txt
    local d2
    d2=$(prepare "$label-steady" "$spec,tstep=steady") || return 1
    cp -r "$d/checkpoints" "$d/postProcessing" "$d/VTK" "$d2/"
    echo "$d2" > $S/logs/$label-steady.dir
    t0=$(date +%s.%N)
    "${ts[@]}" $S/build/bin/scree --case "$d2" --device $dev $([ $dev = cpu ] && echo --threads 2) --restart \
      > $S/logs/$label-steady.log 2>&1
    rc=$?
    wall="$wall + $(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}")"
  fi
  echo "$label exit $rc wall $wall s $dev ${args[*]:2}" >> $S/walltimes.txt
}

start() {
  [ $# -eq 0 ] && set -- pt=flume
  rm -rf $S && mkdir -p $S/logs $S/runs
  source .gpu-bundle/env.sh
  cp -r "${SCREE_BUILD_DIR:-build-cuda}" $S/build && cp -r .gpu-bundle/lib $S/lib
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv > $S/device.txt
  export LD_LIBRARY_PATH=$S/lib:${LD_LIBRARY_PATH:-}
  local mps=1
  mps_start >> $S/device.txt || mps=0
  local r core=0 gpu=()
  for r in "$@"; do
    local label=${r%%=*} spec=${r#*=}
    if [[ ",$spec," == *",cpu,"* ]]; then
      (launch "$label" "$spec" "$((2 + core * 2))-$((3 + core * 2))") > $S/logs/session-$label.log 2>&1 < /dev/null &
      core=$((core + 1))
    elif [ "$mps" = 1 ]; then
      # two cores of its own: a GPU run's host loop launches its kernels and must not wait
      # for a core (seven runs pinned to the same two cores ran at ~50 steps/s each)
      (launch "$label" "$spec" "$((2 + core * 2))-$((3 + core * 2))") > $S/logs/session-$label.log 2>&1 < /dev/null &
      core=$((core + 1))
    else
      gpu+=("$label=$spec")
    fi
  done
  if [ ${#gpu[@]} -gt 0 ]; then
    (for r in "${gpu[@]}"; do launch "${r%%=*}" "${r#*=}" 0-1; done) > $S/logs/session-gpu.log 2>&1 < /dev/null &
  fi
  echo $# > $S/runs.count  # `wait` ends when walltimes.txt has a line for each
  disown -a
  echo "started: $*"
  cat $S/device.txt
}

status() { gpu_status 16; }

collect() {
  mkdir -p "$out"
  status > $S/status.txt
  # at most 8 files come back from a call: the notes in one, a tarball per run
  (cd $S && tar -czf "$out/meta.tar.gz" status.txt device.txt walltimes.txt $(cd $S && ls logs/retries.txt logs/mps.err 2> /dev/null))
  cat $S/status.txt
  local f label d keep t newest
  for f in $S/logs/*.dir; do
    [ -f "$f" ] || continue
    label=$(basename "$f" .dir)
    d=$(cat "$f")
    [ -d "$d/postProcessing" ] || continue
    keep=()
    # the frames at the paper's times for the figures' runs (pt*, frictional*), the last frame of every run
    [[ $label == pt* || $label == frictional* ]] &&
    for t in 0 0.05 0.15 0.45 0.85 1.05 1.55 2.05 2.55 3.05; do  # t = 0, the release, then 0.1 0.4 0.8 ... 3 s
      f=$(grep -oE "timestep=\"$t[0-9]*\"[^>]*file=\"[^\"]+\"" "$d/VTK/particles.pvd" 2>/dev/null | head -1 |
        sed -E 's/.*file="([^"]+)".*/\1/')
      [ -n "$f" ] && [ -f "$d/VTK/$f" ] && keep+=("VTK/$f")
    done
    # the newest checkpoint of an unfinished run (to continue it), and the last frame (a
    # failed run's state, for the diagnosis)
    newest=
    grep -q "scree: done" $S/logs/$label.log 2> /dev/null ||
      newest=$(cd "$d" && ls checkpoints/*.ckpt 2>/dev/null | sort -t/ -k2 -g | tail -1)
    f=$(grep -oE 'file="[^"]+"' "$d/VTK/particles.pvd" 2>/dev/null | tail -1 | sed -E 's/file="([^"]+)"/\1/')
    [ -n "$f" ] && [ -f "$d/VTK/$f" ] && keep+=("VTK/$f")
    cp $S/logs/$label.log "$d/run.log"
    # the stages' times (the release) for the figures: the main case's file, whose variants
    # only include it
    mkdir -p "$d/collected/system" && cp "$S/runs/$label/flume/system/stages" "$d/collected/system/stages"
    (cd "$d" && tar -czf - run.log postProcessing VTK/particles.pvd $(printf '%s\n' "${keep[@]}" | sort -u) $newest \
      -C collected system/stages) > "$out/$label.tar.gz"
  done
  ls -la "$out"
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  cmd=${1:-status}
  shift || true
  case $cmd in
    start) setsid bash "$0" _start "$@" ;;
    _start) start "$@" ;;
    status) status ;;
    wait)
      end=$(($(date +%s) + ${1:-500}))
      while [ "$(date +%s)" -lt $end ] &&
        [ "$(cat $S/walltimes.txt 2>/dev/null | wc -l)" -lt "$(cat $S/runs.count 2>/dev/null || echo 0)" ]; do
        sleep 15
      done
      status ;;
    collect) collect ;;
    *) echo "usage: $0 start LABEL=CASE[,endTime=T][,deltaT=DT][,cellSize=H][,tstep=W][,cpu]...|status|wait SECONDS|collect" >&2; exit 2 ;;
  esac
fi

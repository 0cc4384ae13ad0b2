#!/usr/bin/env bash
# Any cases (or their variants) on a lent GPU machine, side by side in the background, so
# that a series outlasts one device call; a run continues from its newest checkpoint on the
# next machine (scree --restart). gpu-flume.sh is the flume's own version of this (with the
# paper's frames and the health-check retry); this one takes any case under cases/.
#
#   bash scripts/gpu-runs.sh start RUN...     launch (returns at once)
#   bash scripts/gpu-runs.sh status           progress of every run
#   bash scripts/gpu-runs.sh wait SECONDS     until every run is done or SECONDS have passed
#   bash scripts/gpu-runs.sh collect          $OUT/<label>.tar.gz per run (postProcessing/, the
#                                             log, the .pvd; the last frame with `frame`; the
#                                             newest checkpoint of an unfinished run) and
#                                             $OUT/meta.tar.gz (device, wall times, status)
#
# RUN is LABEL=CASE[,endTime=T][,deltaT=DT][,cellSize=H][,frame][,cpu]: CASE a case directory
# relative to the repository (cases/axisymmetricCollapse/variants/a4); endTime, deltaT and
# cellSize replace the case's; `frame` brings back the last VTK frame; `cpu` runs it on two of
# the machine's CPU cores. Each run gets its own copy of cases/ (cases include their
# neighbours' files: a material, the stages). At most 7 runs: 8 files come back from a call.
#
# Run other CUDA programs (ctest -L gpu, scree-bench) before `start` or after the runs end:
# `ctest -L gpu` started beside the runs (outside the MPS daemon's pipe directory) made no
# progress past its first test in 595 s.
#
# Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda). Carry between machines: here,
#   mkdir -p gpu-carry/<label> && tar -xzf <files_at>/<label>.tar.gz -C gpu-carry/<label>
# (gpu-carry/ is ignored by git: name it in `carry`); a run whose gpu-carry/<label>/ holds
# checkpoints continues from the newest. A lent machine goes back about 30 s after a call
# returns, and with it a background run: make the calls back to back.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/gpu-common.sh"
S=/tmp/scree-runs
out=${OUT:-$PWD/gpu-runs-out}
here=$PWD

# prepare LABEL SPEC: the run's own copy of cases/ with its options; prints the case directory
prepare() {
  local label=$1 spec=$2 c opts opt
  IFS=, read -r c opts <<< "$spec"
  [ -d "$here/$c/system" ] || { echo "$label: no case at $c" >&2; return 1; }
  mkdir -p "$S/runs/$label" && cp -r "$here/cases" "$S/runs/$label/cases" && rm -rf "$S/runs/$label"/cases/*/figures
  local dir=$S/runs/$label/$c
  for opt in ${opts//,/ }; do
    case $opt in
      endTime=* | deltaT=*) printf '\n#inputMode overwrite\n%s %s;\n' "${opt%%=*}" "${opt#*=}" >> "$dir/system/controlDict" ;;
      cellSize=*) printf '\n#inputMode overwrite\ncellSize %s;\n' "${opt#cellSize=}" >> "$dir/system/gridDict" ;;
      frame | cpu) ;;
      *) echo "$label: unknown option '$opt'" >&2; return 1 ;;
    esac
  done
  echo "$dir"
}

# launch LABEL SPEC CORES: run it (restarting from gpu-carry/LABEL when that holds checkpoints)
launch() {
  local label=$1 spec=$2 cores=$3 d dev=cuda args t0 rc wall
  d=$(prepare "$label" "$spec") || { echo "$label exit prepare-failed" >> $S/walltimes.txt; return 1; }
  [[ ",$spec," == *",cpu,"* ]] && dev=cpu
  args=(--case "$d" --device $dev)
  [ $dev = cpu ] && args+=(--threads 2)
  if [ -d "$here/gpu-carry/$label/checkpoints" ]; then
    cp -r "$here/gpu-carry/$label/." "$d/"
    args+=(--restart)
  fi
  echo "$d" > $S/logs/$label.dir
  local ts=(taskset -c "$cores")
  taskset -c "$cores" true 2> /dev/null || ts=()
  t0=$(date +%s.%N)
  "${ts[@]}" $S/build/bin/scree "${args[@]}" > $S/logs/$label.log 2>&1
  rc=$?
  wall=$(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}")
  echo "$label exit $rc wall $wall s $dev ${args[*]:2}" >> $S/walltimes.txt
}

start() {
  [ $# -gt 0 ] || { echo "gpu-runs.sh start: no runs given" >&2; exit 2; }
  [ $# -le 7 ] || { echo "gpu-runs.sh start: at most 7 runs (8 files come back from a call)" >&2; exit 2; }
  rm -rf $S && mkdir -p $S/logs $S/runs
  source .gpu-bundle/env.sh
  cp -r "${SCREE_BUILD_DIR:-build-cuda}" $S/build && cp -r .gpu-bundle/lib $S/lib
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv > $S/device.txt 2>&1
  export LD_LIBRARY_PATH=$S/lib:${LD_LIBRARY_PATH:-}
  local mps=1 r core=0 gpu=()
  mps_start >> $S/device.txt || mps=0
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
  echo $# > $S/runs.count
  printf '%s\n' "$@" > $S/runs.txt
  disown -a
  echo "started: $*"
  cat $S/device.txt
}

status() { gpu_status 16; }

collect() {
  mkdir -p "$out"
  status > $S/status.txt
  (cd $S && tar -czf "$out/meta.tar.gz" status.txt device.txt runs.txt $(cd $S && ls walltimes.txt logs/mps.err 2> /dev/null))
  cat $S/status.txt
  local f label d keep spec newest
  for f in $S/logs/*.dir; do
    [ -f "$f" ] || continue
    label=$(basename "$f" .dir)
    d=$(cat "$f")
    spec=$(grep -E "^$label=" $S/runs.txt | head -1)
    keep=()
    if [[ ",$spec," == *",frame,"* ]]; then
      f=$(grep -oE 'file="[^"]+"' "$d/VTK/particles.pvd" 2>/dev/null | tail -1 | sed -E 's/file="([^"]+)"/\1/')
      [ -n "$f" ] && [ -f "$d/VTK/$f" ] && keep+=("VTK/$f")
    fi
    newest=
    grep -q "scree: done" $S/logs/$label.log 2> /dev/null ||
      newest=$(cd "$d" && ls checkpoints/*.ckpt 2>/dev/null | sort -t/ -k2 -g | tail -1)
    cp $S/logs/$label.log "$d/run.log"
    (cd "$d" && tar -czf - run.log $(ls -d postProcessing VTK/particles.pvd 2> /dev/null) "${keep[@]}" $newest) \
      > "$out/$label.tar.gz"
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
        sleep 10
      done
      status ;;
    collect) collect ;;
    *) echo "usage: $0 start LABEL=CASE[,endTime=T][,deltaT=DT][,cellSize=H][,frame][,cpu]...|status|wait SECONDS|collect" >&2; exit 2 ;;
  esac
fi

#!/usr/bin/env bash
# The flume of Feng et al. 2025 (section 4.2) and its variants on a lent GPU machine, in the
# background, so that the runs outlast one device call; a run continues from its newest
# checkpoint on the next machine (scree --restart).
#
#   measure/gpu-flume.sh start RUN...     launch (returns at once)
#   measure/gpu-flume.sh status           progress of every run
#   measure/gpu-flume.sh wait SECONDS     until every run is done or SECONDS have passed
#   measure/gpu-flume.sh collect          $OUT/<label>.tar.gz per run (postProcessing/, the
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
# time-slices between processes, which run one at a time. SCREE_MPS=0:
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
  local label=$1 spec=$2 cores=$3 d rc wall dev=cuda
  d=$(prepare "$label" "$spec") || return 1
  [[ ",$spec," == *",cpu,"* ]] && dev=cpu
  gpu_scree "$label" "$d" "$spec" "$cores" "$here/flume-carry"
  rc=$GPU_RC wall=$GPU_WALL
  if [ $rc = 5 ] && [[ ",$spec," != *",tstep=steady,"* ]] && ls "$d"/checkpoints/*.ckpt > /dev/null 2>&1; then
    # stopped by the health checks: once more from the newest checkpoint, the step from the
    # steady temperature (kinetic_theory.hpp, step_temperature)
    echo "$label exit 5 wall $wall s: continued as $label-steady" >> $S/logs/retries.txt
    local d2
    d2=$(prepare "$label-steady" "$spec,tstep=steady") || return 1
    cp -r "$d/checkpoints" "$d/postProcessing" "$d/VTK" "$d2/"
    gpu_scree "$label-steady" "$d2" "$spec" "$cores" /nonexistent --restart
    rc=$GPU_RC wall="$wall + $GPU_WALL"
  fi
  echo "$label exit $rc wall $wall s $dev ${GPU_ARGS[*]:2}" >> $S/walltimes.txt
}

start() {
  [ $# -eq 0 ] && set -- pt=flume
  gpu_prepare_machine
  gpu_launch_all "$@"
}

# collect_one LABEL DIR: $out/LABEL.tar.gz
collect_one() {
  local label=$1 d=$2 f t newest keep=()
  [ -d "$d/postProcessing" ] || return 0
  # the frames at the paper's times for the figures' runs (pt*, frictional*), the last frame of every run
  # (t = 0, the release, then 0.1 0.4 0.8 ... 3 s after it)
  [[ $label == pt* || $label == frictional* ]] &&
    keep+=($(gpu_frames_near "$d" 0 0.05 0.15 0.45 0.85 1.05 1.55 2.05 2.55 3.05))
  # the newest checkpoint of an unfinished run (to continue it), and the last frame (a
  # failed run's state, for the diagnosis)
  newest=$(gpu_newest_checkpoint "$label" "$d")
  f=$(gpu_last_frame "$d") && keep+=("$f")
  cp $S/logs/$label.log "$d/run.log"
  # the stages' times (the release) for the figures: the main case's file, whose variants
  # only include it
  mkdir -p "$d/collected/system" && cp "$S/runs/$label/flume/system/stages" "$d/collected/system/stages"
  (cd "$d" && tar -czf - run.log postProcessing VTK/particles.pvd $(printf '%s\n' "${keep[@]}" | sort -u) $newest \
    -C collected system/stages) > "$out/$label.tar.gz"
}

collect() {
  gpu_collect_meta
  gpu_collect_each collect_one
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  gpu_main "start LABEL=CASE[,endTime=T][,deltaT=DT][,cellSize=H][,tstep=W][,cpu]...|status|wait SECONDS|collect" "$@"
fi

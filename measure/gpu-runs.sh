#!/usr/bin/env bash
# Any cases (or their variants) on a lent GPU machine, side by side in the background, so
# that a series outlasts one device call; a run continues from its newest checkpoint on the
# next machine (scree --restart). gpu-flume.sh is the flume's own version of this (with the
# paper's frames and the health-check retry); this one takes any case under cases/.
#
#   bash measure/gpu-runs.sh start RUN...     launch (returns at once)
#   bash measure/gpu-runs.sh status           progress of every run
#   bash measure/gpu-runs.sh wait SECONDS     until every run is done or SECONDS have passed
#   bash measure/gpu-runs.sh collect          $OUT/<label>.tar.gz per run (postProcessing/, the
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
  local label=$1 spec=$2 cores=$3 d
  d=$(prepare "$label" "$spec") || { echo "$label exit prepare-failed" >> $S/walltimes.txt; return 1; }
  gpu_scree "$label" "$d" "$spec" "$cores" "$here/gpu-carry"
  echo "$label exit $GPU_RC wall $GPU_WALL s ${GPU_ARGS[*]:2}" >> $S/walltimes.txt
}

start() {
  [ $# -gt 0 ] || { echo "gpu-runs.sh start: no runs given" >&2; exit 2; }
  [ $# -le 7 ] || { echo "gpu-runs.sh start: at most 7 runs (8 files come back from a call)" >&2; exit 2; }
  gpu_prepare_machine
  gpu_launch_all "$@"
}

# collect_one LABEL DIR: $out/LABEL.tar.gz
collect_one() {
  local label=$1 d=$2 f spec newest keep=()
  spec=$(grep -E "^$label=" $S/runs.txt | head -1)
  [[ ",$spec," == *",frame,"* ]] && f=$(gpu_last_frame "$d") && keep+=("$f")
  newest=$(gpu_newest_checkpoint "$label" "$d")
  cp $S/logs/$label.log "$d/run.log"
  (cd "$d" && tar -czf - run.log $(ls -d postProcessing VTK/particles.pvd 2> /dev/null) "${keep[@]}" $newest) \
    > "$out/$label.tar.gz"
}

collect() {
  gpu_collect_meta
  gpu_collect_each collect_one
}

if [ "${BASH_SOURCE[0]}" = "$0" ]; then
  gpu_main "start LABEL=CASE[,endTime=T][,deltaT=DT][,cellSize=H][,frame][,cpu]...|status|wait SECONDS|collect" "$@"
fi

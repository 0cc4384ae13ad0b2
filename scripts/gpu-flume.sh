#!/usr/bin/env bash
# The flume of Feng et al. 2025 (section 4.2) to its end on lent GPU machines: a run of about
# half an hour, longer than one device call and than one machine is held, continued from its
# newest checkpoint on the next machine (scree --restart).
#
#   scripts/gpu-flume.sh start [RUN...]    launch in the background (returns at once); RUN: pt
#                                          (cases/flume), frictional (variants/frictional); one
#                                          after another. A run whose carried state is in
#                                          flume-carry/<run>/ (an earlier `collect`) continues
#                                          from its newest checkpoint.
#   scripts/gpu-flume.sh status            progress
#   scripts/gpu-flume.sh wait SECONDS      until every run is done or SECONDS have passed
#   scripts/gpu-flume.sh collect           $OUT/<run>.tar.gz: postProcessing/, the newest
#                                          checkpoint, VTK/particles.pvd and the frames at the
#                                          paper's times; logs and wall times
#
# A lent machine goes back about 30 s after a call returns, and with it a background run: make
# the calls back to back (start + wait 570, wait 570, ..., collect) with nothing in between, and
# collect before the machine's 30 minutes are up.
#
# Needs .gpu-bundle (../shared/gpu/bundle.sh build-cuda). Carry between machines: here,
#   mkdir -p flume-carry/pt && tar -xzf <files_at>/pt.tar.gz -C flume-carry/pt
# (flume-carry/ is ignored by git: name it in `carry`). Snapshots are single precision with
# the fields of utilities/plot/flume.py.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/gpu-common.sh"
S=/tmp/scree-flume
out=${OUT:-$PWD/gpu-flume-out}
here=$PWD

case_dir() {
  case $1 in
    pt) echo $S/cases/flume ;;
    frictional) echo $S/cases/flume/variants/frictional ;;
    *) echo "unknown run '$1' (pt, frictional)" >&2; return 1 ;;
  esac
}

queue() {
  local r d args t0 rc
  for r in "$@"; do
    d=$(case_dir "$r") || continue
    args=(--case "$d" --device cuda)
    if [ -d "$here/flume-carry/$r/checkpoints" ]; then
      cp -r "$here/flume-carry/$r/." "$d/"
      args+=(--restart)
    fi
    t0=$(date +%s.%N)
    taskset -c 0-1 $S/build/bin/scree "${args[@]}" > $S/logs/$r.log 2>&1
    rc=$?
    echo "$r exit $rc wall $(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}") s ${args[*]: -1}" >> $S/walltimes.txt
  done
  echo done > $S/queue.done
}

start() {
  [ $# -eq 0 ] && set -- pt
  rm -rf $S && mkdir -p $S/logs $S/cases
  source .gpu-bundle/env.sh
  cp -r "${SCREE_BUILD_DIR:-build-cuda}" $S/build && cp -r .gpu-bundle/lib $S/lib
  cp -r cases/flume $S/cases/
  sed -i -e 's|particles { type vtk; }|particles { type vtk; precision single; compressionLevel 6; fields (velocity displacement stress pressure volume plasticStrain shearViscosity granularTemperature collisionalFraction); }|' \
    $S/cases/flume/system/controlDict
  grep -q "precision single" $S/cases/flume/system/controlDict || { echo "controlDict: writer not found" >&2; exit 1; }
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv > $S/device.txt
  export LD_LIBRARY_PATH=$S/lib:${LD_LIBRARY_PATH:-}
  (queue "$@") > $S/logs/session.log 2>&1 < /dev/null &
  disown
  echo "started: $*"
  cat $S/device.txt
}

status() { gpu_status 16; }

collect() {
  mkdir -p "$out"
  status > "$out/status.txt"
  cp $S/device.txt $S/walltimes.txt "$out/" 2>/dev/null
  (cd $S/logs && tar -czf "$out/logs.tar.gz" *.log)
  local r d keep t f newest
  for r in pt frictional; do
    d=$(case_dir $r)
    [ -d "$d/postProcessing" ] || continue
    keep=()
    for t in 0 0.05 0.15 0.45 0.85 1.05 1.55 2.05 2.55 3.05; do  # t = 0, the release, then 0.1 0.4 0.8 ... 3 s
      f=$(grep -oE "timestep=\"$t[0-9]*\"[^>]*file=\"[^\"]+\"" "$d/VTK/particles.pvd" 2>/dev/null | head -1 |
        sed -E 's/.*file="([^"]+)".*/\1/')
      [ -n "$f" ] && [ -f "$d/VTK/$f" ] && keep+=("VTK/$f")
    done
    # the newest checkpoint, and the last frame (a failed run's state, for the diagnosis)
    newest=$(cd "$d" && ls checkpoints/*.ckpt 2>/dev/null | sort -t/ -k2 -g | tail -1)
    f=$(grep -oE 'file="[^"]+"' "$d/VTK/particles.pvd" 2>/dev/null | tail -1 | sed -E 's/file="([^"]+)"/\1/')
    [ -n "$f" ] && [ -f "$d/VTK/$f" ] && keep+=("VTK/$f")
    (cd "$d" && tar -czf - postProcessing VTK/particles.pvd $(printf '%s\n' "${keep[@]}" | sort -u) $newest) > "$out/$r.tar.gz"
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
      while [ "$(date +%s)" -lt $end ] && [ ! -f $S/queue.done ]; do sleep 20; done
      status ;;
    collect) collect ;;
    *) echo "usage: $0 start [pt|frictional]...|status|wait SECONDS|collect" >&2; exit 2 ;;
  esac
fi

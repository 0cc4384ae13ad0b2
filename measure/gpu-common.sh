# Shared by measure/gpu-column.sh and measure/gpu-flume.sh (sourced by both).
#
# gpu_status WIDTH: the time, the newest progress line of each log in $S/logs (names padded to
# WIDTH), then $S/walltimes.txt (one line per finished run).
gpu_status() {
  echo "---- $(date +%T)"
  for f in $S/logs/*.log; do
    [ -s "$f" ] || continue
    printf "%-${1}s %s\n" "$(basename "$f")" "$(tail -c 400 "$f" | tr '\r' '\n' | grep -v '^$' | tail -1 | cut -c1-110)"
  done
  cat $S/walltimes.txt 2>/dev/null
}

# mps_start: a CUDA MPS daemon of the script's own (pipes and logs under $S), so that the
# small kernels of several runs share the GPU side by side instead of time-slicing. Prints whether it started; returns 1 when
# MPS is not available (then run one GPU run after another). SCREE_MPS=0: no daemon.
mps_start() {
  [ "${SCREE_MPS:-1}" = 1 ] || return 1
  export CUDA_MPS_PIPE_DIRECTORY=$S/mps-pipe CUDA_MPS_LOG_DIRECTORY=$S/mps-log
  mkdir -p $CUDA_MPS_PIPE_DIRECTORY $CUDA_MPS_LOG_DIRECTORY
  if nvidia-cuda-mps-control -d 2> $S/logs/mps.err; then echo "MPS daemon started"; return 0; fi
  echo "MPS not available: one GPU run after another"
  return 1
}

# gpu_prepare_machine: a fresh $S with the bundle's build and libraries, the device's name,
# the MPS daemon (GPU_MPS=1 when it runs). Call from the working tree's root.
gpu_prepare_machine() {
  rm -rf $S && mkdir -p $S/logs $S/runs
  source .gpu-bundle/env.sh
  cp -r "${SCREE_BUILD_DIR:-build-cuda}" $S/build && cp -r .gpu-bundle/lib $S/lib
  nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv > $S/device.txt 2>&1
  export LD_LIBRARY_PATH=$S/lib:${LD_LIBRARY_PATH:-}
  GPU_MPS=1
  mps_start >> $S/device.txt || GPU_MPS=0
}

# gpu_launch_all RUN...: each LABEL=SPEC through the script's own `launch LABEL SPEC CORES`,
# in the background. Every run gets two cores of its own: a GPU run's host loop launches its
# kernels and should not wait for a core (runs that share cores wait for each other's
# launches). Without MPS the GPU runs go one after another. `wait`
# ends when $S/walltimes.txt has a line for each run.
gpu_launch_all() {
  local r core=0 gpu=()
  for r in "$@"; do
    local label=${r%%=*} spec=${r#*=}
    if [[ ",$spec," == *",cpu,"* ]] || [ "$GPU_MPS" = 1 ]; then
      (launch "$label" "$spec" "$((2 + core * 2))-$((3 + core * 2))") > $S/logs/session-$label.log 2>&1 < /dev/null &
      core=$((core + 1))
    else
      gpu+=("$label=$spec")
    fi
  done
  if [ ${#gpu[@]} -gt 0 ]; then
    (for r in "${gpu[@]}"; do launch "${r%%=*}" "${r#*=}" 2-3; done) > $S/logs/session-gpu.log 2>&1 < /dev/null &
  fi
  echo $# > $S/runs.count
  printf '%s\n' "$@" > $S/runs.txt
  disown -a
  echo "started: $*"
  cat $S/device.txt
}

# gpu_newest_checkpoint LABEL DIR: the newest checkpoint of a run that did not finish (to
# continue it on the next machine), nothing for a finished one
gpu_newest_checkpoint() {
  grep -q "scree: done" $S/logs/$1.log 2> /dev/null ||
    (cd "$2" && ls checkpoints/*.ckpt 2>/dev/null | sort -t/ -k2 -g | tail -1)
}

# gpu_last_frame DIR: the newest VTK frame of a run (relative to DIR), if any
gpu_last_frame() {
  local f
  f=$(grep -oE 'file="[^"]+"' "$1/VTK/particles.pvd" 2>/dev/null | tail -1 | sed -E 's/file="([^"]+)"/\1/')
  [ -n "$f" ] && [ -f "$1/VTK/$f" ] && echo "VTK/$f"
}

# gpu_frames_near DIR T...: the VTK frames of a run (relative to DIR) nearest to each time T,
# within 1e-6 s (the writer's times are sums of steps: 3.04999999999996 for 3.05)
gpu_frames_near() {
  local d=$1
  shift
  [ -f "$d/VTK/particles.pvd" ] || return 0
  grep -oE 'timestep="[^"]+"[^>]*file="[^"]+"' "$d/VTK/particles.pvd" |
    sed -E 's/timestep="([^"]+)".*file="([^"]+)"/\1 \2/' |
    awk -v want="$*" 'BEGIN { n = split(want, w, " ") }
      { for (i = 1; i <= n; i++) { e = $1 - w[i]; if (e < 0) e = -e; if (e < 1e-6) print "VTK/" $2 } }' |
    sort -u | while read -r f; do [ -f "$d/$f" ] && echo "$f"; done
}

# gpu_main USAGE CMD [ARGS]: the scripts' commands (start, status, wait SECONDS, collect);
# the script defines start (after gpu_prepare_machine) and collect
gpu_main() {
  local usage=$1 cmd=${2:-status} end
  shift 2 || shift $#
  case $cmd in
    start) setsid bash "$0" _start "$@" ;;
    _start) start "$@" ;;
    status) gpu_status 16 ;;
    wait)
      end=$(($(date +%s) + ${1:-500}))
      while [ "$(date +%s)" -lt $end ] &&
        [ "$(cat $S/walltimes.txt 2>/dev/null | wc -l)" -lt "$(cat $S/runs.count 2>/dev/null || echo 0)" ]; do
        sleep 10
      done
      gpu_status 16 ;;
    collect) collect ;;
    *) echo "usage: $0 $usage" >&2; exit 2 ;;
  esac
}

# gpu_scree LABEL DIR SPEC CORES CARRY [EXTRA...]: run scree on the case DIR (on the GPU, or on
# the CPU's two cores when SPEC has `cpu`), restarting from CARRY/LABEL when that holds
# checkpoints; its log is $S/logs/LABEL.log. Sets GPU_RC, GPU_WALL (s) and GPU_ARGS.
gpu_scree() {
  local label=$1 d=$2 spec=$3 cores=$4 carry=$5 dev=cuda t0
  shift 5
  [[ ",$spec," == *",cpu,"* ]] && dev=cpu
  GPU_ARGS=(--case "$d" --device $dev "$@")
  [ $dev = cpu ] && GPU_ARGS+=(--threads 2)
  if [ -d "$carry/$label/checkpoints" ]; then
    cp -r "$carry/$label/." "$d/"
    GPU_ARGS+=(--restart)
  fi
  echo "$d" > $S/logs/$label.dir
  local ts=(taskset -c "$cores")
  taskset -c "$cores" true 2> /dev/null || ts=()  # fewer cores than that here
  t0=$(date +%s.%N)
  "${ts[@]}" $S/build/bin/scree "${GPU_ARGS[@]}" > $S/logs/$label.log 2>&1
  GPU_RC=$?
  GPU_WALL=$(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $t0}")
}

# gpu_collect_meta: $out/meta.tar.gz (status, device, runs, wall times, retries, MPS errors;
# at most 8 files come back from a call: this one and a tarball per run) and the status
gpu_collect_meta() {
  mkdir -p "$out"
  gpu_status 16 > $S/status.txt
  (cd $S && tar -czf "$out/meta.tar.gz" status.txt device.txt $(ls runs.txt walltimes.txt logs/retries.txt logs/mps.err 2> /dev/null))
  cat $S/status.txt
}

# gpu_collect_each FUNC: FUNC LABEL DIR for every run launched (its case directory DIR)
gpu_collect_each() {
  local f
  for f in $S/logs/*.dir; do
    [ -f "$f" ] || continue
    "$1" "$(basename "$f" .dir)" "$(cat "$f")"
  done
  ls -la "$out"
}

# Shared by scripts/gpu-column.sh and scripts/gpu-flume.sh (sourced by both).
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
# small kernels of several runs share the GPU side by side instead of time-slicing (two runs
# each ran 3x slower without it: gpu-column.sh). Prints whether it started; returns 1 when
# MPS is not available (then run one GPU run after another). SCREE_MPS=0: no daemon.
mps_start() {
  [ "${SCREE_MPS:-1}" = 1 ] || return 1
  export CUDA_MPS_PIPE_DIRECTORY=$S/mps-pipe CUDA_MPS_LOG_DIRECTORY=$S/mps-log
  mkdir -p $CUDA_MPS_PIPE_DIRECTORY $CUDA_MPS_LOG_DIRECTORY
  if nvidia-cuda-mps-control -d 2> $S/logs/mps.err; then echo "MPS daemon started"; return 0; fi
  echo "MPS not available: one GPU run after another"
  return 1
}

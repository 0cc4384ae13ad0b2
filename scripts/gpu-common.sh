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

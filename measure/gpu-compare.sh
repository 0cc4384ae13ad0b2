#!/usr/bin/env bash
# Time two builds of Scree side by side on one GPU, in one device call (GPU timings drift
# between machines and sessions, so a before/after pair must share a machine):
#
#   measure/gpu-compare.sh BASE_BIN NEW_BIN OUT_DIR [ROUNDS]
#
# BASE_BIN and NEW_BIN are bin/ directories holding scree-bench (with their lib/ beside).
# Each round runs the paper cases (the column collapse and the flume: at rest, right after
# the release and late in the flow) and the 1e6 and 1e7 blocks of both materials, first
# with one build and then the other, alternating which goes first; the CSVs land in
# OUT_DIR/<round>-<base|new>-<cases>.csv and a summary of the ratios in OUT_DIR/summary.txt.
set -euo pipefail
base=$1; new=$2; out=$3; rounds=${4:-2}
repo=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
run() {  # label bin cases-label args...
  local label=$1 bin=$2 what=$3; shift 3
  "$bin/scree-bench" --device cuda --source-dir "$repo" --csv "$out/$label-$what.csv" --json "$out/$label-$what.json" \
    "$@" > "$out/$label-$what.log" 2>&1 || { echo "gpu-compare: $label $what failed"; tail -20 "$out/$label-$what.log"; }
}
for r in $(seq 1 "$rounds"); do
  order=(base new); [ $((r % 2)) -eq 0 ] && order=(new base)
  for who in "${order[@]}"; do
    bin=$base; [ "$who" = new ] && bin=$new
    run "$r-$who" "$bin" paper --cases column,flume
    run "$r-$who" "$bin" blocks --cases scaling --materials linearElastic,phaseTransition --shapes linear \
      --schemes USL --steps 500 --max-particles 10000000
  done
done
/usr/bin/env python3 - "$out" "$rounds" <<'PY' > "$out/summary.txt" || true
import csv, sys, glob, collections
out, rounds = sys.argv[1], int(sys.argv[2])
rows = collections.defaultdict(lambda: collections.defaultdict(list))
for f in glob.glob(f"{out}/*-*.csv"):
    who = f.split("/")[-1].split("-")[1]
    for r in csv.DictReader(open(f)):
        key = (r.get("case", ""), r.get("material", ""), r.get("particles", ""), r.get("kernels", ""))
        try:
            rows[key][who].append(float(r["ms_per_step"]))
        except (KeyError, ValueError):
            pass
print(f"{'case':40s} {'material':16s} {'points':>10s} {'base ms':>10s} {'new ms':>10s} {'new/base':>9s}")
for key in sorted(rows):
    b, n = rows[key].get("base", []), rows[key].get("new", [])
    if b and n:
        mb, mn = min(b), min(n)
        print(f"{key[0][:40]:40s} {key[1][:16]:16s} {key[2]:>10s} {mb:10.4f} {mn:10.4f} {mn / mb:9.3f}")
PY
cat "$out/summary.txt"

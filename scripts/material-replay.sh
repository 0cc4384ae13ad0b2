#!/usr/bin/env bash
# Bit-for-bit comparison of the granular material models between two versions of their
# headers, independent of the MPM solver: the same random stress updates (initial state,
# update, update_elastic, wave speed, every output field; scripts/material-replay.cpp) are
# compiled against the headers of OLD_REV and of the working tree and their results
# compared. Identical bits print "identical"; otherwise the largest relative difference.
#
#   scripts/material-replay.sh BUILD_DIR OLD_REV        # e.g. build main
#
# A complement to reference-outputs.sh for refactors of the models: a flow such as the
# column collapse C-2 is not reproducible bit for bit from run to run on the CPU, so whole
# runs cannot show that a model's arithmetic is unchanged. Links the dictionary and spec
# code of BUILD_DIR's libscree for both versions (their ABI must not differ). CPU, about a
# minute.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$1" && pwd)
old=$2
work=$(mktemp -d /tmp/scree-replay-XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/old"
git -C "$repo" archive "$old" materials framework/include | tar -x -C "$work/old"
eigen=$(pkg-config --cflags-only-I eigen3 2>/dev/null || echo -I/usr/include/eigen3)
for side in old new; do
  src=$work/old
  [ "$side" = new ] && src=$repo
  # materials/common/include: where the shared model headers live since they were split out
  g++ -O3 -DNDEBUG -std=c++20 -fopenmp $eigen -I"$src/framework/include" -I"$src/materials" \
      -I"$src/materials/common/include" "$repo/scripts/material-replay.cpp" -L"$build/lib" -lscree \
      -Wl,-rpath,"$build/lib" -o "$work/replay_$side"
done
status=0
for m in phaseTransition simsand kineticTheory; do
  "$work/replay_old" $m > "$work/$m.old"
  "$work/replay_new" $m > "$work/$m.new"
  if cmp -s "$work/$m.old" "$work/$m.new"; then
    echo "$m: identical ($(wc -l < "$work/$m.new") values)"
  else
    status=1
    python3 - "$work/$m.old" "$work/$m.new" "$m" <<'PY'
import struct, sys
def val(h): return struct.unpack('<d', bytes.fromhex(h)[::-1])[0]
a = open(sys.argv[1]).read().split(); b = open(sys.argv[2]).read().split()
if len(a) != len(b):
    print('%s: different number of values (%d, %d)' % (sys.argv[3], len(a), len(b))); sys.exit()
rel = sorted(abs(val(x) - val(y)) / max(abs(val(x)), abs(val(y))) for x, y in zip(a, b) if x != y)
print('%s: %d of %d values differ; relative difference median %.2e, 99th percentile %.2e, largest %.2e'
      % (sys.argv[3], len(rel), len(a), rel[len(rel) // 2], rel[int(0.99 * (len(rel) - 1))], rel[-1]))
PY
  fi
done
exit $status

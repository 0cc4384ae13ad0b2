#!/usr/bin/env bash
# Where a particle kernel's instructions come from, without a GPU: compiles a unit of
# kernels (default: measure/ptx/phase_transition_2d_kernels.cu) with ptxas statistics
# (registers, stack, spills) and to PTX with line info, then counts each kernel's PTX
# instructions per source line, inclusive of everything inlined from it
# (measure/ptx_line_counts.py). Static counts: a branch's both sides count, a slow path
# as much as the fast one; divisions and square roots are weighted by their SASS length.
#
#   measure/ptx-line-counts.sh [UNIT.cu] [KERNEL-NAME-SUBSTRING] [TOP]
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
unit=${1:-$src/measure/ptx/phase_transition_2d_kernels.cu}
kernel=${2:-Lb1E}   # the mangled name's "true" of ElasticFirst: the elastic-only kernel
top=${3:-40}
out=$(mktemp -d)
flags=(-DSCREE_HAVE_CUDA=1 -I"$src/framework/include" -I"$src/materials/common/include" -O3 -DNDEBUG
       -arch=sm_90 --extended-lambda --expt-relaxed-constexpr -std=c++20 -x cu)
nvcc "${flags[@]}" -Xptxas -v -cubin "$unit" -o "$out/k.cubin" 2>&1 |
  grep -E "Compiling entry|registers|stack frame" | sed 's/ptxas info *: *//'
nvcc "${flags[@]}" -lineinfo -ptx "$unit" -o "$out/k.ptx"
python3 "$src/measure/ptx_line_counts.py" "$out/k.ptx" "$kernel" "$top"

#!/usr/bin/env python3
"""PTX instructions of one kernel per source line, inclusive of what is inlined from it.

    measure/ptx_line_counts.py FILE.ptx KERNEL-NAME-SUBSTRING [TOP]

Needs PTX made with -lineinfo: each instruction is charged to the line of the .loc before it
and to every line of that .loc's inlined-at chain. Weighted: a double division 18, a
square root 14, a reciprocal 10 (their SASS sequences), everything else 1.
"""
import collections
import re
import sys

ptx = open(sys.argv[1]).read().split("\n")
pattern = sys.argv[2]
top = int(sys.argv[3]) if len(sys.argv) > 3 else 40
files = {}
for line in ptx:
    m = re.match(r'\s*\.file\s+(\d+)\s+"([^"]+)"', line)
    if m:
        files[int(m.group(1))] = m.group(2).split("/")[-1]
entries = [i for i, line in enumerate(ptx) if re.search(r"\.entry\s", line) and pattern in line]
if not entries:
    sys.exit(f"no .entry containing {pattern!r}")
start = entries[0]
end = start
while not ptx[end].startswith("}"):
    end += 1
weight = {"div.rn.f64": 18, "sqrt.rn.f64": 14, "rcp.rn.f64": 10}
loc_re = re.compile(r"\.loc\s+(\d+)\s+(\d+)\s+(\d+)(?:,\s*function_name\s+\S+,\s*inlined_at\s+(\d+)\s+(\d+)\s+(\d+))?")
parent = {}
current = (0, 0, 0)
inclusive = collections.Counter()
raw = weighted = 0
for line in ptx[start:end]:
    t = line.strip()
    m = loc_re.search(t)
    if m:
        current = tuple(int(g) for g in m.group(1, 2, 3))
        if m.group(4):
            parent[current] = tuple(int(g) for g in m.group(4, 5, 6))
        continue
    if not t or t[0] in ".$/{}" or t.endswith(":"):
        continue
    op = t.split()[1] if t.startswith("@") else t.split()[0]
    w = weight.get(op.rstrip(";"), 1)
    raw += 1
    weighted += w
    frames, loc = set(), current
    while loc not in frames:
        frames.add(loc)
        loc = parent.get(loc, loc)
    for f, ln, _ in frames:
        inclusive[(f, ln)] += w
print(f"{ptx[start].split('(')[0].split()[-1][:100]}\n{raw} PTX instructions, {weighted} weighted")
for (f, ln), c in sorted(inclusive.items(), key=lambda x: -x[1])[:top]:
    print(f"{c:7d} {100 * c / weighted:5.1f}%  {files.get(f, f)}:{ln}")

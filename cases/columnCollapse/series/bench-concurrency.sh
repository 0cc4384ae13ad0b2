#!/bin/bash
# Do separate processes share one GPU usefully? One a = 8, 5 mm case (first-batch layout:
# git show e220053:./generate.py > g.py; /usr/bin/python3 g.py runs --set all) alone, then
# 8 copies at once, 4000 steps each, from the folder that holds runs/.
set -u
rm -rf /tmp/bench && mkdir -p /tmp/bench
for i in 0 1 2 3 4 5 6 7 8; do cp -r runs/a8_h5mm /tmp/bench/b$i; done
t0=$(date +%s%N)
scree --case /tmp/bench/b0 --device cuda --max-steps 4000 --no-output > /tmp/bench/b0.log 2>&1
t1=$(date +%s%N)
grep -E "Running|done:" /tmp/bench/b0.log
echo "alone: $(( (t1 - t0) / 1000000 )) ms"
t0=$(date +%s%N)
for i in 1 2 3 4 5 6 7 8; do scree --case /tmp/bench/b$i --device cuda --max-steps 4000 --no-output > /tmp/bench/b$i.log 2>&1 & done
wait
t1=$(date +%s%N)
grep -h "done:" /tmp/bench/b[1-8].log
echo "8 at once: $(( (t1 - t0) / 1000000 )) ms"

source .gpu-bundle/env.sh
nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv
ctest --test-dir build-cuda -L gpu --output-on-failure 2>&1 | tee $OUT/gpu-tests.log | tail -25
for g in "" --no-graphs; do build-cuda/bin/scree --case cases/columnCollapse --device cuda --no-output --max-steps 20000 $g 2>&1 | tail -1; done
build-cuda/bin/scree-bench --device both --threads 16 --cases column,flume,scaling --steps 2000 --cpu-steps 20 --max-particles 1000000 --csv $OUT/bench.csv --json $OUT/bench.json 2>&1 | tail -45

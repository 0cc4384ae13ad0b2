# A run to its endTime: checkpoints at 0.005 and 0.01 s.
"$SCREE" --case . --device cpu --threads 1 > /dev/null

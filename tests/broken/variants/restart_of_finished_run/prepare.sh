# A run to its endTime: its newest checkpoint is at endTime.
"$SCREE" --case . --device cpu --threads 1 > /dev/null

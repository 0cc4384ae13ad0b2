# A finished run, whose results and checkpoints are there.
"$SCREE" --case . --device cpu --threads 1 > /dev/null

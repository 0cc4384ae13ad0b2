# A run to its endTime (checkpoints at 0.005 and 0.01 s); then endTime is lowered below them.
"$SCREE" --case . --device cpu --threads 1 > /dev/null
sed -i 's/^endTime .*/endTime 0.004;/' system/controlDict

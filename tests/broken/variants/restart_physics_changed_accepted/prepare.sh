# A run stopped halfway (endTime 0.005 of 0.01), then the material's E doubled.
sed -i 's/^endTime .*/endTime 0.005;/' system/controlDict
"$SCREE" --case . --device cpu --threads 1 > /dev/null
sed -i 's/^endTime .*/endTime 0.01;/' system/controlDict
sed -i 's/^    E       1e6;/    E       2e6;/' constant/materialProperties

# 51.2 million points: 0.2 m x 1.0 m of column at 8 x 8 points per cell of 0.5 mm
sed -i 's/^cellSize .*/cellSize    0.0005;/' system/gridDict
sed -i 's/particlesPerCell    2;/particlesPerCell    8;/' constant/bodies
grep -q 'particlesPerCell    8;' constant/bodies

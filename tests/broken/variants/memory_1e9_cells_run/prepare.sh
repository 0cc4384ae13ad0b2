# cellSize 1.5e-5: about 1e9 cells, and 3.6e9 points of the column at 2 x 2 per cell
sed -i 's/^cellSize .*/cellSize    1.5e-5;/' system/gridDict
grep -q '1.5e-5' system/gridDict

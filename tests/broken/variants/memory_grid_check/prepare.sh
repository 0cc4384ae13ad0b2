# A domain of 40 m x 40 m at 0.1 mm cells: 1.6e11 nodes, about 24 TB of nodal fields
sed -i 's/^upper .*/upper       (40 40);/' system/gridDict
sed -i 's/^cellSize .*/cellSize    1e-4;/' system/gridDict
grep -q '(40 40)' system/gridDict

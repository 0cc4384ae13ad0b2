# A rain whose hyetograph names a CSV file the case does not have.
cat >> constant/boundaryConditions <<'DICT'
rain        { type rainfall; face yMax; intensity { type csvFile; file "constant/hyetograph.csv"; unit mm/h; } }
DICT

# A hyetograph whose third row has a word where the intensity should be.
printf 'hour,rain_mm_per_h\n0,10\n1,heavy\n2,0\n' > constant/hyetograph.csv
cat >> constant/boundaryConditions <<'DICT'
rain        { type rainfall; face yMax; intensity { type csvFile; file "constant/hyetograph.csv"; timeUnit h; unit mm/h; } }
DICT

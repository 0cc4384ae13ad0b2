sed -i 's/^writeControl .*/writeControl    timeStep;/; s/^writeInterval .*/writeInterval   0.4;/' system/controlDict

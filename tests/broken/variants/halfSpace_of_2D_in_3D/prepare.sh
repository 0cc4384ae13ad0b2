sed -i 's/face yMin;/halfSpace { point (0 0.1); normal (0 1); }/' constant/boundaryConditions

echo 'slope { type inclinedPlane; point (0 0.1); normal (1 1); condition friction; }' >> constant/boundaryConditions

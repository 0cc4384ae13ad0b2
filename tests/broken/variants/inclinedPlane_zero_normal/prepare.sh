echo 'slope { type inclinedPlane; point (0 0.1); normal (0 0); condition slip; }' >> constant/boundaryConditions

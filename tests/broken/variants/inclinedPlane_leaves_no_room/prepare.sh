echo 'slope { type inclinedPlane; point (0 2); normal (1 1); condition noSlip; }' >> constant/boundaryConditions

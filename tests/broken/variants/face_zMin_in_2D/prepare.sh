sed -i 's/face yMin;/face zMin;/' constant/boundaryConditions

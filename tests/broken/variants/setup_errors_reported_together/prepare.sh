sed -i 's/upper   (0.2 0.2);/upper   (0.5 0.2);/' constant/bodies
sed -i 's/face yMin;/face zMin;/' constant/boundaryConditions

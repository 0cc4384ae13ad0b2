sed -i 's/^deltaT .*/deltaT          5e-4;/' system/controlDict
echo 'stopCo          1.5;' >> system/controlDict

sed -i 's/^deltaT .*/deltaT          1e-15;/' system/controlDict

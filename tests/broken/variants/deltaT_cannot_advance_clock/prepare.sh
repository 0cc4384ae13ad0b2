sed -i 's/^deltaT .*/deltaT          1e-30;/' system/controlDict

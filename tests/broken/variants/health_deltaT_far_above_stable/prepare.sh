sed -i 's/^deltaT .*/deltaT          2e-3;/' system/controlDict
grep -q '^deltaT          2e-3;' system/controlDict

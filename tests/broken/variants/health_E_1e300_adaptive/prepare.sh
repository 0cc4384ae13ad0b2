sed -i 's/^\s*E .*/    E 1e300;/' constant/materialProperties
sed -i 's/^adjustTimeStep .*/adjustTimeStep yes;/' system/controlDict
grep -q 'E 1e300;' constant/materialProperties
grep -q 'adjustTimeStep yes;' system/controlDict

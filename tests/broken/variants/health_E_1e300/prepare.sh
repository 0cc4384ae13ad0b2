sed -i 's/^\s*E .*/    E 1e300;/' constant/materialProperties
grep -q 'E 1e300;' constant/materialProperties

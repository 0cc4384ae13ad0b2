sed -i 's/^    E       1e6;/    E       1e6/' constant/materialProperties

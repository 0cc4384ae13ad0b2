sed -i 's/^endTime .*/endTime         1000;/' system/controlDict

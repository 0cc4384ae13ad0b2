sed -i 's/^endTime .*/endTime         1000;/' system/controlDict
echo 'progressInterval 500;' >> system/controlDict

echo "endTime 1e9;" >> system/controlDict

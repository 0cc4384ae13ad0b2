mkdir -p postProcessing/front
echo "time [s],runout [m]" > postProcessing/front/runOut.csv

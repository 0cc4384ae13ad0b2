sed -i 's/value       (0 -9.81 0);/value       (0 -9.81);/' constant/g

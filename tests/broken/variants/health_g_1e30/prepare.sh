sed -i 's/^value .*/value       (0 -1e30);/' constant/g
grep -q -- '-1e30' constant/g

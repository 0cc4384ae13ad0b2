rm constant/g
mkfifo constant/g

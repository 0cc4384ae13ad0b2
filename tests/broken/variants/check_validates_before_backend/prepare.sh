rm constant/g

sed -i 's/p2      (0.1 0.2 0.1);/p2      (0.1 0 0.1);/' constant/bodies

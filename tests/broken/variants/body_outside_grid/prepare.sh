sed -i 's/upper   (0.2 0.2);/upper   (0.5 0.2);/' constant/bodies

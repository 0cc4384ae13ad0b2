sed -i 's/type    rectangle;/type    cylinder; p1 (0.1 0); p2 (0.1 0.2); radius 0.1;/; /lower \|upper /d' constant/bodies

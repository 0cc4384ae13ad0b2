sed -i 's/type    cylinder;/type    rectangle; lower (0 0 0); upper (0.2 0.2 0.2);/; /p1 \|p2 \|radius/d' constant/bodies

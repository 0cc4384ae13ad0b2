sed -i 's/material            soil;/material            soil; angularVelocity (0 0 1);/' constant/bodies

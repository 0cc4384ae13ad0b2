sed -i 's/material            soil;/material            soil; clip { lower (0.3 0 0); upper (0.4 0.4 0.2); }/' constant/bodies

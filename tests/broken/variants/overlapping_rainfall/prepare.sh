# Two rainfalls on overlapping stretches of the block's top (y = 0.2 m) at once, which the
# run gave the smaller intensity of; beside them, conditions that do not conflict: a rain
# on the same nodes after the first two stop, and ponding (another type) on the same nodes.
cat >> constant/boundaryConditions <<'DICT'
rainA       { type rainfall; box { min (0 0.15); max (0.2 0.25); } intensity 1e-4; unit m/s; endTime 10; }
rainB       { type rainfall; box { min (0.1 0.15); max (0.4 0.25); } intensity 2e-4; unit m/s; endTime 10; }
later       { type rainfall; box { min (0 0.15); max (0.4 0.25); } intensity 3e-4; unit m/s; startTime 10; }
pond        { type ponding; box { min (0 0.15); max (0.4 0.25); } }
DICT

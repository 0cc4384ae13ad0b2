# Four conditions on the pore liquid whose regions lie above the grid (0.4 m high): rain,
# ponding, a water table box and a seepage face; and one that selects nodes.
cat >> constant/boundaryConditions <<'DICT'
rain        { type rainfall; box { min (0 1.0); max (0.4 1.2); } intensity 1e-4; unit m/s; }
pond        { type ponding; box { min (0 1.0); max (0.4 1.2); } }
table       { type porePressure; min (0 1.0); max (0.4 1.2); value 0; }
seep        { type seepageFace; box { min (0 1.0); max (0.4 1.2); } }
inside      { type ponding; box { min (0 0.15); max (0.4 0.25); } }
DICT

# A solid wall (terrain, shape solid) drawn with two vertices: no closed polygon.
cat >> constant/boundaryConditions <<'DICT'
wall        { type terrain; shape solid; condition slip; points ((0.2 0) (0.2 0.5)); }
DICT

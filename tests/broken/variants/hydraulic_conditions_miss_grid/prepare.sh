# A two-phase block, and four conditions on its pore liquid whose regions lie above the
# grid (0.4 m high): rain, ponding, a water table box and a seepage face.
cat > constant/bodies <<'DICT'
FoamFile { version 2.0; format ascii; class dictionary; object bodies; }

block
{
    material            soil;
    region              { type rectangle; lower (0 0); upper (0.2 0.2); }
    twoPhase
    {
        porosity                0.3;
        liquidDensity           1000;
        liquidBulkModulus       2e8;
        viscosity               1e-3;
        hydraulicConductivity   1e-4;
    }
}
DICT
cat >> constant/boundaryConditions <<'DICT'
rain        { type rainfall; box { min (0 1.0); max (0.4 1.2); } intensity 1e-4; unit m/s; }
pond        { type ponding; box { min (0 1.0); max (0.4 1.2); } }
table       { type porePressure; min (0 1.0); max (0.4 1.2); value 0; }
seep        { type seepageFace; box { min (0 1.0); max (0.4 1.2); } }
inside      { type ponding; box { min (0 0.15); max (0.4 0.25); } }
DICT
printf 'updateScheme USL;\n' > system/mpmSchemes
sed -i 's/^deltaT .*/deltaT 1e-5;/' system/controlDict  # stable for the two-phase block

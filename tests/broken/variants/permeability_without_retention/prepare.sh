# A two-phase body with a relative permeability and no retention curve.
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
        permeability            { type mualemVanGenuchten; }
    }
}
DICT
printf 'updateScheme USL;\n' > system/mpmSchemes

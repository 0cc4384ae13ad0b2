# The two-phase base's body given a relative permeability and no retention curve.
sed -i 's/^        hydraulicConductivity   1e-4;/&\n        permeability            { type mualemVanGenuchten; }/' constant/bodies

#!/usr/bin/env bash
# make-factors.sh DEST CASE: two copies of the axisymmetric case at 5 mm: DEST/full (the whole
# cylinder, no symmetry planes) and DEST/coulomb (a Coulomb floor, mu = tan 22 deg)
set -eu
D=$1; C=$2
rm -rf $D && mkdir -p $D && cp -r $C $D/full && cp -r $C $D/coulomb
for k in full coulomb; do sed -i 's/^cellSize    0.0025;/cellSize    0.005;/' $D/$k/system/gridDict; done
sed -i 's/^lower       (0 0 0);/lower       (-0.35 0 -0.35);/; s/^upper       (0.4 0.22 0.4);/upper       (0.35 0.22 0.35);/' $D/full/system/gridDict
sed -i '/^    clip /d' $D/full/constant/column
sed -i '/^symmetryX/d; /^symmetryZ/d' $D/full/constant/boundaryConditions
sed -i 's/^floor .*/floor       { type friction; face yMin; coefficient 0.404026; }    \/\/ Coulomb, mu = tan 22 deg/' $D/coulomb/constant/boundaryConditions

# The axisymmetric collapse as it shipped, its materials included from a sibling case: in
# a copy elsewhere that file does not exist.
cat > constant/materialProperties <<'DICT'
FoamFile { version 2.0; format ascii; class dictionary; object materialProperties; }
#include "../../columnCollapse/constant/materialProperties"
DICT

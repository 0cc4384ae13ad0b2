mkdir -p constant/triSurface
# A triangle of three vertices "x y z".
facet() {
  printf 'facet normal 0 0 0\nouter loop\nvertex %s\nvertex %s\nvertex %s\nendloop\nendfacet\n' "$1" "$2" "$3"
}
# A cube with its top face missing (its 4 rim edges used once).
{
  echo "solid block"
  facet "0 0 0" "0 0 0.2" "0 0.2 0.2"
  facet "0 0 0" "0 0.2 0.2" "0 0.2 0"
  facet "0.2 0 0" "0.2 0.2 0" "0.2 0.2 0.2"
  facet "0.2 0 0" "0.2 0.2 0.2" "0.2 0 0.2"
  facet "0 0 0" "0.2 0 0" "0.2 0 0.2"
  facet "0 0 0" "0.2 0 0.2" "0 0 0.2"
  facet "0 0 0" "0 0.2 0" "0.2 0.2 0"
  facet "0 0 0" "0.2 0.2 0" "0.2 0 0"
  facet "0 0 0.2" "0.2 0 0.2" "0.2 0.2 0.2"
  facet "0 0 0.2" "0.2 0.2 0.2" "0 0.2 0.2"
  echo "endsolid block"
} > constant/triSurface/block.stl
sed -i "s|type    cylinder;|type    stl; file \"constant/triSurface/block.stl\";|; /p1 \\|p2 \\|radius/d" constant/bodies

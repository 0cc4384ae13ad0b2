mkdir -p constant/triSurface
printf "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.1 0 zero\nvertex 0 0.1 0\nendloop\nendfacet\nendsolid s\n" > constant/triSurface/block.stl
sed -i "s|type    cylinder;|type    stl; file \"constant/triSurface/block.stl\";|; /p1 \\|p2 \\|radius/d" constant/bodies

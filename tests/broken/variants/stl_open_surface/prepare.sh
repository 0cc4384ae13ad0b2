mkdir -p constant/triSurface
# A cube with its top face missing (its 4 rim edges used once).
cat > constant/triSurface/block.stl <<EOF
solid block
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0 0.2
vertex 0 0.2 0.2
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0.2 0.2
vertex 0 0.2 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0.2 0 0
vertex 0.2 0.2 0
vertex 0.2 0.2 0.2
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0.2 0 0
vertex 0.2 0.2 0.2
vertex 0.2 0 0.2
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0.2 0 0
vertex 0.2 0 0.2
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0.2 0 0.2
vertex 0 0 0.2
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0 0.2 0
vertex 0.2 0.2 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 0.2 0.2 0
vertex 0.2 0 0
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0.2
vertex 0.2 0 0.2
vertex 0.2 0.2 0.2
endloop
endfacet
facet normal 0 0 0
outer loop
vertex 0 0 0.2
vertex 0.2 0.2 0.2
vertex 0 0.2 0.2
endloop
endfacet
endsolid block
EOF
sed -i "s|type    cylinder;|type    stl; file \"constant/triSurface/block.stl\";|; /p1 \\|p2 \\|radius/d" constant/bodies

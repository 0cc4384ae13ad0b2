echo "not a directory" > out
sed -i 's|particles   { type vtk; }|particles   { type vtk; directory "out/VTK"; }|' system/controlDict

sed -i 's|particles   { type vtk; }|particles   { type vtk; directory "../elsewhere"; }|' system/controlDict

mkdir -p VTK postProcessing
echo notes > VTK/notes.txt
echo tmp > VTK/.particles.pvd.tmp1_0

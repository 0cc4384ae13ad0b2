cat >> constant/bodies <<'B'
block
{
    material soil;
    region { type rectangle; lower (0.2 0); upper (0.4 0.2); }
}
B

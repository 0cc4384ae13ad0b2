#!/usr/bin/python3
"""Write constant/bodies of cases/rainfallSlope: the slope as vertical strips.

Why strips: the geostatic initial stress of a body (framework/src/solver/particle_generation.cpp
and porous/porous_media.cpp) measures every point's depth from one elevation, the top of the
body. One polygon for the whole slope would load the toe with the 2.5 m of soil that stands
above the crest, and leave the base under the crest without it. Cut into vertical strips one
cell wide, each strip's points take their depth from the strip's own top (off by at most one
cell times tan(beta) at the strip's low side). The strips are bodies of the same material on
the same grid: they share the nodes, so they move as one continuum.

    /usr/bin/python3 cases/rainfallSlope/makeBodies.py > cases/rainfallSlope/constant/bodies
"""

# Geometry [m] (keep in step with system/gridDict and the README).
H_BASE = 0.5       # base layer thickness: the toe's level
H_SLOPE = 2.5      # slope height above the base layer
X_CREST = 1.5      # the crest runs from the left wall to here
X_TOE = 3.3        # the face meets the base layer here: beta = atan(2.5 / 1.8) = 54.2 deg
X_END = 6.0        # right wall
H = 0.1            # cell size: the strips' width

BODY = """{name}
{{
    material            soil;
    region              {{ type polygon; points ({pts}); }}
    particlesPerCell    2;
    initialStress       {{ type geostatic; K0 $_K0; }}
    twoPhase            $_twoPhase;
}}
"""


def surface(x):
    """Elevation of the ground surface at x."""
    top = H_BASE + H_SLOPE
    if x <= X_CREST:
        return top
    if x >= X_TOE:
        return H_BASE
    return top - (x - X_CREST) / (X_TOE - X_CREST) * H_SLOPE


def fmt(p):
    return "({:.6g} {:.6g})".format(*p)


def main():
    print("FoamFile { version 2.0; format ascii; class dictionary; object bodies; }")
    print("// Written by makeBodies.py (the slope cut into vertical strips; why: its docstring).")
    print("// The soil's two-phase entries and K0 are in constant/soilProperties.")
    print('#include "soilProperties"')
    print()
    # The crest block and the toe's base layer are single strips: their tops are flat.
    strips = [(0.0, X_CREST)]
    n = round((X_TOE - X_CREST) / H)
    strips += [(X_CREST + i * H, X_CREST + (i + 1) * H) for i in range(n)]
    strips += [(X_TOE, X_END)]
    for i, (a, b) in enumerate(strips):
        pts = [(a, 0.0), (b, 0.0), (b, surface(b)), (a, surface(a))]
        print(BODY.format(name="strip%02d" % i, pts=" ".join(fmt(p) for p in pts)))


if __name__ == "__main__":
    main()

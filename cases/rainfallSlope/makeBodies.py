#!/usr/bin/python3
"""Write constant/bodies of cases/rainfallSlope: the slope as a staircase of rectangles.

    /usr/bin/python3 cases/rainfallSlope/makeBodies.py > cases/rainfallSlope/constant/bodies

Why a staircase of whole cells. A polygon face cuts cells: a node next to a partly filled
cell is not a surface node (the two-phase formulation finds surface nodes as nodes next to an
empty cell, porous/two_phase.hpp surface_node), so it gets neither the closed surface's
boundary term nor a place in the surface-inflow count, and it acts as an open surface at
p_w = 0. Measured without rain, 5 s (README, "Without rain"): with the same face as polygon
columns the slope's stored water grew by 24.8 kg/m, as this staircase by 17.7 kg/m. The
staircase removes that part; the rest of the spurious water is there either way.

Why one body per column. The geostatic initial stress of a body used to measure every
point's depth from one elevation, the body's top: one body for the whole slope would have
loaded the toe with the 2.4 m of soil that stands above the crest. As rectangles of one cell's
width, each column's points took their depth from the column's own top. The stress now takes
each point's own column (case/overburden.hpp, `overburden all`), so one polygon tracing this
staircase starts from the same state (README); the columns stay because the README's results
were measured with them. The columns are bodies of one material on one grid: they share the
nodes and move as one continuum.
"""

# Geometry [m] (keep in step with system/gridDict, constant/boundaryConditions, the README).
H = 0.1            # cell size (system/gridDict): the columns' width, the steps' unit
H_BASE = 5         # base layer: 5 cells, 0.5 m (the toe's level)
H_SLOPE = 24       # slope height above the base layer: 24 cells, 2.4 m
X_CREST = 15       # the crest runs from the left wall to x = 1.5 m
RISE = 1.5         # the face rises 1.5 cells per cell: beta = atan(1.5) = 56.3 deg
X_END = 60         # right wall at x = 6 m

BODY = """{name}
{{
    material            soil;
    region              {{ type rectangle; lower ({x0:.6g} 0); upper ({x1:.6g} {y1:.6g}); }}
    particlesPerCell    2;
    initialStress       {{ type geostatic; K0 $_K0; }}
    twoPhase            $_twoPhase;
}}
"""


def columns():
    """(x0, x1, top) in cells: the crest block, one column per cell of the face, the toe."""
    out = [(0, X_CREST, H_BASE + H_SLOPE)]
    i = 0
    while True:
        # The face line at the column's centre, rounded to whole cells (steps of 1 and 2).
        top = round(H_SLOPE - RISE * (i + 0.5))
        if top <= 0:
            break
        out.append((X_CREST + i, X_CREST + i + 1, H_BASE + top))
        i += 1
    out.append((X_CREST + i, X_END, H_BASE))
    return out


def main():
    print("FoamFile { version 2.0; format ascii; class dictionary; object bodies; }")
    print("// Written by makeBodies.py: the slope as a staircase of columns of whole cells (why: its")
    print("// docstring). The soil's two-phase entries and K0 are in constant/soilProperties.")
    print('#include "soilProperties"')
    print()
    for k, (x0, x1, top) in enumerate(columns()):
        print(BODY.format(name="column%02d" % k, x0=x0 * H, x1=x1 * H, y1=top * H))


if __name__ == "__main__":
    main()

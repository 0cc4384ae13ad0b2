#!/usr/bin/python3
"""Write constant/bodies of cases/rainfallSlope: the slope as one polygon tracing a staircase
of whole cells; or, with --columns, as the staircase's 18 rectangles (variants/columns).

    /usr/bin/python3 cases/rainfallSlope/makeBodies.py > cases/rainfallSlope/constant/bodies
    /usr/bin/python3 cases/rainfallSlope/makeBodies.py --columns \
        > cases/rainfallSlope/variants/columns/constant/bodies

Why a staircase of whole cells. A polygon face cuts cells: a node next to a partly filled
cell is not a surface node (the two-phase formulation finds surface nodes as nodes next to an
empty cell, porous/two_phase.hpp surface_node), so it gets neither the closed surface's
boundary term nor a place in the surface-inflow count, and it acts as an open surface at
p_w = 0. Measured without rain, 5 s (README, "Without rain"): with the same face as polygon
columns the slope's stored water grew by 24.8 kg/m, as this staircase by 17.7 kg/m. The
staircase removes that part; the rest of the spurious water is there either way.

Why one body. The geostatic stress takes the material above each point in its own column
(case/overburden.hpp, `overburden all`), so one polygon starts from the same state as the
staircase's 18 column bodies, each measured from its own top. The two are the same points
and run alike (README, "One body"); each body is launched on its own in every phase of a
step, so one body runs the step about ten times faster.
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


POLYGON = """slope
{{
    material            soil;
    region
    {{
        type    polygon;
        points  ({points});
    }}
    particlesPerCell    2;
    initialStress       {{ type geostatic; K0 $_K0; }}
    twoPhase            $_twoPhase;
}}
"""


def outline():
    """The staircase's vertices [cells], counter-clockwise from the origin."""
    cols = columns()
    pts = [(0, 0), (X_END, 0)]
    for x0, x1, top in reversed(cols):  # from the toe up to the crest: each column's top
        if pts[-1][1] != top:
            pts.append((x1, top))
        pts.append((x0, top))
    return pts


def main():
    import sys

    as_columns = "--columns" in sys.argv[1:]
    include = '"../../../constant/soilProperties"' if as_columns else '"soilProperties"'
    print("FoamFile { version 2.0; format ascii; class dictionary; object bodies; }")
    if as_columns:
        print("// Written by makeBodies.py --columns: the slope as the staircase's columns, one body each,")
        print("// the same points as the main case's one polygon (why: its docstring).")
    else:
        print("// Written by makeBodies.py: the slope as one polygon tracing a staircase of whole cells")
        print("// (why: its docstring). The soil's two-phase entries and K0 are in constant/soilProperties.")
    print("#include " + include)
    print()
    if as_columns:
        for k, (x0, x1, top) in enumerate(columns()):
            print(BODY.format(name="column%02d" % k, x0=x0 * H, x1=x1 * H, y1=top * H))
    else:
        text = " ".join("(%.6g %.6g)" % (x * H, y * H) for x, y in outline())
        print(POLYGON.format(points=text))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Write the column-collapse aspect-ratio series: one self-contained case per
(aspect ratio, cell size, factor) into a target folder.

The column keeps the shipped length L0 = 0.2 m and grows in height, h0 = a L0; every
other setting is the shipped case's (system/ and constant/ one folder up): the two
stages (consolidation behind a gate with local damping, then release), the SIMSAND +
kinetic-theory material, the no-slip floor, 2 x 2 points per cell, FLIP with picRate 10.
A factor changes one of these and nothing else.

    cd cases/columnCollapse/series
    /usr/bin/python3 generate.py runs                 # the series: every a at 5 and 2.5 mm
    /usr/bin/python3 generate.py runs --set factors   # one factor at a time, a = 8 and 2
    /usr/bin/python3 generate.py runs --set all       # both, in the order run-series.sh starts them
    /usr/bin/python3 generate.py runs --list          # the names only

The names go to runs/cases.txt in the order a runner should start them.

Each case writes only function objects (no VTK): postProcessing/<name>/runOut.csv for
the fronts (quantiles 1, 0.999, 0.99), the height and the kinetic energy, and the free
surface profile (postProcessing/surface/<time>.csv) from which the analysis takes the
front of the connected mass.
"""
import argparse
import math
import os
import sys

L0 = 0.2                 # [m] column length (the shipped case's)
RELEASE = 0.1            # [s] end of the consolidation stage (system/stages)
G = 9.81
ASPECTS = (0.5, 1, 2, 4, 8, 16)
CELLS = (0.005, 0.0025)  # [m] coarse (the shipped variant C-2) and fine (C-3)

# One factor at a time against the coarse baseline (every entry: the shipped value).
FACTORS = {
    "floorFriction": {"floor": ("friction", math.tan(math.radians(22.0)))},
    "floorSlip":     {"floor": ("slip", None)},
    "ppc3":          {"ppc": 3},
    "pic0":          {"picRate": 0},
    "pic100":        {"picRate": 100},
    "maxVR513":      {"maxVolumeRatio": 513},
    "frictional":    {"material": "sandFrictional"},
}
FACTOR_ASPECTS = (8, 2)


def law_runout(a):
    """(d - L0)/L0 of Lube et al. 2005 (quasi-2D): 1.2 a below 2.3, 1.9 a^(2/3) above."""
    return 1.2 * a if a < 2.3 else 1.9 * a ** (2.0 / 3.0)


def end_time(a):
    """Release + 6 sqrt(h0/g) (at least 0.7 s), rounded up to 0.1 s."""
    tc = math.sqrt(a * L0 / G)
    return math.ceil((RELEASE + max(0.7, 6.0 * tc)) * 10.0 - 1e-9) / 10.0


def domain(a, h):
    # Long enough for a linear run-out at twice Lube's slope (the shipped a = 0.5 case
    # already runs 1.9 a), i.e. at least 1.5 x the law everywhere; tall enough for h0.
    length = max(0.6, L0 * (1.0 + 2.2 * a), 1.5 * L0 * (1.0 + law_runout(a)))
    length = math.ceil(length / 0.05) * 0.05
    height = math.ceil((1.1 * a * L0 + 0.02) / 0.01) * 0.01
    return length, height


HEAD = "FoamFile {{ version 2.0; format ascii; class {cls}; object {obj}; }}\n"


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def make_case(root, name, a, h, opts):
    d = os.path.join(root, name)
    h0 = a * L0
    length, height = domain(a, h)
    t_end = end_time(a)
    tc = math.sqrt(h0 / G)
    floor = opts.get("floor", ("fixed", None))
    ppc = opts.get("ppc", 2)
    pic = opts.get("picRate", 10)
    transfer = opts.get("transfer", "FLIP")
    mvr = opts.get("maxVolumeRatio")
    material = opts.get("material", "sand")
    note = (f"// Column-collapse series (cases/columnCollapse/series/generate.py): {name}\n"
            f"// a = h0/L0 = {a:g}, L0 = {L0:g} m, h0 = {h0:g} m, cells {h*1e3:g} mm, "
            f"tau_c = sqrt(h0/g) = {tc:.4f} s\n")

    write(f"{d}/system/stages", note + f"_releaseTime    {RELEASE:g};    // [s]\n")
    write(f"{d}/system/controlDict", note + HEAD.format(cls="dictionary", obj="controlDict") + f"""
#include "stages"

endTime         {t_end:g};   // [s] release + 6 sqrt(h0/g) (at least 0.7 s)
deltaT          1e-5;       // [s] the first step
adjustTimeStep  yes;
maxCo           0.5;        // the step follows the wave speed, dt = 0.5 h / (c + |v|), at
maxDeltaT       1e-4;       // every cell size (the shipped case caps it at 1e-5 s)
writeControl    adjustableRunTime;
writeInterval   {t_end:g};
maxLostFraction 1;          // a point leaving the domain is counted, not fatal

functions
{{
    deposit   {{ type runOut; executeControl runTime; executeInterval 0.005; }}
    front999  {{ type runOut; frontQuantile 0.999; executeControl runTime; executeInterval 0.005; }}
    massFront {{ type runOut; frontQuantile 0.99;  executeControl runTime; executeInterval 0.005; }}
    surface   {{ type surfaceProfile; binWidth {h:g}; executeControl runTime; executeInterval 0.1; }}
}}
""")
    write(f"{d}/system/gridDict", note + HEAD.format(cls="dictionary", obj="gridDict") + f"""
dimension   2;
lower       (0 0);
upper       ({length:g} {height:g});
cellSize    {h:g};
""")
    extra = f"maxVolumeRatio  {mvr:g};\n" if mvr else ""
    write(f"{d}/system/mpmSchemes", note + HEAD.format(cls="dictionary", obj="mpmSchemes") + f"""
#include "stages"

updateScheme    USF;
shapeFunction   linear;
transfer        {transfer};
picRate         {pic:g};        // [1/s]
{extra}
damping
{{
    coefficient 0.1;
    endTime     $_releaseTime;
}}
""")
    write(f"{d}/constant/g", note + HEAD.format(cls="uniformDimensionedVectorField", obj="g")
          + "value       (0 -9.81);\n")
    write(f"{d}/constant/bodies", note + HEAD.format(cls="dictionary", obj="bodies") + f"""
column
{{
    material            {material};
    region              {{ type rectangle; lower (0 0); upper ({L0:g} {h0:g}); }}
    particlesPerCell    {ppc};
    initialStress       {{ type geostatic; K0 0.5; }}
}}
""")
    kind, mu = floor
    if kind == "fixed":
        floor_text = "floor       { type fixed;   face yMin; }     // no-slip base (the shipped case's)\n"
    elif kind == "slip":
        floor_text = "floor       { type slip;    face yMin; }     // frictionless base\n"
    else:
        floor_text = (f"floor       {{ type friction; face yMin; coefficient {mu:.6g}; }}"
                      "   // Coulomb base, mu = tan 22 deg\n")
    write(f"{d}/constant/boundaryConditions", note + HEAD.format(cls="dictionary", obj="boundaryConditions") + f"""
#include "../system/stages"

{floor_text}leftWall    {{ type slip;    face xMin; }}     // roller
gate
{{
    type        slip;
    box         {{ min ({L0:g} -0.01); max ({L0 + 0.03:g} {height + 0.1:g}); }}
    normal      (-1 0);
    endTime     $_releaseTime;
}}
""")
    write(f"{d}/constant/materialProperties", note + HEAD.format(cls="dictionary", obj="materialProperties") + """
sand
{
    #includeEtc "materials/feng2025/table3-columnCollapse"
    integrationTolerance        1e-2;
    minSolidFraction            0.01;
}

sandFrictional
{
    #includeEtc "materials/feng2025/table3-columnCollapse-frictional"
    integrationTolerance        1e-2;
    minSolidFraction            0.01;
}
""")
    return d


def cases(which):
    """The cases in the order a runner should start them (most needed first)."""
    series = [(f"a{a:g}_h{h*1e3:g}mm", a, h, {}) for h in CELLS for a in ASPECTS]
    last = [c for c in series if c[1] == max(ASPECTS) and c[2] == min(CELLS)]
    factors = [(f"a{a:g}_h{CELLS[0]*1e3:g}mm_{f}", a, CELLS[0], opts)
               for a in sorted(FACTOR_ASPECTS) for f, opts in FACTORS.items()]
    if which == "series":
        return series
    if which == "factors":
        return factors
    # all: the series but its most expensive case, the factors, then that case
    return [c for c in series if c not in last] + factors + last


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("target", help="folder to write the cases into")
    p.add_argument("--set", choices=("series", "factors", "all"), default="series")
    p.add_argument("--only", nargs="*", help="write only these case names")
    p.add_argument("--list", action="store_true", help="print the names and estimated steps, write nothing")
    args = p.parse_args()
    for name, a, h, opts in cases(args.set):
        if args.only and name not in args.only:
            continue
        if args.list:
            length, height = domain(a, h)
            ppc = opts.get("ppc", 2)
            npts = round(L0 / h) * round(a * L0 / h) * ppc * ppc
            print(f"{name:32s} end {end_time(a):4.1f} s  domain {length:.2f} x {height:.2f} m  points {npts}")
            continue
        make_case(args.target, name, a, h, opts)
        with open(os.path.join(args.target, "cases.txt"), "a") as f:
            f.write(name + "\n")
        print(os.path.join(args.target, name))


if __name__ == "__main__":
    sys.exit(main())

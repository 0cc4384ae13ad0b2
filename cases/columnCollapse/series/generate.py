#!/usr/bin/python3
"""Write the column-collapse aspect-ratio series as self-contained cases.

The column keeps the shipped length L0 = 0.2 m and grows in height, h0 = a L0; every
other setting is the shipped case's (system/ and constant/ one folder up): the two
stages (consolidation behind a gate with local damping, then release), the SIMSAND +
kinetic-theory material, the no-slip floor, 2 x 2 points per cell, FLIP with picRate 10.
A factor changes one of these and nothing else.

One case holds several columns side by side, each in its own slot of the floor with its
own left wall (a roller) and gate, far enough apart that no run-out reaches the next
slot: fewer processes share the GPU (separate processes take turns on it), and every
column of a case steps with the same time step. What a slot holds besides the column
(its floor, points per cell, material) can differ between columns; what mpmSchemes,
gridDict, controlDict and materialProperties set (cell size, PIC share, maxVolumeRatio,
maxCo, the energy budget, the critical friction angle) is the case's, so those factors are
cases of their own. A column of a combined case and the same column alone give the same
fronts (series/README.md); a case allows at most 32 walls, so columns on the same floor
share one floor condition.

    cd cases/columnCollapse/series
    /usr/bin/python3 generate.py runs             # every case (names: runs/cases.txt)
    /usr/bin/python3 generate.py runs --only h5mm h2.5mm
    /usr/bin/python3 generate.py runs --list      # the cases and their columns

Each column writes function objects only (no VTK), named after the column (body) c:
postProcessing/c_deposit, c_front999, c_massFront/runOut.csv (front quantiles 1, 0.999,
0.99 from the column's left wall, the highest point, the kinetic energy) and
postProcessing/c_surface/<time>.csv (the free surface, from which analyse.py takes the
front of the connected mass).
"""
import argparse
import math
import os
import sys

L0 = 0.2                 # [m] column length (the shipped case's)
RELEASE = 0.1            # [s] end of the consolidation stage (system/stages)
G = 9.81
MU_BASE = math.tan(math.radians(22.0))   # Coulomb floor of the floor factor

# Column factors (what a slot holds); the empty name is the shipped setting.
COLUMN_FACTORS = {
    "":              {},
    "floorFriction": {"floor": "friction"},
    "floorSlip":     {"floor": "slip"},
    "ppc3":          {"ppc": 3},
    "frictional":    {"material": "sandFrictional"},
}

# The cases: name -> cell size, case-wide settings (picRate, maxVolumeRatio, maxCo, budget,
# phiC: the critical friction angle), columns (a, column factor).
# Columns on the same floor are neighbours and share one floor condition.
FACTOR_COLUMNS = [(a, f) for f in ("ppc3", "frictional", "floorFriction", "floorSlip") for a in (2, 8)]
CASES = {
    "h5mm":          (0.005,  {}, [(a, "") for a in (0.5, 1, 2, 4, 8, 16)] + FACTOR_COLUMNS),
    "h2.5mm":        (0.0025, {}, [(a, "") for a in (0.5, 1, 2, 4, 8)]),
    "h5mm_pic0":     (0.005,  {"picRate": 0}, [(2, ""), (8, "")]),
    "h5mm_pic100":   (0.005,  {"picRate": 100}, [(2, ""), (8, "")]),
    "h5mm_maxVR513": (0.005,  {"maxVolumeRatio": 513}, [(2, ""), (8, "")]),
    "h2.5mm_a16":    (0.0025, {}, [(16, "")]),
    # The tall columns one to a case, so that each stops at its own end time (in h5mm the
    # a = 16 column sets every column's), and the PIC blend's limit at a = 4.
    "h5mm_a4":       (0.005,  {}, [(4, "")]),
    "h5mm_a8":       (0.005,  {}, [(8, "")]),
    "h5mm_a16":      (0.005,  {}, [(16, "")]),
    "h2.5mm_a4":     (0.0025, {}, [(4, "")]),
    "h5mm_pic0_a4":  (0.005,  {"picRate": 0}, [(4, "")]),
    "h5mm_pic0_a8":  (0.005,  {"picRate": 0}, [(8, "")]),
    "h5mm_pic100_a4": (0.005, {"picRate": 100}, [(4, "")]),
    "h2.5mm_a1":     (0.0025, {}, [(1, "")]),
    "h2.5mm_a2":     (0.0025, {}, [(2, "")]),
    # The material's friction near the experiments' (natural sands and grains have friction
    # angles near 30 degrees and above; the paper's material, fitted to Bui et al.'s
    # aluminium rods, has 19.8).
    "h5mm_phic30_a0p5": (0.005, {"phiC": 30}, [(0.5, "")]),
    "h5mm_phic30_a1": (0.005, {"phiC": 30}, [(1, "")]),
    "h5mm_phic30_a2": (0.005, {"phiC": 30}, [(2, "")]),
    "h5mm_phic30_a4": (0.005, {"phiC": 30}, [(4, "")]),
    "h5mm_phic30_a8": (0.005, {"phiC": 30}, [(8, "")]),
    "h5mm_phic30_a16": (0.005, {"phiC": 30}, [(16, "")]),
    "h2.5mm_phic30_a4": (0.0025, {"phiC": 30}, [(4, "")]),
    # The floor at rest for a tall column, at cells a CPU runs (both columns in one case).
    "h10mm_floor_a4": (0.01, {}, [(4, ""), (4, "floorFriction")]),
    # The CI's coarse tall column (tests/verification/columnCollapse/tall_column.py), with
    # the energy budget.
    "h20mm_a4":      (0.02,   {"budget": True}, [(4, "")]),
}


def law_runout(a):
    """(d - L0)/L0 of Lube et al. 2005 (quasi-2D): 1.2 a below 2.3, 1.9 a^(2/3) above."""
    return 1.2 * a if a < 2.3 else 1.9 * a ** (2.0 / 3.0)


def tau(a):
    return math.sqrt(a * L0 / G)


def end_time(amax):
    """Release + 5 sqrt(h0/g) of the tallest column (at least 0.7 s), up to 0.1 s."""
    return math.ceil((RELEASE + max(0.7, 5.0 * tau(amax))) * 10.0 - 1e-9) / 10.0


def slot_length(a):
    # Room for a linear run-out at 3 a: Scree's 0.99 fronts run 1.4-2.0 a up to a = 2,
    # and the furthest points about 0.5 L0 beyond; a slot of 1.5 x Lube's law lost 1.5 %
    # of the points of a = 2 on a Coulomb floor over the domain's end.
    length = max(0.8, L0 * (1.0 + 3.0 * a), 1.5 * L0 * (1.0 + law_runout(a)))
    return math.ceil(length / 0.05) * 0.05 + 0.1


def column_name(a, factor):
    return ("a" + f"{a:g}".replace(".", "p")) + (f"_{factor}" if factor else "")


HEAD = "FoamFile {{ version 2.0; format ascii; class {cls}; object {obj}; }}\n"


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def layout(columns):
    """Left-wall positions of the columns' slots and the domain size."""
    x = 0.05
    out = []
    for a, f in columns:
        out.append((a, f, x))
        x = round(x + slot_length(a), 6)
    height = math.ceil((1.1 * max(a for a, _ in columns) * L0 + 0.02) / 0.01) * 0.01
    return out, round(x + 0.05, 6), height


def make_case(root, name):
    h, settings, columns = CASES[name]
    d = os.path.join(root, name)
    slots, length, height = layout(columns)
    amax = max(a for a, _ in columns)
    t_end = end_time(amax)
    q = 0.25 * h     # a box edge a quarter cell past a node row, so that the row is in
    note = (f"// Column-collapse series (cases/columnCollapse/series/generate.py), case {name}:\n"
            f"// cells {h*1e3:g} mm; columns L0 = {L0:g} m long, h0 = a L0 high:\n"
            + "".join(f"//   {column_name(a, f):18s} a = {a:<4g} left wall x = {x:g} m, "
                      f"tau_c = sqrt(h0/g) = {tau(a):.4f} s\n" for a, f, x in slots))

    write(f"{d}/system/stages", note + f"_releaseTime    {RELEASE:g};    // [s]\n")

    fos = []
    for a, f, x in slots:
        c = column_name(a, f)
        common = f"bodies ({c}); origin ({x:g} 0); executeControl runTime; executeInterval"
        fos.append(f"    {c}_deposit   {{ type runOut; {common} 0.05; }}")
        fos.append(f"    {c}_front999  {{ type runOut; frontQuantile 0.999; {common} 0.05; }}")
        fos.append(f"    {c}_massFront {{ type runOut; frontQuantile 0.99; {common} 0.02; }}")
        fos.append(f"    {c}_surface   {{ type surfaceProfile; bodies ({c}); origin ({x:g} 0); "
                   f"binWidth {h:g}; executeControl runTime; executeInterval 0.25; }}")
    if settings.get("budget"):
        fos.append("    energy        { type energies; budget yes; executeControl runTime; executeInterval 0.05; }")
    write(f"{d}/system/controlDict", note + HEAD.format(cls="dictionary", obj="controlDict") + f"""
#include "stages"

endTime         {t_end:g};   // [s] release + 5 sqrt(h0/g) of the tallest column (at least 0.7 s)
deltaT          1e-5;       // [s] the first step
adjustTimeStep  yes;
maxCo           {settings.get("maxCo", 0.5):g};        // the step follows the wave speed, dt = maxCo h / (c + |v|), at
maxDeltaT       1e-4;       // every cell size (the shipped case caps it at 1e-5 s)
writeControl    adjustableRunTime;
writeInterval   {t_end:g};
maxLostFraction 1;          // a point leaving the domain is counted, not fatal

functions
{{
{chr(10).join(fos)}
}}
""")
    write(f"{d}/system/gridDict", note + HEAD.format(cls="dictionary", obj="gridDict") + f"""
dimension   2;
lower       (0 0);
upper       ({length:g} {height:g});
cellSize    {h:g};
""")
    pic = settings.get("picRate", 10)
    mvr = settings.get("maxVolumeRatio")
    extra = f"maxVolumeRatio  {mvr:g};\n" if mvr else ""
    write(f"{d}/system/mpmSchemes", note + HEAD.format(cls="dictionary", obj="mpmSchemes") + f"""
#include "stages"

updateScheme    USF;
shapeFunction   linear;
transfer        FLIP;
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

    bodies, bcs = [], []
    for i, (a, f, x) in enumerate(slots):
        c = column_name(a, f)
        opts = COLUMN_FACTORS[f]
        bodies.append(f"""{c}
{{
    material            {opts.get("material", "sand")};
    region              {{ type rectangle; lower ({x:g} 0); upper ({x + L0:g} {a * L0:g}); }}
    particlesPerCell    {opts.get("ppc", 2)};
    initialStress       {{ type geostatic; K0 0.5; }}
}}
""")
        floor = opts.get("floor", "fixed")
        prev = COLUMN_FACTORS[slots[i - 1][1]].get("floor", "fixed") if i else None
        following = [j for j in range(i + 1, len(slots))
                     if COLUMN_FACTORS[slots[j][1]].get("floor", "fixed") != floor]
        xend = slots[following[0]][2] if following else length
        if floor != prev:   # one condition for a run of neighbouring slots on the same floor
            fbox = f"box {{ min ({x - 0.02:g} -1); max ({xend - 0.04:g} {q:g}); }}"
            if floor == "fixed":
                bcs.append(f"{c}_floor    {{ type fixed; {fbox} }}    // no-slip (the shipped floor)")
            elif floor == "slip":
                bcs.append(f"{c}_floor    {{ type slip; {fbox} normal (0 1); }}    // frictionless")
            else:
                bcs.append(f"{c}_floor    {{ type friction; {fbox} normal (0 1); coefficient {MU_BASE:.6g}; }}"
                           "    // Coulomb, mu = tan 22 deg")
        bcs.append(f"{c}_wall     {{ type slip; box {{ min ({x - 0.03:g} -1); max ({x + q:g} {height + 1:g}); }}"
                   " normal (1 0); }    // the column's left wall, a roller")
        bcs.append(f"{c}_gate     {{ type slip; box {{ min ({x + L0 - q:g} -1); max ({x + L0 + 0.03:g} {height + 1:g}); }}"
                   " normal (-1 0); endTime $_releaseTime; }    // removed at release")
    write(f"{d}/constant/bodies", note + HEAD.format(cls="dictionary", obj="bodies") + "\n" + "\n".join(bodies))
    write(f"{d}/constant/boundaryConditions", note + HEAD.format(cls="dictionary", obj="boundaryConditions")
          + '\n#include "../system/stages"\n\n' + "\n".join(bcs) + "\n")
    phic = settings.get("phiC")
    friction = (f"    criticalFrictionAngle       {phic:g};    // [deg] instead of the paper's 19.8\n"
                if phic else "")
    write(f"{d}/constant/materialProperties", note + HEAD.format(cls="dictionary", obj="materialProperties") + f"""
sand
{{
    #includeEtc "materials/feng2025/table3-columnCollapse"
    integrationTolerance        1e-2;
    minSolidFraction            0.01;
{friction}}}

sandFrictional
{{
    #includeEtc "materials/feng2025/table3-columnCollapse-frictional"
    integrationTolerance        1e-2;
    minSolidFraction            0.01;
{friction}}}
""")
    return d


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("target", help="folder to write the cases into")
    p.add_argument("--only", nargs="*", help="write only these cases")
    p.add_argument("--list", action="store_true", help="print the cases, write nothing")
    args = p.parse_args()
    for name, (h, settings, columns) in CASES.items():
        if args.only and name not in args.only:
            continue
        if args.list:
            slots, length, height = layout(columns)
            npts = sum(round(L0 / h) * round(a * L0 / h) * COLUMN_FACTORS[f].get("ppc", 2) ** 2
                       for a, f, _ in slots)
            print(f"{name:14s} end {end_time(max(a for a, _ in columns)):4.1f} s  domain {length:.2f} x "
                  f"{height:.2f} m  points {npts}  columns {' '.join(column_name(a, f) for a, f in columns)}")
            continue
        make_case(args.target, name)
        with open(os.path.join(args.target, "cases.txt"), "a") as f:
            f.write(name + "\n")
        print(os.path.join(args.target, name))


if __name__ == "__main__":
    sys.exit(main())

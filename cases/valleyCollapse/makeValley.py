#!/usr/bin/env python3
"""Writes constant/triSurface/valley.stl: the ground of the valleyCollapse case.

The ground is a height field z_g(x, y) over the domain's footprint, closed into a solid by
four side walls and a base (the terrain condition and an stl region both read closed
surfaces), written as a binary STL. Standard library only.

Along the valley (x, downhill): a flat release bench at z = H (x <= XB), a 35-degree slope,
a transition whose inclination falls linearly to 0 over XT metres, and a flat run-out at
z = 0. Across it (y): a flat floor of width FLOOR centred at y = W/2, between banks rising at
40 degrees to BANK metres; the banks fade out over the run-out (a fan), from x = XF0 to XF1.

    python3 makeValley.py [--spacing 0.25] [--out constant/triSurface/valley.stl]

Run it again with other constants to draw another valley; the case's bodies and grid are
written for these.
"""
import argparse
import math
import struct

L, W = 34.2, 12.0            # [m] footprint: x in [0, L], y in [0, W]
H = 6.0                      # [m] the release bench's elevation
XB = 6.0                     # [m] the bench ends, the slope begins
SLOPE = math.radians(35.0)   # the slope's inclination
XT = 4.0                     # [m] the transition's length (inclination 35 -> 0 degrees)
FLOOR = 6.0                  # [m] the floor's width
BANK_ANGLE = math.radians(40.0)
BANK = 2.5                   # [m] the banks' height along the bench and the slope
XF0, XF1 = 20.0, 28.0        # [m] the banks fade out between these (the fan)
BASE = -1.0                  # [m] the solid's base

# Where the slope ends: the transition drops XT * mean(tan) = the integral below.
def _transition_drop():
    n = 2000
    return sum(math.tan(SLOPE * (1 - (i + 0.5) / n)) for i in range(n)) * XT / n

XS = XB + (H - _transition_drop()) / math.tan(SLOPE)  # [m] the slope ends, the transition begins
XR = XS + XT                                          # [m] the run-out begins


def thalweg(x):
    """The floor's elevation along the valley."""
    if x <= XB:
        return H
    if x <= XS:
        return H - (x - XB) * math.tan(SLOPE)
    if x <= XR:
        # z = z(XS) - integral of tan(SLOPE (1 - s / XT)) ds, s = x - XS: closed form.
        s = min(x - XS, XT)
        k = SLOPE / XT
        drop = (math.log(math.cos(SLOPE - k * s)) - math.log(math.cos(SLOPE))) / k
        return H - (XS - XB) * math.tan(SLOPE) - drop
    return 0.0


def bank_height(x):
    if x <= XF0:
        return BANK
    if x >= XF1:
        return 0.0
    return BANK * 0.5 * (1 + math.cos(math.pi * (x - XF0) / (XF1 - XF0)))


def ground(x, y):
    off = max(0.0, abs(y - W / 2) - FLOOR / 2)
    return thalweg(x) + min(bank_height(x), math.tan(BANK_ANGLE) * off)


def triangles(spacing):
    nx, ny = round(L / spacing), round(W / spacing)
    xs = [L * i / nx for i in range(nx + 1)]
    ys = [W * j / ny for j in range(ny + 1)]
    # Exact breaks of slope on the lattice: the bench's edge and the floor's edges.
    xs = sorted(set(xs) | {XB})
    ys = sorted(set(ys) | {W / 2 - FLOOR / 2, W / 2 + FLOOR / 2})
    top = [[(x, y, ground(x, y)) for y in ys] for x in xs]
    bot = [[(x, y, BASE) for y in ys] for x in xs]
    out = []

    def quad(a, b, c, d):  # counter-clockwise seen from outside
        out.append((a, b, c))
        out.append((a, c, d))

    I, J = len(xs) - 1, len(ys) - 1
    for i in range(I):
        for j in range(J):
            quad(top[i][j], top[i + 1][j], top[i + 1][j + 1], top[i][j + 1])  # up
            quad(bot[i][j], bot[i][j + 1], bot[i + 1][j + 1], bot[i + 1][j])  # down
    for i in range(I):  # the walls y = 0 and y = W
        quad(bot[i][0], bot[i + 1][0], top[i + 1][0], top[i][0])
        quad(bot[i][J], top[i][J], top[i + 1][J], bot[i + 1][J])
    for j in range(J):  # the walls x = 0 and x = L
        quad(bot[0][j], top[0][j], top[0][j + 1], bot[0][j + 1])
        quad(bot[I][j], bot[I][j + 1], top[I][j + 1], top[I][j])
    return out


def write_binary_stl(path, tris):
    with open(path, "wb") as f:
        f.write(b"valleyCollapse ground (makeValley.py)".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for a, b, c in tris:
            u = [b[k] - a[k] for k in range(3)]
            v = [c[k] - a[k] for k in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            ln = math.sqrt(sum(t * t for t in n)) or 1.0
            f.write(struct.pack("<12fH", *(t / ln for t in n), *a, *b, *c, 0))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spacing", type=float, default=0.25, help="the lattice of the height field [m]")
    p.add_argument("--out", default="constant/triSurface/valley.stl")
    a = p.parse_args()
    tris = triangles(a.spacing)
    write_binary_stl(a.out, tris)
    print(f"{a.out}: {len(tris)} triangles; bench z = {H} m to x = {XB} m, slope to x = {XS:.4f} m, "
          f"transition to x = {XR:.4f} m, run-out z = 0")


if __name__ == "__main__":
    main()

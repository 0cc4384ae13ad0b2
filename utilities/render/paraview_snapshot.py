"""A ParaView screenshot of a Scree run: the particles of a .pvd series at one time,
drawn as Point Gaussian discs and coloured by a point array -- what a user sees after
File > Open particles.pvd in ParaView, saved without a window.

    pvbatch paraview_snapshot.py case/VTK/particles.pvd out.png [--field plasticStrain]
        [--component X] [--time 1.1] [--range 0 1] [--preset Jet] [--size 1600 520]
        [--radius 0.0005] [--zoom 1.0 | --scale 3.5e-4]

Needs ParaView's pvbatch (Debian: apt-get install paraview python3-paraview). Debian's
ParaView renders through X: without a display run it under `xvfb-run -a pvbatch ...`.
--time picks the step nearest to that time (default: the last); --radius is the disc
radius in metres (default: 0.6 x the smallest particle spacing, sqrt of the `volume` array, 2D).
The view frames the data shown (ParaView's Reset Camera), so with --zoom the scale depends on
the extent of the particles; --scale M sets it instead (M metres per pixel), so that pictures
of different runs can be compared by length. The scale of every picture is printed.
"""

import argparse
import math
import sys

from paraview.simple import (
    ColorBy, GetActiveViewOrCreate, GetColorTransferFunction, PVDReader, ResetCamera,
    SaveScreenshot, Show)

# component name -> index of a vector (x, y, z) or of Scree's symmetric tensor (Voigt order)
COMPONENTS = {"X": 0, "Y": 1, "Z": 2, "XX": 0, "YY": 1, "ZZ": 2, "XY": 3, "YZ": 4, "XZ": 5}


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("pvd")
    p.add_argument("png")
    p.add_argument("--field", default="plasticStrain")
    p.add_argument("--component", help="X, Y, Z (vectors) or XX, YY, XY, ... (tensors); default magnitude")
    p.add_argument("--time", type=float, help="time to show (nearest step; default the last)")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"))
    p.add_argument("--preset", default="Jet", help="ParaView colour preset (default Jet)")
    p.add_argument("--size", type=int, nargs=2, default=[1600, 520], metavar=("W", "H"))
    p.add_argument("--radius", type=float, help="disc radius [m]")
    p.add_argument("--zoom", type=float, default=1.0, help="> 1 zooms in")
    p.add_argument("--scale", type=float, help="metres per pixel (instead of --zoom)")
    a = p.parse_args(argv)

    src = PVDReader(FileName=a.pvd)
    times = list(src.TimestepValues) if src.TimestepValues else [0.0]
    t = times[-1] if a.time is None else min(times, key=lambda x: abs(x - a.time))
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = a.size
    view.ViewTime = t
    view.OrientationAxesVisibility = 0
    src.UpdatePipeline(t)

    if a.component and a.component not in COMPONENTS:
        sys.exit(f"paraview_snapshot: component '{a.component}' is not one of {', '.join(COMPONENTS)}")
    names = src.PointData.keys()
    if a.field not in names:
        sys.exit(f"paraview_snapshot: no point array '{a.field}' in {a.pvd}; it has: {', '.join(names)}")
    radius = a.radius
    if radius is None and "volume" in names:
        vmin, vmax = src.PointData["volume"].GetRange()
        radius = 0.6 * math.sqrt(vmin) if vmin > 0 else None  # the densest particles touch
    disp = Show(src, view)
    disp.SetRepresentationType("Point Gaussian")
    disp.ShaderPreset = "Plain circle"
    if radius:
        disp.GaussianRadius = radius
    if a.component:
        ColorBy(disp, ("POINTS", a.field, a.component))
    else:
        ColorBy(disp, ("POINTS", a.field))
    lut = GetColorTransferFunction(a.field)
    lut.ApplyPreset(a.preset, True)
    if a.component:
        lut.VectorMode = "Component"
        lut.VectorComponent = COMPONENTS[a.component]
    if a.range:
        lut.RescaleTransferFunction(*a.range)
    else:
        disp.RescaleTransferFunctionToDataRange(False, True)
    disp.SetScalarBarVisibility(view, True)
    view.InteractionMode = "2D"
    ResetCamera()
    cam = view.GetActiveCamera()
    if a.scale:
        cam.SetParallelScale(0.5 * a.scale * a.size[1])  # half the view height [m]
    else:
        cam.Zoom(a.zoom)
    SaveScreenshot(a.png, view, ImageResolution=a.size)
    scale = 2 * cam.GetParallelScale() / a.size[1]
    print(f"paraview_snapshot: wrote {a.png} ({a.field}{' ' + a.component if a.component else ''} at t = {t:g} s; "
          f"{scale:.6g} m per pixel, 0.1 m = {0.1 / scale:.1f} pixels)")


if __name__ == "__main__":
    main(sys.argv[1:])

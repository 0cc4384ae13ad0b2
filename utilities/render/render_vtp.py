#!/usr/bin/python3
"""Render Scree particle output (.vtp, or the last/chosen step of a .pvd) to a PNG.

Particles are drawn as discs (2D) or spheres (3D) of their own size (from the `volume`
array when present), coloured by a point array: a scalar, one component of a vector or
tensor, or the magnitude of a vector.

Two back ends:
  VTK (default)    offscreen rendering with VTK's Python module (Debian: python3-vtk9).
                   Debian's VTK renders through X: without a display the script restarts
                   itself under `xvfb-run -a` (apt-get install xvfb) when that exists.
  --matplotlib     a scatter plot of the particles (x-y plane) with matplotlib; needs no
                   OpenGL or X server. Files are still read with VTK's XML reader.

Examples:
  render_vtp.py case/VTK/vtk.pvd -o column.png --field stress_yy
  render_vtp.py case/VTK/vtk_5.vtp -o p.png --field pressure --range 0 1e4 --cmap viridis
  render_vtp.py case/VTK/vtk.pvd --index 0 -o v.png --field velocity        # |velocity|
  render_vtp.py case/VTK/vtk_5.vtp -o s.png --field stress --component XY --matplotlib
  render_vtp.py case/VTK/vtk_5.vtp --list                                   # arrays in the file
"""

import argparse
import math
import os
import re
import shutil
import sys
import xml.etree.ElementTree as ET

COMPONENT_NAMES = {
    3: ["X", "Y", "Z"],
    6: ["XX", "YY", "ZZ", "XY", "YZ", "XZ"],
}
ALIASES = {"ZX": "XZ"}  # Scree's Voigt order writes zx; VTK's symmetric tensors say XZ


def fail(msg):
    sys.stderr.write("render_vtp: error: " + msg + "\n")
    sys.exit(2)


def resolve_input(path, index):
    """The .vtp to render: the file itself, or the index-th step of a .pvd (default: last)."""
    if not os.path.exists(path):
        fail(f"no such file: {path}")
    if not path.endswith(".pvd"):
        return path, None
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        fail(f"{path}: not a readable .pvd ({e})")
    sets = [(float(d.get("timestep", "nan")), d.get("file")) for d in root.iter("DataSet")]
    if not sets:
        fail(f"{path}: the series is empty")
    i = len(sets) - 1 if index is None else index
    if not -len(sets) <= i < len(sets):
        fail(f"{path}: --index {index} out of range (the series has {len(sets)} steps)")
    t, f = sets[i]
    return os.path.join(os.path.dirname(path), f), t


def read_polydata(path):
    import vtk  # noqa: PLC0415 (imported late: --help works without VTK)

    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        fail(f"cannot read {path}")
    return r.GetOutput()


def field_data_strings(pd, name):
    a = pd.GetFieldData().GetAbstractArray(name)
    if a is None:
        return []
    return [a.GetValue(i) for i in range(a.GetNumberOfValues())]


def time_of(pd):
    a = pd.GetFieldData().GetArray("TimeValue")
    return a.GetTuple1(0) if a is not None else None


def unit_of(pd, name):
    for line in field_data_strings(pd, "fieldDescriptions"):
        m = re.match(r"(\S+) \[([^\]]*)\]", line)
        if m and m.group(1) == name:
            return m.group(2)
    return ""


def list_arrays(pd):
    pt = pd.GetPointData()
    print(f"{pd.GetNumberOfPoints()} particles, time {time_of(pd)}")
    for i in range(pt.GetNumberOfArrays()):
        a = pt.GetAbstractArray(i)
        comps = a.GetNumberOfComponents()
        names = COMPONENT_NAMES.get(comps, [])
        unit = unit_of(pd, a.GetName())
        print(f"  {a.GetName():24s} {comps} component(s) {' '.join(names)}  [{unit or '-'}]")


def pick_values(pd, field, component):
    """Values to colour by (a list of floats) and a label, from --field/--component.

    `field` may carry the component as a suffix (stress_yy, velocity_x)."""
    import numpy as np
    from vtk.util.numpy_support import vtk_to_numpy

    pt = pd.GetPointData()
    if pt.GetArray(field) is None and component is None and "_" in field:
        base, _, comp = field.rpartition("_")
        if pt.GetArray(base) is not None:
            field, component = base, comp
    arr = pt.GetArray(field)
    if arr is None:
        names = [pt.GetArrayName(i) for i in range(pt.GetNumberOfArrays())]
        fail(f"no point array '{field}'; the file has: {', '.join(names)} "
             "(components as name_xx / --component)")
    data = vtk_to_numpy(arr).astype(float)
    comps = arr.GetNumberOfComponents()
    unit = unit_of(pd, field)
    if comps == 1:
        values, label = data, field
    else:
        data = data.reshape(-1, comps)
        names = COMPONENT_NAMES.get(comps, [str(i) for i in range(comps)])
        if component is None:
            component = "magnitude" if comps == 3 else names[0]
        c = str(component)
        if c.lower() in ("mag", "magnitude"):
            values, label = np.linalg.norm(data, axis=1), f"|{field}|"
        else:
            key = ALIASES.get(c.upper(), c.upper())
            if key in names:
                k = names.index(key)
            elif c.isdigit() and int(c) < comps:
                k = int(c)
            else:
                fail(f"'{field}' has components {' '.join(names)}; no component '{component}'")
            values, label = data[:, k], f"{field}_{names[k].lower()}"
    if unit:
        label += f" [{unit}]"
    return values, label


def particle_size(pd, dim):
    """Diameter of a particle disc: from `volume` (area per unit thickness in 2D)."""
    from vtk.util.numpy_support import vtk_to_numpy

    vol = pd.GetPointData().GetArray("volume")
    if vol is not None and vol.GetNumberOfTuples() > 0:
        v = float(vtk_to_numpy(vol).mean())
        if v > 0:
            return v ** (1.0 / dim)
    b = pd.GetBounds()
    ext = [b[1] - b[0], b[3] - b[2], b[5] - b[4]]
    area = max(ext[0], 1e-12) * max(ext[1], 1e-12)
    return math.sqrt(area / max(pd.GetNumberOfPoints(), 1))


def dimension_of(pd):
    b = pd.GetBounds()
    return 2 if abs(b[5] - b[4]) < 1e-12 * max(1.0, abs(b[1] - b[0]), abs(b[3] - b[2])) else 3


def value_range(values, given):
    if given:
        return given
    lo, hi = float(min(values)), float(max(values))
    if lo == hi:
        lo, hi = lo - 0.5 * max(abs(lo), 1.0), hi + 0.5 * max(abs(hi), 1.0)
    return lo, hi


def title_text(args, t):
    if args.title is not None:
        return args.title
    return f"t = {t:.4g} s" if t is not None else ""


# ----------------------------------------------------------------------------- VTK


def needs_x_server():
    import vtk

    rw = vtk.vtkRenderWindow()
    return rw.GetClassName() == "vtkXOpenGLRenderWindow"


def render_vtk(pd, values, label, args, t):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    dim = dimension_of(pd)
    d = particle_size(pd, dim) * args.scale
    colour = numpy_to_vtk(values.astype(float), deep=True)
    colour.SetName("colour")
    pts = vtk.vtkPolyData()
    pts.SetPoints(pd.GetPoints())
    pts.GetPointData().SetScalars(colour)

    if dim == 2:
        src = vtk.vtkRegularPolygonSource()
        src.SetNumberOfSides(16)
        src.SetRadius(0.5 * d)
    else:
        src = vtk.vtkSphereSource()
        src.SetRadius(0.5 * d)
        src.SetThetaResolution(10)
        src.SetPhiResolution(8)
    glyph = vtk.vtkGlyph3D()
    glyph.SetInputData(pts)
    glyph.SetSourceConnection(src.GetOutputPort())
    glyph.SetScaleModeToDataScalingOff()
    glyph.SetColorModeToColorByScalar()
    glyph.OrientOff()

    lo, hi = value_range(values, args.range)
    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    try:
        import matplotlib

        cmap = matplotlib.colormaps[args.cmap]
        for i in range(256):
            r, g, b, _ = cmap(i / 255.0)
            lut.SetTableValue(i, r, g, b, 1.0)
    except (ImportError, KeyError):
        lut.SetHueRange(0.667, 0.0)
    lut.SetTableRange(lo, hi)
    lut.Build()

    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(glyph.GetOutputPort())
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(lo, hi)
    mapper.SetScalarModeToUsePointData()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)

    # Two panels: the particles (left) and the colour bar with the time (right).
    split = 0.72
    ren = vtk.vtkRenderer()
    ren.SetBackground(1, 1, 1)
    ren.SetViewport(0.0, 0.0, split, 1.0)
    ren.AddActor(actor)
    side = vtk.vtkRenderer()
    side.SetBackground(1, 1, 1)
    side.SetViewport(split, 0.0, 1.0, 1.0)
    side.InteractiveOff()

    font = max(12, args.size[1] // 50)
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(label)
    bar.SetNumberOfLabels(6)
    bar.SetLabelFormat("%-.4g")
    bar.UnconstrainedFontSizeOn()
    bar.SetBarRatio(0.25)
    bar.SetTextPad(4)
    for tp in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        tp.SetColor(0, 0, 0)
        tp.ItalicOff()
        tp.BoldOff()
        tp.ShadowOff()
        tp.SetFontSize(font)
    bar.SetPosition(0.08, 0.08)
    bar.SetWidth(0.85)
    bar.SetHeight(0.78)
    side.AddActor2D(bar)

    text = title_text(args, t)
    if text:
        ta = vtk.vtkTextActor()
        ta.SetInput(text)
        ta.GetTextProperty().SetColor(0, 0, 0)
        ta.GetTextProperty().SetFontSize(int(font * 1.2))
        ta.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        ta.SetPosition(0.08, 0.93)
        side.AddActor2D(ta)

    cam = ren.GetActiveCamera()
    b = pd.GetBounds()
    centre = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
    if dim == 2:
        w, h = b[1] - b[0] + d, b[3] - b[2] + d
        aspect = split * args.size[0] / args.size[1]
        cam.ParallelProjectionOn()
        cam.SetFocalPoint(*centre)
        cam.SetPosition(centre[0], centre[1], centre[2] + 10 * max(w, h))
        cam.SetViewUp(0, 1, 0)
        ren.ResetCameraClippingRange()
        cam.SetParallelScale(0.53 * max(h, w / aspect))
    else:
        cam.SetFocalPoint(*centre)
        cam.SetPosition(centre[0] + 1, centre[1] - 2, centre[2] + 1)
        cam.SetViewUp(0, 0, 1)
        ren.ResetCamera()

    rw = vtk.vtkRenderWindow()
    rw.SetOffScreenRendering(1)
    rw.SetSize(*args.size)
    rw.AddRenderer(ren)
    rw.AddRenderer(side)
    rw.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(rw)
    grab.ReadFrontBufferOff()
    grab.Update()
    w = vtk.vtkPNGWriter()
    w.SetFileName(args.output)
    w.SetInputConnection(grab.GetOutputPort())
    w.Write()


# ----------------------------------------------------------------------------- matplotlib


def render_matplotlib(pd, values, label, args, t):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.collections import EllipseCollection
    from vtk.util.numpy_support import vtk_to_numpy

    xyz = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    dim = dimension_of(pd)
    d = particle_size(pd, dim) * args.scale
    lo, hi = value_range(values, args.range)
    dpi = 100
    fig, ax = plt.subplots(figsize=(args.size[0] / dpi, args.size[1] / dpi), dpi=dpi)
    widths = np.full(len(xyz), d)
    coll = EllipseCollection(widths, widths, np.zeros(len(xyz)), units="xy", offsets=xyz[:, :2],
                             offset_transform=ax.transData, cmap=args.cmap)
    coll.set_array(np.asarray(values))
    coll.set_clim(lo, hi)
    ax.add_collection(coll)
    pad = d
    ax.set_xlim(xyz[:, 0].min() - pad, xyz[:, 0].max() + pad)
    ax.set_ylim(xyz[:, 1].min() - pad, xyz[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    text = title_text(args, t)
    if text:
        ax.set_title(text)
    fig.colorbar(coll, ax=ax, label=label)
    fig.tight_layout()
    fig.savefig(args.output, dpi=dpi)
    plt.close(fig)


# ----------------------------------------------------------------------------- main


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", help="a .vtp file, or a .pvd series (renders its last step, or --index)")
    p.add_argument("-o", "--output", help="PNG file to write (default: the input's name with .png)")
    p.add_argument("-f", "--field", default="pressure",
                   help="point array to colour by (default: pressure); name_xx selects a component")
    p.add_argument("-c", "--component",
                   help="component: X Y Z, XX YY ZZ XY YZ XZ, an index, or magnitude (vectors' default)")
    p.add_argument("--index", type=int, help="step of a .pvd series (0 = first, -1 = last; default last)")
    p.add_argument("--range", type=float, nargs=2, metavar=("MIN", "MAX"), help="colour range")
    p.add_argument("--cmap", default="viridis", help="matplotlib colour map name (default viridis)")
    p.add_argument("--size", type=int, nargs=2, default=[900, 1200], metavar=("W", "H"),
                   help="image size in pixels (default 900 1200)")
    p.add_argument("--scale", type=float, default=1.0, help="particle size factor (default 1)")
    p.add_argument("--title", help="text at the top (default: the time)")
    p.add_argument("--matplotlib", action="store_true", help="draw with matplotlib instead of VTK")
    p.add_argument("--list", action="store_true", help="list the point arrays of the file and exit")
    args = p.parse_args(argv)

    path, t = resolve_input(args.input, args.index)
    pd = read_polydata(path)
    if args.list:
        list_arrays(pd)
        return 0
    if t is None:
        t = time_of(pd)
    if pd.GetNumberOfPoints() == 0:
        fail(f"{path} has no particles")
    values, label = pick_values(pd, args.field, args.component)
    if not args.output:
        args.output = os.path.splitext(path)[0] + ".png"

    if args.matplotlib:
        render_matplotlib(pd, values, label, args, t)
    else:
        if needs_x_server() and not os.environ.get("DISPLAY"):
            # Debian's VTK renders through GLX: restart under a virtual X server.
            if os.environ.get("SCREE_RENDER_UNDER_XVFB"):
                fail("no X display even under xvfb-run; use --matplotlib")
            xvfb = shutil.which("xvfb-run")
            if not xvfb:
                fail("VTK needs an X display for rendering and xvfb-run is not installed "
                     "(apt-get install xvfb), or use --matplotlib")
            env = dict(os.environ, SCREE_RENDER_UNDER_XVFB="1")
            os.execve(xvfb, [xvfb, "-a", "-s", "-screen 0 1920x1080x24", sys.executable,
                             os.path.abspath(__file__)] + argv, env)
        render_vtk(pd, values, label, args, t)
    print(f"render_vtp: wrote {args.output} ({pd.GetNumberOfPoints()} particles, {label})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

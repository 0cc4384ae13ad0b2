#!/usr/bin/python3
"""A plan view and a side view of a 3D Scree run's particles, read with numpy alone.

For runs too large for ParaView on the machine at hand (a frame of 2.5e8 points is some
9 GB): reads a frame of the vtk writer's binary output (a .pvtp and its pieces, a .vtp, or
the last frame of a .pvd, or the one nearest --time), raw or zlib-compressed, Float32 or
Float64, without VTK, and draws

  - the plan (x, y): for each bin, the largest speed |v| of the points in it;
  - the side (x, z): the points seen across y, coloured by speed (at most --sample of
    them, an even subsample), over the ground's profile along the valley's axis where
    --ground names the STL solid of a terrain condition.

    plan_view.py case/VTK/particles.pvd out.png [--time 2.0] [--bin 0.1] [--ground
        case/constant/triSurface/valley.stl] [--axis-y 6.0] [--sample 2000000]

Needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib).
"""
import argparse
import os
import re
import struct
import sys
import xml.etree.ElementTree as ET
import zlib

import numpy as np

TYPES = {"Float32": np.float32, "Float64": np.float64, "Int32": np.int32, "Int64": np.int64,
         "UInt8": np.uint8, "UInt32": np.uint32, "UInt64": np.uint64}


def fail(msg):
    sys.exit("plan_view.py: " + msg)


def frame_of(path, time):
    """The .pvtp/.vtp of a .pvd at `time` (None: the last), or `path` itself."""
    if not path.endswith(".pvd"):
        return path, None
    sets = [(float(d.get("timestep")), d.get("file")) for d in ET.parse(path).getroot().iter("DataSet")]
    if not sets:
        fail(f"{path} lists no frame")
    t, f = min(sets, key=lambda s: abs(s[0] - time)) if time is not None else sets[-1]
    return os.path.join(os.path.dirname(path), f), t


def pieces_of(path):
    if path.endswith(".pvtp"):
        root = ET.parse(path).getroot()
        return [os.path.join(os.path.dirname(path), p.get("Source")) for p in root.iter("Piece")]
    return [path]


def read_vtp(path, names):
    """{name: array} of the Points (as 'Points') and the named point arrays of one piece."""
    with open(path, "rb") as f:
        data = f.read()
    start = data.find(b"<AppendedData")
    if start < 0:
        fail(f"{path}: no appended data (write with `format binary`)")
    mark = data.index(b"_", start) + 1
    head = data[:start].decode("utf-8", "replace") + "</VTKFile>"
    head = re.sub(r"<AppendedData[^>]*>", "", head)
    root = ET.fromstring(head.split("?>", 1)[-1] if head.startswith("<?xml") else head)
    compressed = root.get("compressor") is not None
    if root.get("header_type", "UInt32") != "UInt64":
        fail(f"{path}: expected header_type UInt64 (Scree's writer)")
    n = int(root.find(".//Piece").get("NumberOfPoints"))
    out = {}
    for arr in root.iter("DataArray"):
        name = arr.get("Name")
        parent_points = arr in list(root.find(".//Points"))
        key = "Points" if parent_points else name
        if key not in names:
            continue
        dtype = TYPES[arr.get("type")]
        comps = int(arr.get("NumberOfComponents", "1"))
        off = mark + int(arr.get("offset"))
        if not compressed:
            size = struct.unpack_from("<Q", data, off)[0]
            raw = data[off + 8:off + 8 + size]
        else:
            blocks = struct.unpack_from("<Q", data, off)[0]
            sizes = struct.unpack_from(f"<{blocks}Q", data, off + 24)
            pos = off + 24 + 8 * blocks
            parts = []
            for s in sizes:
                parts.append(zlib.decompress(data[pos:pos + s]))
                pos += s
            raw = b"".join(parts)
        out[key] = np.frombuffer(raw, dtype=dtype).reshape(n, comps) if comps > 1 else np.frombuffer(raw, dtype=dtype)
    return out


def ground_top(stl):
    """The vertices (x, y, z) of the upward-facing triangles of a binary STL solid: its top."""
    with open(stl, "rb") as f:
        f.seek(80)
        count = struct.unpack("<I", f.read(4))[0]
        rec = np.frombuffer(f.read(50 * count), dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    up = rec["n"][:, 2] > 0.05
    return np.unique(rec["v"][up].reshape(-1, 3), axis=0)


def ground_profile(top, y0):
    """The ground's top along the line of vertices nearest y = y0: (x, z)."""
    near = np.abs(top[:, 1] - y0) <= np.min(np.abs(top[:, 1] - y0)) + 1e-6
    x, z = top[near, 0], top[near, 2]
    order = np.argsort(x)
    return x[order], z[order]


def main(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", help=".pvd, .pvtp or .vtp")
    p.add_argument("output", help="PNG")
    p.add_argument("--time", type=float, help="the frame nearest this time (a .pvd; default: the last)")
    p.add_argument("--bin", type=float, default=0.1, help="plan bin size [m]")
    p.add_argument("--ground", help="the terrain's STL solid (binary), for the side view's ground line")
    p.add_argument("--axis-y", type=float, help="y of the side view's ground line (default: the points' mean y)")
    p.add_argument("--sample", type=int, default=2000000, help="points drawn in the side view")
    p.add_argument("--title", default="")
    a = p.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frame, t = frame_of(a.input, a.time)
    xs, speeds = [], []
    for piece in pieces_of(frame):
        d = read_vtp(piece, {"Points", "velocity"})
        if "velocity" not in d:
            fail(f"{piece}: no velocity array (the writer's fields must include velocity)")
        xs.append(d["Points"].astype(np.float32))
        speeds.append(np.linalg.norm(d["velocity"].astype(np.float32), axis=1))
    x = np.concatenate(xs)
    s = np.concatenate(speeds)
    n = len(s)
    lo, hi = x.min(axis=0), x.max(axis=0)
    top = ground_top(a.ground) if a.ground else None
    if top is not None:  # the plan over the whole ground
        lo[:2], hi[:2] = np.minimum(lo[:2], top[:, :2].min(axis=0)), np.maximum(hi[:2], top[:, :2].max(axis=0))
    nx = max(1, int(np.ceil((hi[0] - lo[0]) / a.bin)))
    ny = max(1, int(np.ceil((hi[1] - lo[1]) / a.bin)))
    ix = np.minimum(((x[:, 0] - lo[0]) / a.bin).astype(np.int64), nx - 1)
    iy = np.minimum(((x[:, 1] - lo[1]) / a.bin).astype(np.int64), ny - 1)
    plan = np.full(nx * ny, np.nan, dtype=np.float32)
    flat = iy * nx + ix
    if n:  # the largest per bin: sorted by bin once (np.fmax.at is slow on 1e8 items)
        order = np.argsort(flat)
        f, v = flat[order], s[order]
        starts = np.flatnonzero(np.r_[True, f[1:] != f[:-1]])
        plan[f[starts]] = np.maximum.reduceat(v, starts)
    plan = plan.reshape(ny, nx)
    vmax = float(np.nanmax(plan)) if n else 1.0

    fig, ax = plt.subplots(2, 1, figsize=(12, 8.5), gridspec_kw={"height_ratios": [1, 1]})
    im = ax[0].imshow(plan, origin="lower", extent=[lo[0], lo[0] + nx * a.bin, lo[1], lo[1] + ny * a.bin],
                      cmap="viridis", vmin=0, vmax=vmax, interpolation="nearest", aspect="equal")
    if top is not None:  # the ground's contours, every 0.5 m
        ax[0].tricontour(top[:, 0], top[:, 1], top[:, 2], levels=np.arange(0.25, top[:, 2].max(), 0.5), colors="0.55",
                         linewidths=0.4)
    ax[0].set_xlabel("x [m] (down the valley)")
    ax[0].set_ylabel("y [m]")
    ax[0].set_title(f"plan: the largest speed in each {a.bin:g} m bin" + (", ground contours every 0.5 m" if top is not None else ""))
    fig.colorbar(im, ax=ax[0], label="|v| [m/s]", shrink=0.8)
    step = max(1, n // max(1, a.sample))
    order = np.argsort(s[::step])
    ax[1].scatter(x[::step, 0][order], x[::step, 2][order], c=s[::step][order], s=0.2, cmap="viridis", vmin=0,
                  vmax=vmax, rasterized=True)
    if top is not None:
        gx, gz = ground_profile(top, a.axis_y if a.axis_y is not None else float(x[:, 1].mean()))
        ax[1].plot(gx, gz, "k-", lw=1, label="ground along the valley's axis")
        ax[1].legend(loc="upper right")
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("x [m]")
    ax[1].set_ylabel("z [m]")
    ax[1].set_title("side: every point, seen across y" if step == 1 else f"side: one point in {step}, seen across y")
    when = f"t = {t:g} s, " if t is not None else ""
    fig.suptitle(f"{a.title}{' - ' if a.title else ''}{when}{n:,} points")
    fig.tight_layout()
    fig.savefig(a.output, dpi=130)
    print(f"{a.output}: {when}{n} points, x {lo[0]:.3f}..{hi[0]:.3f}, y {lo[1]:.3f}..{hi[1]:.3f}, "
          f"z {lo[2]:.3f}..{hi[2]:.3f} m, largest speed {vmax:.3f} m/s")


if __name__ == "__main__":
    main(sys.argv[1:])

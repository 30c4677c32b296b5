#!/usr/bin/python3
"""Rasterise an OpenSCAD file the way csgfit rasterises its trees, to check a .scad export.

OpenSCAD renders the file (2D: exported as SVG; extruded: exported as STL, then cut through the
middle with projection(cut=true) and exported as SVG), the SVG outline is filled with the
even-odd rule and sampled at pixel centres: pixel (col, row) of a W x H canvas with pixel size s
has its centre at ((col + 0.5) * s, (H - row - 0.5) * s) in model units, y up (csgfit's
ARCHITECTURE.md), row 0 at the top of the returned array.

Library use (scripts/ on sys.path):
    import scad_raster
    mask = scad_raster.rasterize_scad("part.scad", width=128, height=128, pixel_size=0.5)
    agreement = scad_raster.agreement(mask, scad_raster.read_mask("part.png"))

CLI:
    scad_raster.py part.scad --width 128 --height 128 --pixel-size 0.5 \\
        [--thickness 3] [--compare solver.png] [--min-agreement 0.995] [--out mask.pbm]

Only numpy is needed (python3-numpy); run with /usr/bin/python3.
"""

import argparse
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

import numpy as np

__all__ = [
    "OpenScadError", "find_openscad", "define_args", "render_svg", "parse_svg_path",
    "parse_svg_paths", "rasterize_polygons", "rasterize_scad", "read_mask", "write_pbm",
    "agreement", "png_chunks", "png_unfilter",
]


class OpenScadError(RuntimeError):
    """OpenSCAD is missing or failed on the file."""


def find_openscad():
    """Path of the openscad executable, or None."""
    return shutil.which("openscad")


def _run_openscad(args, timeout):
    exe = find_openscad()
    if exe is None:
        raise OpenScadError("openscad is not installed")
    proc = subprocess.run([exe] + args, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        lines = [l for l in proc.stderr.splitlines() if "ERROR" in l or "WARNING" in l]
        raise OpenScadError("openscad %s failed: %s" % (
            " ".join(args), "; ".join(lines) or proc.stderr.strip()[-500:]))
    return proc.stderr


def define_args(defines):
    """OpenSCAD's -D arguments for {name: value} (numbers as %r, so 0.25 stays 0.25)."""
    out = []
    for name, value in (defines or {}).items():
        out += ["-D", "%s=%r" % (name, value)]
    return out


_THICKNESS_RE = re.compile(r"^\s*thickness\s*=\s*([-+0-9.eE]+)\s*;", re.M)


def render_svg(scad_path, thickness=None, timeout=300, defines=None):
    """Renders scad_path with OpenSCAD and returns the SVG text of its 2D outline.

    A 3D (extruded) file is exported as STL and cut in the middle of its height; the height is
    `thickness`, or read from the file's `thickness = ...;` line when not given. `defines`
    ({name: value}) are passed as OpenSCAD -D name=value (e.g. a morph's frame).
    """
    scad_path = os.path.abspath(scad_path)
    dargs = define_args(defines)
    with tempfile.TemporaryDirectory(prefix="scad_raster_") as tmp:
        svg = os.path.join(tmp, "out.svg")
        if not thickness:
            try:
                _run_openscad(dargs + ["-o", svg, scad_path], timeout)
                with open(svg, encoding="utf-8") as f:
                    return f.read()
            except OpenScadError as e:
                if "top level object is empty" in str(e):
                    return ""  # OpenSCAD refuses to export nothing; nothing is a valid shape
                if "not a 2D object" not in str(e):
                    raise
                with open(scad_path, encoding="utf-8") as f:
                    m = _THICKNESS_RE.search(f.read())
                if not m:
                    raise OpenScadError(
                        "%s is 3D and its thickness is unknown (pass thickness)" % scad_path)
                thickness = float(m.group(1))
        # The cut goes through the middle of the extrusion, where a linear_extrude of the 2D
        # shape has exactly that shape, far from the top and bottom faces.
        stl = os.path.join(tmp, "solid.stl")
        _run_openscad(dargs + ["-o", stl, scad_path], timeout)
        wrapper = os.path.join(tmp, "cut.scad")
        with open(wrapper, "w", encoding="utf-8") as f:
            f.write('projection(cut = true) translate([0, 0, %r]) import("%s");\n'
                    % (-float(thickness) / 2, stl.replace("\\", "/")))
        try:
            _run_openscad(["-o", svg, wrapper], timeout)
        except OpenScadError as e:
            if "top level object is empty" in str(e):
                return ""
            raise
        with open(svg, encoding="utf-8") as f:
            return f.read()


_PATH_RE = re.compile(r'<path[^>]*?\sd="([^"]*)"', re.S)
PATH_TOKEN_RE = re.compile(r"[MmLlHhVvCcSsQqZz]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
PARAM_COUNT = {"M": 2, "L": 2, "H": 1, "V": 1, "C": 6, "S": 4, "Q": 4, "Z": 0}


def _bezier_points(ctrl):
    """Flattens one Bezier (3 or 4 control points) into points after the first one."""
    ctrl = np.asarray(ctrl, dtype=np.float64)
    length = np.sum(np.hypot(*np.diff(ctrl, axis=0).T))
    n = int(min(256, max(8, math.ceil(length / 0.25))))  # <= 1/4 unit per chord
    t = np.linspace(0.0, 1.0, n + 1)[1:, None]
    if len(ctrl) == 3:
        p0, p1, p2 = ctrl
        return (1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t ** 2 * p2
    p0, p1, p2, p3 = ctrl
    return ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t ** 2 * p2
            + t ** 3 * p3)


def parse_svg_path(d):
    """Path data -> list of closed polylines (N x 2 arrays, path coordinates).

    Handles absolute and relative M L H V C S Q Z with implicit repetition, which covers what
    OpenSCAD (M, L, z) and potrace (M, l, c, m, z) write."""
    tokens = PATH_TOKEN_RE.findall(d)
    polys, cur = [], []
    x = y = 0.0
    start = (0.0, 0.0)
    last_ctrl = None
    cmd = None
    i = 0

    def close():
        nonlocal cur
        if len(cur) >= 3:
            polys.append(np.array(cur, dtype=np.float64))
        cur = []

    while i < len(tokens):
        tok = tokens[i]
        if tok.isalpha():
            cmd = tok
            i += 1
            if cmd in "Zz":
                close()
                x, y = start
                last_ctrl = None
                continue
        elif cmd is None:
            raise ValueError("path data starts with a number")
        n = PARAM_COUNT[cmd.upper()]
        args = [float(t) for t in tokens[i:i + n]]
        if len(args) < n:
            raise ValueError("truncated path data")
        i += n
        rel = cmd.islower()
        up = cmd.upper()
        if up == "M":
            close()
            x, y = (x + args[0], y + args[1]) if rel else (args[0], args[1])
            start = (x, y)
            cur = [(x, y)]
            cmd = "l" if rel else "L"  # implicit repetition after a moveto is a lineto
            last_ctrl = None
            continue
        if not cur:
            cur = [(x, y)]
        if up in "LHV":
            if up == "L":
                nx, ny = (x + args[0], y + args[1]) if rel else (args[0], args[1])
            elif up == "H":
                nx, ny = (x + args[0] if rel else args[0]), y
            else:
                nx, ny = x, (y + args[0] if rel else args[0])
            cur.append((nx, ny))
            x, y = nx, ny
            last_ctrl = None
        else:
            pts = [(args[k] + (x if rel else 0), args[k + 1] + (y if rel else 0))
                   for k in range(0, n, 2)]
            if up == "S":
                refl = (2 * x - last_ctrl[0], 2 * y - last_ctrl[1]) if last_ctrl else (x, y)
                pts = [refl] + pts
            ctrl = [(x, y)] + pts
            if up == "Q":
                ctrl = ctrl[:3]
            cur.extend(map(tuple, _bezier_points(ctrl)))
            last_ctrl = ctrl[-2]
            x, y = ctrl[-1]
    close()
    return polys


def parse_svg_paths(svg_text):
    """Closed polygons (lists of (x, y) in model units, y up) from OpenSCAD's SVG output.

    OpenSCAD 2021.01 writes one <path> of absolute M/L/z commands with y negated; the other
    commands of parse_svg_path are accepted too.
    """
    polygons = []
    for d in _PATH_RE.findall(svg_text):
        polygons += parse_svg_path(d)
    # SVG's y axis points down; OpenSCAD writes -y.
    return [[(px, -py) for (px, py) in poly] for poly in polygons]


def rasterize_polygons(polygons, width, height, pixel_size):
    """Even-odd fill of `polygons` sampled at pixel centres: bool array (height, width)."""
    mask = np.zeros((height, width), dtype=bool)
    if not polygons or width <= 0 or height <= 0:
        return mask
    x0 = []
    y0 = []
    x1 = []
    y1 = []
    for poly in polygons:
        p = np.asarray(poly, dtype=np.float64)
        q = np.roll(p, -1, axis=0)
        x0.append(p[:, 0]), y0.append(p[:, 1]), x1.append(q[:, 0]), y1.append(q[:, 1])
    x0, y0, x1, y1 = (np.concatenate(a) for a in (x0, y0, x1, y1))
    centres_x = (np.arange(width) + 0.5) * pixel_size
    for row in range(height):
        y = (height - row - 0.5) * pixel_size
        # Half-open rule: an edge counts when it crosses the line with one end strictly above.
        crosses = (y0 > y) != (y1 > y)
        if not crosses.any():
            continue
        ax, ay, bx, by = x0[crosses], y0[crosses], x1[crosses], y1[crosses]
        xs = np.sort(ax + (y - ay) * (bx - ax) / (by - ay))
        # Inside when an odd number of crossings lies to the left of the centre.
        mask[row] = (np.searchsorted(xs, centres_x, side="left") % 2) == 1
    return mask


def rasterize_scad(scad_path, width, height, pixel_size, thickness=None, timeout=300,
                   defines=None):
    """OpenSCAD's rendering of scad_path sampled at the canvas's pixel centres (row 0 on top);
    `defines` as for render_svg."""
    return rasterize_polygons(parse_svg_paths(render_svg(scad_path, thickness, timeout,
                                                         defines)),
                              width, height, pixel_size)


# ---- bitmaps ---------------------------------------------------------------------------------

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_chunks(data):
    """(kind, body) of every chunk of a PNG file's bytes, up to and with IEND."""
    if data[:8] != PNG_SIGNATURE:
        raise ValueError("not a PNG file")
    pos = 8
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        yield kind, data[pos + 8:pos + 8 + length]
        if kind == b"IEND":
            return
        pos += 12 + length


def png_unfilter(raw, height, stride, bpp):
    """Undoes the per-row filters of decompressed PNG data: (height, stride) uint8 bytes."""
    out = np.zeros((height, stride), dtype=np.uint8)
    prev = np.zeros(stride, dtype=np.int32)
    for r in range(height):
        f = raw[r * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=r * (stride + 1) + 1)
        line = line.astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + prev) & 0xFF
        else:  # Sub, Average, Paeth depend on the left neighbour: byte by byte
            cur = np.zeros(stride, dtype=np.int32)
            for i in range(stride):
                a = cur[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                if f == 1:
                    pred = a
                elif f == 3:
                    pred = (a + b) // 2
                elif f == 4:
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                else:
                    raise ValueError("bad PNG filter %d" % f)
                cur[i] = (line[i] + pred) & 0xFF
        out[r] = cur
        prev = cur
    return out


def _read_png(data):
    idat = []
    header = None
    palette = None
    for kind, chunk in png_chunks(data):
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif kind == b"PLTE":
            palette = np.frombuffer(chunk, dtype=np.uint8).reshape(-1, 3)
        elif kind == b"IDAT":
            idat.append(chunk)
    if header is None:
        raise ValueError("PNG without IHDR")
    w, h, depth, colour, _, _, interlace = header
    if interlace:
        raise ValueError("interlaced PNG is not supported")
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[colour]
    bits = depth * channels
    stride = (w * bits + 7) // 8
    bpp = max(1, bits // 8)
    out = png_unfilter(zlib.decompress(b"".join(idat)), h, stride, bpp)
    if depth < 8:
        bitsarr = np.unpackbits(out, axis=1)[:, : w * depth]
        vals = bitsarr.reshape(h, w, depth).dot(1 << np.arange(depth - 1, -1, -1))
        samples = vals.reshape(h, w, 1)
        scale = 255 // ((1 << depth) - 1)
    elif depth == 16:
        samples = out.reshape(h, w, channels, 2)[..., 0].astype(np.int64)
        scale = 1
    else:
        samples = out.reshape(h, w, channels).astype(np.int64)
        scale = 1
    if colour == 3:
        rgb = palette[samples[..., 0]]
        grey = rgb.mean(axis=2)
        alpha = None
    else:
        samples = samples * scale
        grey = samples[..., 0] if channels <= 2 else samples[..., :3].mean(axis=2)
        alpha = samples[..., -1] if channels in (2, 4) else None
    return grey, alpha


def _read_pnm(data):
    # P1/P4 (bit: 1 = black = shape) and P2/P5 (grey).
    tokens = []
    pos = 2
    magic = data[:2]
    need = 2 if magic in (b"P1", b"P4") else 3
    while len(tokens) < need:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while data[pos:pos + 1] not in (b"\n", b""):
                pos += 1
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        tokens.append(int(data[start:pos]))
    w, h = tokens[0], tokens[1]
    if magic == b"P4":
        pos += 1
        rows = np.frombuffer(data, dtype=np.uint8, count=h * ((w + 7) // 8), offset=pos)
        bits = np.unpackbits(rows.reshape(h, -1), axis=1)[:, :w]
        return np.where(bits == 1, 0, 255), None
    if magic == b"P1":
        vals = [int(c) for c in data[pos:].decode("ascii") if c in "01"]
        return np.where(np.array(vals[: w * h]).reshape(h, w) == 1, 0, 255), None
    maxval = tokens[2]
    if magic == b"P5":
        pos += 1
        dtype = np.uint8 if maxval < 256 else np.dtype(">u2")
        grey = np.frombuffer(data, dtype=dtype, count=w * h, offset=pos).reshape(h, w)
    else:
        grey = np.array(data[pos:].split()[: w * h], dtype=np.int64).reshape(h, w)
    return grey.astype(np.float64) * 255.0 / maxval, None


def read_mask(path, invert=False, threshold=128):
    """Shape pixels of a PNG, PBM or PGM file: dark (< threshold) and opaque, as csgfit reads
    images; `invert` makes light pixels the shape. Returns bool array (height, width)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] == PNG_SIGNATURE:
        grey, alpha = _read_png(data)
    elif data[:2] in (b"P1", b"P2", b"P4", b"P5"):
        grey, alpha = _read_pnm(data)
    else:
        raise ValueError("%s: not a PNG, PBM or PGM file" % path)
    mask = grey >= threshold if invert else grey < threshold
    if alpha is not None:
        mask &= alpha >= 128
    return mask


def write_pbm(path, mask):
    """Writes a bool mask as binary PBM (shape black)."""
    mask = np.asarray(mask, dtype=bool)
    h, w = mask.shape
    with open(path, "wb") as f:
        f.write(b"P4\n%d %d\n" % (w, h))
        f.write(np.packbits(mask, axis=1).tobytes())


def agreement(a, b):
    """Fraction of pixels on which two masks of the same shape agree."""
    a = np.asarray(a, dtype=bool)
    b = np.asarray(b, dtype=bool)
    if a.shape != b.shape:
        raise ValueError("masks differ in size: %s vs %s" % (a.shape, b.shape))
    return float((a == b).mean()) if a.size else 1.0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scad")
    ap.add_argument("--width", type=int, required=True, help="canvas width in pixels")
    ap.add_argument("--height", type=int, required=True, help="canvas height in pixels")
    ap.add_argument("--pixel-size", type=float, default=1.0, help="model units per pixel")
    ap.add_argument("--thickness", type=float, default=None,
                    help="extrusion height of a 3D file (default: read from the file)")
    ap.add_argument("--out", help="write OpenSCAD's raster as PBM")
    ap.add_argument("--compare", help="reference bitmap (PNG/PBM/PGM, dark = shape)")
    ap.add_argument("--invert", action="store_true", help="light pixels of --compare are shape")
    ap.add_argument("--min-agreement", type=float, default=None,
                    help="exit 1 when the agreement with --compare is below this fraction")
    ap.add_argument("--timeout", type=float, default=300)
    args = ap.parse_args(argv)
    try:
        mask = rasterize_scad(args.scad, args.width, args.height, args.pixel_size,
                              args.thickness, args.timeout)
    except OpenScadError as e:
        print("scad_raster: %s" % e, file=sys.stderr)
        return 77 if find_openscad() is None else 2
    if args.out:
        write_pbm(args.out, mask)
    if not args.compare:
        print("pixels %d of %d" % (int(mask.sum()), mask.size))
        return 0
    ref = read_mask(args.compare, invert=args.invert)
    if ref.shape != mask.shape:
        print("scad_raster: %s is %dx%d, canvas is %dx%d" % (
            args.compare, ref.shape[1], ref.shape[0], args.width, args.height), file=sys.stderr)
        return 2
    a = agreement(mask, ref)
    print("agreement %.6f (%d of %d pixels differ; openscad %d, reference %d shape pixels)" % (
        a, int((mask != ref).sum()), mask.size, int(mask.sum()), int(ref.sum())))
    if args.min_agreement is not None and a < args.min_agreement:
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

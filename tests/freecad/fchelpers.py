"""Shared helpers of the FreeCAD tests: locating FreeCAD, the built csgfit module and the
benchmarks, rasterising a section of a solid, and an independent CSG evaluation of a JSON tree
with plain Part shapes (to check what the parametric tree computes)."""

import contextlib
import math
import os
import shutil
import subprocess
import sys

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("CSGFIT_BUILD_DIR", os.path.join(REPO, "build"))
BENCH = os.path.join(os.path.dirname(REPO), "shared", "benchmarks", "2d")
FREECAD_LIB = "/usr/lib/freecad-python3/lib"
# FreeCAD's PySide shim, which the workbench imports Qt through; FreeCAD puts it on its own path.
FREECAD_QT_SHIM = "/usr/share/freecad/Ext"
WORKBENCH = os.path.join(REPO, "freecad_workbench")
#: The workbench's headless JSON -> .FCStd writer, which `csgfit ... -o part.FCStd` runs.
FCSTD_WRITER = os.path.join(WORKBENCH, "csgfit_freecad", "fcstd_writer.py")

if FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)
# Importing FreeCAD puts the user's installed modules first on sys.path, and an installed CSG
# Fit workbench (scripts/install_workbench.sh) may link another checkout: FreeCAD comes first,
# then this checkout's workbench goes before it, so that the tests test the code beside them.
try:
    import FreeCAD  # noqa: F401
except ImportError:
    pass
if WORKBENCH in sys.path:
    sys.path.remove(WORKBENCH)
sys.path.insert(0, WORKBENCH)
if os.path.join(BUILD, "python") not in sys.path:
    sys.path.insert(0, os.path.join(BUILD, "python"))


def section_mask(shape, width, height, pixel_size, z):
    """Pixel-centre raster (bool, row 0 at the top) of the section of `shape` at height z:
    the section's wires, finely discretised, filled with the even-odd rule."""
    import FreeCAD as App

    s = pixel_size
    polys = []
    for wire in shape.slice(App.Vector(0, 0, 1), z):
        pts = np.array([(p.x, p.y) for p in wire.discretize(Deflection=s * 1e-3)])
        if len(pts) >= 3:
            polys.append(pts)
    xs = (np.arange(width) + 0.5) * s
    mask = np.zeros((height, width), bool)
    if not polys:
        return mask
    x1 = np.concatenate([p[:, 0] for p in polys])
    y1 = np.concatenate([p[:, 1] for p in polys])
    x2 = np.concatenate([np.roll(p[:, 0], -1) for p in polys])
    y2 = np.concatenate([np.roll(p[:, 1], -1) for p in polys])
    for row in range(height):
        y = (height - row - 0.5) * s
        cross = (y1 > y) != (y2 > y)
        if not cross.any():
            continue
        xi = x1[cross] + (y - y1[cross]) * (x2[cross] - x1[cross]) / (y2[cross] - y1[cross])
        xi.sort()
        # Odd number of crossings to the right = inside.
        mask[row] = (len(xi) - np.searchsorted(xi, xs)) % 2 == 1
    return mask


def iou(a, b):
    a, b = np.asarray(a, bool), np.asarray(b, bool)
    union = np.logical_or(a, b).sum()
    return 1.0 if union == 0 else float(np.logical_and(a, b).sum() / union)


def combine(op, shapes):
    """The CSG operator `op` of Part shapes: union, intersection, or the first minus the rest."""
    if len(shapes) == 1:
        return shapes[0]
    if op == "union":
        return shapes[0].fuse(shapes[1:]).removeSplitter()
    if op == "intersection":
        out = shapes[0]
        for s in shapes[1:]:
            out = out.common(s)
        return out
    return shapes[0].cut(shapes[1:])


def static_shape(node, thickness):
    """The solid of a JSON tree (model units) built directly with Part's functions: an
    evaluation independent of the builder's parametric objects."""
    import FreeCAD as App
    import Part

    z = App.Vector(0, 0, 1)
    if "op" in node:
        return combine(node["op"], [static_shape(c, thickness) for c in node["children"]])
    t = node["type"]
    cx, cy = node["cx"], node["cy"]
    a = math.radians(node.get("angle", 0.0))
    c, s = math.cos(a), math.sin(a)

    def local(x, y):
        return App.Vector(cx + c * x - s * y, cy + s * x + c * y, 0)

    if t in ("rectangle", "rect"):
        w, h = node["w"], node["h"]
        pts = [local(-w / 2, -h / 2), local(w / 2, -h / 2), local(w / 2, h / 2),
               local(-w / 2, h / 2)]
    elif t == "triangle":
        w, h, apex = node["w"], node["h"], node.get("apex", 0.0)
        pts = [local(-w / 2, -h / 2), local(w / 2, -h / 2), local(apex * w / 2, h / 2)]
    elif t == "circle":
        return Part.makeCylinder(node["r"], thickness, App.Vector(cx, cy, 0), z)
    elif t == "ellipse":
        rx, ry = node["rx"], node["ry"]
        major, minor, ang = (rx, ry, a) if rx >= ry else (ry, rx, a + math.pi / 2)
        e = Part.Ellipse(App.Vector(0, 0, 0), major, minor)
        face = Part.Face(Part.Wire(e.toShape()))
        face.rotate(App.Vector(0, 0, 0), z, math.degrees(ang))
        face.translate(App.Vector(cx, cy, 0))
        return face.extrude(z * thickness)
    else:
        raise ValueError(t)
    face = Part.Face(Part.makePolygon(pts + [pts[0]]))
    return face.extrude(z * thickness)


def components(mask):
    """Number of 4-connected components of a bool mask."""
    m = np.asarray(mask, bool)
    h, w = m.shape
    seen = np.zeros_like(m)
    n = 0
    for r0, c0 in zip(*np.nonzero(m)):
        if seen[r0, c0]:
            continue
        n += 1
        stack = [(r0, c0)]
        seen[r0, c0] = True
        while stack:
            r, c = stack.pop()
            for rr, cc in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
                if 0 <= rr < h and 0 <= cc < w and m[rr, cc] and not seen[rr, cc]:
                    seen[rr, cc] = True
                    stack.append((rr, cc))
    return n


def _quat_matrix(q):
    """App.Matrix of the rotation of unit quaternion [w, x, y, z] (the textbook formula, so
    the check does not go through App.Rotation as the builder does)."""
    import FreeCAD as App

    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    m = App.Matrix()
    m.A11, m.A12, m.A13 = r[0]
    m.A21, m.A22, m.A23 = r[1]
    m.A31, m.A32, m.A33 = r[2]
    return m


def static_shape3d(node):
    """The solid of a 3D JSON tree built directly with Part's functions in each primitive's
    centred local frame, then turned and moved by a matrix: independent of the builder's
    corner/base offsets and Placements."""
    import FreeCAD as App
    import Part

    if "op" in node:
        return combine(node["op"], [static_shape3d(c) for c in node["children"]])
    t = node["type"]
    V = App.Vector
    if t in ("cylinder", "cone") and "sides" in node:
        r1 = node.get("r1", node.get("r"))
        s = polygonal_solid(node["sides"], r1, node.get("r2", r1), node["h"])
    elif t == "box":
        sx, sy, sz = node["size"]
        s = Part.makeBox(sx, sy, sz, V(-sx / 2, -sy / 2, -sz / 2))
    elif t == "sphere":
        s = Part.makeSphere(node["r"])
    elif t == "cylinder":
        s = Part.makeCylinder(node["r"], node["h"], V(0, 0, -node["h"] / 2))
    elif t == "cone" and node["r1"] == node["r2"]:
        s = Part.makeCylinder(node["r1"], node["h"], V(0, 0, -node["h"] / 2))
    elif t == "cone":
        s = Part.makeCone(node["r1"], node["r2"], node["h"], V(0, 0, -node["h"] / 2))
    elif t == "torus":
        s = Part.makeTorus(node["R"], node["r"])
    elif t == "ellipsoid":
        rx, ry, rz = node["radii"]
        m = App.Matrix()
        m.scale(rx, ry, rz)
        s = Part.makeSphere(1.0).transformGeometry(m)
    elif t in ("rounded_box", "rounded-box"):
        s = rounded_box_pieces(node["size"], node["corner"])
    elif t == "prism":
        w, h, d, apex = node["w"], node["h"], node["depth"], node.get("apex", 0.0)
        pts = [V(-w / 2, -h / 2, -d / 2), V(w / 2, -h / 2, -d / 2), V(apex * w / 2, h / 2, -d / 2)]
        s = Part.Face(Part.makePolygon(pts + [pts[0]])).extrude(V(0, 0, d))
    else:
        raise ValueError(t)
    m = _quat_matrix(node.get("rotation", [1, 0, 0, 0]))
    m.move(V(*node["center"]))
    # transformShape keeps analytic surfaces exact for a rigid matrix (transformGeometry would
    # turn them into approximate B-splines).
    s = s.copy()
    s.transformShape(m, True)
    return s


def rounded_box_pieces(size, r):
    """A rounded box centred on the origin as the union of what makes it: the two slabs that
    cross at the corner centres (either left out when it has no width) and four cylinders."""
    import FreeCAD as App
    import Part

    sx, sy, sz = size
    V = App.Vector
    pieces = [Part.makeCylinder(r, sz, V(x, y, -sz / 2))
              for x in (-(sx / 2 - r), sx / 2 - r) for y in (-(sy / 2 - r), sy / 2 - r)]
    if sx - 2 * r > 1e-9:
        pieces.append(Part.makeBox(sx - 2 * r, sy, sz, V(-(sx / 2 - r), -sy / 2, -sz / 2)))
    if sy - 2 * r > 1e-9:
        pieces.append(Part.makeBox(sx, sy - 2 * r, sz, V(-sx / 2, -(sy / 2 - r), -sz / 2)))
    return pieces[0].multiFuse(pieces[1:]).removeSplitter()


def rounded_box_volume(size, r):
    """The rectangle less its four corner squares plus four quarter discs, times the height."""
    return size[2] * (size[0] * size[1] - (4 - math.pi) * r * r)


def polygonal_volume(sides, r1, r2, h):
    """Volume of the frustum of a regular pyramid (a prism when r1 == r2) of circumradii r1 at
    the bottom and r2 at the top: the prismatoid formula over the n-gons' areas."""
    return 0.5 * sides * math.sin(2 * math.pi / sides) * h / 3 * (r1 * r1 + r1 * r2 + r2 * r2)


def polygonal_solid(sides, r1, r2, h):
    """OpenSCAD's cylinder(h, r1, r2, center = true, $fn = sides) from its plane faces: vertex
    i of both end polygons at 360 i / sides degrees; a radius of 0 is an apex."""
    import FreeCAD as App
    import Part

    def ring(r, z):
        return [App.Vector(r * math.cos(2 * math.pi * i / sides),
                           r * math.sin(2 * math.pi * i / sides), z) for i in range(sides)]

    def face(pts):
        pts = [p for k, p in enumerate(pts) if not p.isEqual(pts[k - 1], 1e-12)]
        return Part.Face(Part.makePolygon(pts + [pts[0]]))

    lo, hi = ring(r1, -h / 2), ring(r2, h / 2)
    faces = [face(end) for end, r in ((lo, r1), (hi, r2)) if r > 0]
    for i in range(sides):
        j = (i + 1) % sides
        faces.append(face([lo[i], lo[j], hi[j], hi[i]]))
    solid = Part.Solid(Part.Shell(faces))
    if solid.Volume < 0:
        solid.reverse()
    return solid


def make_fixture(path, placement=None):
    """A 32 x 20 x 12 block minus a radius-5 cylinder through it (z), as STL; returns the
    mesh's volume. At 64 voxels along the longest side the block's faces fall on voxel
    boundaries (0.5 mm voxels), so the voxels hold the block's volume exactly; a side that is
    not a whole number of voxels rounds to one, which moves the volume by up to a voxel layer
    per face (about 3 % at this size when the block is turned by 30 degrees)."""
    import FreeCAD as App
    import Mesh
    import Part

    block = Part.makeBox(32, 20, 12)
    hole = Part.makeCylinder(5, 20, App.Vector(20, 10, -4))
    solid = block.cut(hole)
    if placement is not None:
        solid.Placement = placement
    mesh = Mesh.Mesh(solid.tessellate(0.01))
    mesh.write(str(path))
    return mesh.Volume


def freecadcmd():
    """The freecadcmd executable, or a pytest skip."""
    import pytest

    exe = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    if not exe:
        pytest.skip("freecadcmd not installed")
    return exe


@contextlib.contextmanager
def reopened(path):
    """The one csgfit group of a saved .FCStd, reopened and recomputed from scratch (every
    object touched) and checked sound; the document is closed after the with block."""
    import FreeCAD as App
    from csgfit_freecad import builder

    d = App.openDocument(str(path))
    try:
        for obj in d.Objects:
            obj.touch()
        d.recompute()
        groups = builder.find_groups(d)
        assert len(groups) == 1
        assert builder.check_tree(d, groups[0]) == []
        yield groups[0]
    finally:
        App.closeDocument(d.Name)


def document_fixture(name):
    """A pytest fixture `doc`: a new FreeCAD document called `name`, closed after the test
    (assign it at a test module's top level: doc = H.document_fixture("..."))."""
    import pytest

    @pytest.fixture
    def doc():
        import FreeCAD as App

        d = App.newDocument(name)
        yield d
        App.closeDocument(d.Name)

    return doc


def installed_home(tmp_path):
    """The environment of a FreeCAD run whose HOME is a fresh folder under tmp_path with the
    workbench installed there by scripts/install_workbench.sh: FreeCAD finds it where the
    installer puts it, and the user's own FreeCAD folder is left alone."""
    import subprocess

    home = tmp_path / "home"
    home.mkdir()
    env = dict(os.environ, HOME=str(home), XDG_DATA_HOME=str(home / ".local" / "share"),
               XDG_CONFIG_HOME=str(home / ".config"), CSGFIT_BUILD_DIR=BUILD,
               # FreeCAD's start page embeds Chromium, which refuses to run as root otherwise.
               QTWEBENGINE_DISABLE_SANDBOX="1")
    env.pop("XDG_RUNTIME_DIR", None)
    subprocess.run(["bash", os.path.join(REPO, "scripts", "install_workbench.sh")], env=env,
                   check=True, capture_output=True, timeout=120)
    return env


def csgfit_or_skip():
    """The csgfit Python module from the build, or a pytest skip saying where it was looked for."""
    import pytest

    try:
        import csgfit
    except ImportError as e:
        pytest.skip(f"csgfit module not built in {BUILD}/python ({e})")
    return csgfit


def run_fcstd_writer(document, out):
    """freecadcmd FCSTD_WRITER on the JSON document file `document`, writing `out`: the
    CompletedProcess (or a pytest skip without freecadcmd)."""
    env = dict(os.environ, CSGFIT_JSON=str(document), CSGFIT_FCSTD=str(out))
    return subprocess.run([freecadcmd(), FCSTD_WRITER], env=env, capture_output=True, text=True,
                          timeout=120)

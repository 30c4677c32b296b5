"""Headless FreeCAD tests of the NURBS terminal (JSON leaf "type": "nurbs", issue 14): the
parametric feature of nurbs_feature.py as the builder makes it from a 3D document, alone and
under a boolean.

Volumes are checked against this file's own evaluation of the B-spline (Cox-de Boor in numpy,
not OpenCASCADE) integrated by Gauss-Legendre quadrature per knot span: for a patch whose border
lies over the rectangle's sides and which stays above its floor, the volume under it is
  V = integral of z (x_u y_v - x_v y_u) du dv
(the divergence theorem with the field (0, 0, z): the vertical walls and the floor add nothing),
exact for the piecewise polynomials up to rounding.
"""

import copy
import json
import math
import os
import subprocess

import numpy as np
import pytest

import fchelpers as H

try:
    import FreeCAD as App  # noqa: E402
    import Part  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import builder, nurbs_feature  # noqa: E402

BLADE = os.path.join(os.path.dirname(H.REPO), "shared", "benchmarks", "points", "blade.gt.json")

R90Z = [math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)]   # 90 degrees about z
TILT = [0.9, 0.3, -0.2, 0.25]                                 # not unit: normalised


# ---- an independent B-spline evaluation --------------------------------------------------

def basis(knots, p, u):
    """N_{i,p}(u) for every i (rows) at the parameters u (columns): Cox-de Boor's recursion;
    u = 1 belongs to the last non-empty span (clamped end)."""
    t = np.asarray(knots, float)
    u = np.atleast_1d(np.asarray(u, float))
    n = np.zeros((len(t) - 1, len(u)))
    for i in range(len(t) - 1):
        n[i] = (t[i] <= u) & (u < t[i + 1])
    n[np.max(np.nonzero(t < t[-1])), u >= t[-1]] = 1.0
    for k in range(1, p + 1):
        m = np.zeros((len(t) - 1 - k, len(u)))
        for i in range(len(t) - 1 - k):
            if t[i + k] > t[i]:
                m[i] += (u - t[i]) / (t[i + k] - t[i]) * n[i]
            if t[i + k + 1] > t[i + 1]:
                m[i] += (t[i + k + 1] - u) / (t[i + k + 1] - t[i + 1]) * n[i + 1]
        n = m
    return n[:len(t) - p - 1]


def dbasis(knots, p, u):
    """dN_{i,p}/du: p (N_{i,p-1} / (t_{i+p} - t_i) - N_{i+1,p-1} / (t_{i+p+1} - t_{i+1}))."""
    t = np.asarray(knots, float)
    lower = np.vstack([np.zeros((1, np.size(u))), basis(t[1:-1], p - 1, u),
                       np.zeros((1, np.size(u)))])  # N_{i,p-1}, i = 0 .. n, ends zero
    d = np.zeros((len(t) - p - 1, np.size(u)))
    for i in range(len(d)):
        if t[i + p] > t[i]:
            d[i] += p / (t[i + p] - t[i]) * lower[i]
        if t[i + p + 1] > t[i + 1]:
            d[i] -= p / (t[i + p + 1] - t[i + 1]) * lower[i + 1]
    return d


def gauss(knots, lo=0.0, hi=1.0, order=8):
    """Gauss-Legendre points and weights on every knot span inside [lo, hi] (lo and hi knots)."""
    x, w = np.polynomial.legendre.leggauss(order)
    spans = [(a, b) for a, b in zip(np.unique(knots)[:-1], np.unique(knots)[1:])
             if a >= lo - 1e-12 and b <= hi + 1e-12]
    return (np.concatenate([(a + b) / 2 + (b - a) / 2 * x for a, b in spans]),
            np.concatenate([(b - a) / 2 * w for a, b in spans]))


def net(leaf):
    """The leaf's control points as an array [j, i, xyz] (u index fastest in the JSON)."""
    nu, nv = leaf["counts"]
    return np.asarray(leaf["control_points"], float).reshape(nv, nu, 3)


def evaluate(leaf, u, v, du=0, dv=0):
    """S (or a first partial) at the grid u x v: array [len(u), len(v), xyz]."""
    (p, q) = leaf["degree"]
    nu_ = dbasis(leaf["knots_u"], p, u) if du else basis(leaf["knots_u"], p, u)
    nv_ = dbasis(leaf["knots_v"], q, v) if dv else basis(leaf["knots_v"], q, v)
    return np.einsum("ia,jb,jic->abc", nu_, nv_, net(leaf))


def volume_under(leaf, u_range=(0.0, 1.0)):
    """The integral of z (x_u y_v - x_v y_u) over u_range x [0, 1] (see the module's doc)."""
    u, wu = gauss(leaf["knots_u"], *u_range)
    v, wv = gauss(leaf["knots_v"])
    s, su, sv = evaluate(leaf, u, v), evaluate(leaf, u, v, du=1), evaluate(leaf, u, v, dv=1)
    jac = su[..., 0] * sv[..., 1] - sv[..., 0] * su[..., 1]
    return float(np.einsum("a,b,ab->", wu, wv, s[..., 2] * jac))


# ---- documents -------------------------------------------------------------------------

def blade_gt():
    if not os.path.exists(BLADE):
        pytest.skip(f"benchmark {BLADE} not present")
    with open(BLADE, encoding="utf-8") as f:
        return json.load(f)


def blade_leaf(**extra):
    """The blade's patch in the contract's format, as the contract converts it: the GT's
    control points with x - 30, y - 10, reordered u fastest; centre [30, 10, 0]."""
    gt = blade_gt()
    cp = gt["control_points"]  # [i][j], i along u
    nu, nv = len(cp), len(cp[0])
    points = [[cp[i][j][0] - 30, cp[i][j][1] - 10, cp[i][j][2]] for j in range(nv)
              for i in range(nu)]
    leaf = {"type": "nurbs", "center": [30, 10, 0], "rotation": [1, 0, 0, 0],
            "euler_deg": [0, 0, 0], "size": [60, 20, max(p[2] for p in points)],
            "degree": [gt["degree_u"], gt["degree_v"]], "counts": [nu, nv],
            "knots_u": gt["knots_u"], "knots_v": gt["knots_v"], "control_points": points}
    leaf.update(extra)
    return leaf


def greville(knots, p):
    return [sum(knots[i + 1:i + p + 1]) / p for i in range(len(knots) - p - 1)]


def greville_leaf(heights, size, degree=(3, 3), knots=None, **extra):
    """A height-field leaf as the solver makes one: heights[j][i] over the Greville abscissae
    of the rectangle (open uniform knots unless given)."""
    nv, nu = len(heights), len(heights[0])
    (p, q), (sx, sy) = degree, size
    ku, kv = knots or ([0.0] * (p + 1) + list(np.linspace(0, 1, nu - p + 1)[1:-1])
                       + [1.0] * (p + 1),
                       [0.0] * (q + 1) + list(np.linspace(0, 1, nv - q + 1)[1:-1])
                       + [1.0] * (q + 1))
    gu, gv = greville(ku, p), greville(kv, q)
    points = [[-sx / 2 + sx * gu[i], -sy / 2 + sy * gv[j], heights[j][i]] for j in range(nv)
              for i in range(nu)]
    leaf = {"type": "nurbs", "center": [0, 0, 0], "size": [sx, sy, max(map(max, heights))],
            "degree": list(degree), "counts": [nu, nv], "knots_u": list(ku),
            "knots_v": list(kv), "control_points": points}
    leaf.update(extra)
    return leaf


def document(tree):
    return {"schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "blade_top.xyz",
            "tree": tree, "stats": {"iou": 1.0, "primitives": 1}}


REOPEN_SCRIPT = """import FreeCAD as App
d = App.openDocument({path!r})
obj = [o for o in d.Objects if o.TypeId == "Part::FeaturePython"][0]
points = list(obj.ControlPoints)
points[7 + 15] = points[7 + 15] + App.Vector(0, 0, 2.0)
obj.ControlPoints = points
d.recompute()
print("CSGFIT_VOLUME=%r" % obj.Shape.Volume if obj.isValid() else "CSGFIT_FAILED")
"""


doc = H.document_fixture("csgfit_nurbs_test")


def terminal(built):
    """The one NURBS terminal of a built tree."""
    found = [o for _, o, _ in built.primitives if nurbs_feature.is_nurbs_terminal(o)]
    assert len(found) == 1
    return found[0]


def raise_pole_of(leaf, i, j, dz):
    """A copy of the leaf with control point (i, j) raised by dz."""
    edited = copy.deepcopy(leaf)
    edited["control_points"][i + leaf["counts"][0] * j][2] += dz
    return edited


def raise_pole(obj, leaf, i, j, dz):
    """Edits one control point of the feature and of the leaf (the reference) alike."""
    nu = leaf["counts"][0]
    points = list(obj.ControlPoints)
    points[i + nu * j] = points[i + nu * j] + App.Vector(0, 0, dz)
    obj.ControlPoints = points
    return raise_pole_of(leaf, i, j, dz)


def bspline_faces(shape):
    return [f for f in shape.Faces if isinstance(f.Surface, Part.BSplineSurface)]


# ---- the tests ---------------------------------------------------------------------------

def test_the_blade_alone_is_one_valid_solid_under_its_exact_bspline_face(doc):
    leaf = blade_leaf()
    built = builder.build(doc, document(leaf))
    assert builder.check_tree(doc, built.group) == []
    obj = terminal(built)
    assert obj is built.root and obj.TypeId == "Part::FeaturePython"
    shape = obj.Shape
    assert shape.isValid() and len(shape.Solids) == 1
    assert shape.Volume == pytest.approx(volume_under(leaf), rel=1e-6)
    # The top is the JSON's surface itself: its poles are the control points (moved to the
    # model by the centre), its knots the leaf's.
    faces = bspline_faces(shape)
    assert faces
    surface = faces[0].Surface
    assert (surface.UDegree, surface.VDegree) == (3, 3)
    assert (surface.NbUPoles, surface.NbVPoles) == (15, 4)
    pole = surface.getPole(8, 2)  # 1-based: control point i = 7, j = 1
    assert list(pole) == pytest.approx(np.add(leaf["control_points"][7 + 15], [30, 10, 0]))
    assert surface.getUKnots() == pytest.approx(sorted(set(leaf["knots_u"])))
    box = shape.optimalBoundingBox()
    assert (box.XMin, box.XMax, box.YMin, box.YMax) == pytest.approx((0, 60, 0, 20), abs=1e-6)
    assert box.ZMin == pytest.approx(0, abs=1e-6)


def test_a_greville_net_is_the_gt_height_field(doc):
    """The GT defines its solid as 0 <= z <= S(x / 60, y / 20) with the heights of its net; a
    net at the Greville abscissae (as the contract places x and y) is exactly that field."""
    gt = blade_gt()
    heights = [[row[j][2] for row in gt["control_points"]] for j in range(4)]
    leaf = greville_leaf(heights, (60, 20), knots=(gt["knots_u"], gt["knots_v"]),
                         center=[30, 10, 0])
    shape = builder.build(doc, document(leaf)).root.Shape
    u, wu = gauss(gt["knots_u"])
    v, wv = gauss(gt["knots_v"])
    z = evaluate(leaf, u, v)[..., 2]
    assert shape.Volume == pytest.approx(1200 * float(np.einsum("a,b,ab->", wu, wv, z)),
                                         rel=1e-6)
    # Points of the GT's surface, (60 u, 20 v, S), lie on the solid's top.
    for a, b in ((0.1, 0.2), (0.37, 0.8), (0.5, 0.5), (0.93, 0.05)):
        height = float(evaluate(leaf, [a], [b])[0, 0, 2])
        point = Part.Vertex(App.Vector(60 * a, 20 * b, height))
        assert shape.distToShape(point)[0] < 1e-6
        assert shape.isInside(App.Vector(60 * a, 20 * b, height - 1e-3), 1e-7, True)
        assert not shape.isInside(App.Vector(60 * a, 20 * b, height + 1e-3), 1e-7, True)


def test_editing_a_control_point_recomputes_the_face_and_the_solid_under_a_difference(doc):
    leaf = blade_leaf()
    # The box crosses the blade's side walls and lies below its lowest point (z 1 .. 3 under
    # heights above 5): it takes exactly 20 x 20 x 2 mm.
    hole = {"type": "box", "center": [30, 10, 2], "rotation": [1, 0, 0, 0], "size": [20, 30, 2]}
    built = builder.build(doc, document({"op": "difference", "children": [leaf, hole]}))
    assert builder.check_tree(doc, built.group) == []
    assert built.root.TypeId == "Part::Cut"
    obj = terminal(built)
    assert built.root.Shape.Volume == pytest.approx(volume_under(leaf) - 800, rel=1e-6)
    assert len(built.root.Shape.Solids) == 1 and built.root.Shape.isValid()

    edited = raise_pole(obj, leaf, 7, 1, 3.0)  # an interior pole of the middle
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    gain = volume_under(edited) - volume_under(leaf)
    assert gain > 10  # the expected change is well above the tolerance
    assert obj.Shape.Volume == pytest.approx(volume_under(edited), rel=1e-6)
    assert built.root.Shape.Volume == pytest.approx(volume_under(edited) - 800, rel=1e-6)
    pole = bspline_faces(obj.Shape)[0].Surface.getPole(8, 2)
    assert pole.z == pytest.approx(leaf["control_points"][7 + 15][2] + 3.0)


def test_the_leafs_placement_is_honoured(doc):
    turned = blade_leaf(center=[5, -2, 7], rotation=R90Z)
    tilted = blade_leaf(center=[100, 0, 0], rotation=TILT)
    built = builder.build(doc, document({"op": "union", "children": [turned, tilted]}))
    assert builder.check_tree(doc, built.group) == []
    a, b = (o.Shape for _, o, _ in built.primitives)
    # 90 degrees about z: local x (60 mm) runs along model y, local y along -x.
    box = a.optimalBoundingBox()
    assert (box.XMin, box.XMax, box.YMin, box.YMax, box.ZMin) == pytest.approx(
        (5 - 10, 5 + 10, -2 - 30, -2 + 30, 7), abs=1e-6)
    assert a.Volume == pytest.approx(volume_under(turned), rel=1e-6)
    # The tilted one: points just under and over the patch, moved by the quaternion's
    # textbook matrix, are inside and outside.
    m = H._quat_matrix(TILT)
    m.move(App.Vector(100, 0, 0))
    for s, t in ((0.2, 0.3), (0.5, 0.5), (0.8, 0.9)):
        x, y, z = evaluate(tilted, [s], [t])[0, 0]
        assert b.isInside(m.multVec(App.Vector(x, y, z - 1e-3)), 1e-7, True)
        assert not b.isInside(m.multVec(App.Vector(x, y, z + 1e-3)), 1e-7, True)
    assert b.isInside(m.multVec(App.Vector(0, 0, 1e-3)), 1e-7, True)  # the floor, local z = 0
    assert not b.isInside(m.multVec(App.Vector(0, 0, -1e-3)), 1e-7, True)


def test_nothing_below_the_floor_and_the_rectangle_trims(doc):
    # Heights from -2 to 5 along x: the patch dips under its floor over a strip at x < 0.
    heights = [[-2.0 + 0.5 * j, -1.0, 3.0 + 0.5 * j, 5.0 - 0.5 * j] for j in range(4)]
    leaf = greville_leaf(heights, (40, 10))
    obj = terminal(builder.build(doc, document(leaf)))
    shape = obj.Shape
    assert shape.isValid() and len(shape.Solids) == 1
    # max(S, 0) on a fine midpoint grid (a single Bezier patch: x, y linear in u, v).
    n = 1500
    mid = (np.arange(n) + 0.5) / n
    z = evaluate(leaf, mid, mid)[..., 2]
    assert z.min() < 0 < z.max()
    assert shape.Volume == pytest.approx(np.maximum(z, 0).mean() * 400, rel=1e-4)
    assert shape.optimalBoundingBox().ZMin == pytest.approx(0, abs=1e-6)

    # A narrower rectangle cuts the patch: 0 <= z <= S only for |x| <= 10 (u in [1/4, 3/4]).
    positive = greville_leaf([[2.0 + i + j for i in range(7)] for j in range(5)], (40, 10))
    obj = terminal(builder.build(doc, document(positive)))
    whole = obj.Shape.Volume
    assert whole == pytest.approx(volume_under(positive), rel=1e-6)
    obj.SizeX = 20
    doc.recompute()
    assert obj.Shape.isValid() and len(obj.Shape.Solids) == 1
    assert obj.Shape.Volume == pytest.approx(volume_under(positive, (0.25, 0.75)), rel=1e-6)
    box = obj.Shape.optimalBoundingBox()
    assert (box.XMin, box.XMax) == pytest.approx((-10, 10), abs=1e-6)


def test_bad_nurbs_leaves_raise_build_error_and_leave_nothing(doc):
    for field, value, match in (
            ("knots_u", [0.0] * 3 + [0.5] * 13 + [1.0] * 3, "clamped"),
            ("knots_v", [0, 0, 0, 0, 1, 1, 1], "knots"),
            ("counts", [15, 3], "control_points"),
            ("degree", [0, 3], "degree"),
            ("degree", [3.5, 3], "integers"),
            ("size", [60, -20, 15], "size"),
            ("control_points", [[0, 0]] * 60, "control point 0"),
            ("knots_u", [0, 0, 0, 0] + [0.5, 0.4] + [0.5] * 9 + [1] * 4, "decrease")):
        with pytest.raises(builder.BuildError, match=match):
            builder.build(doc, document(blade_leaf(**{field: value})))
        assert doc.Objects == []
    # Every control point under the floor: no solid, the feature says so.
    built = builder.build(doc, document(greville_leaf([[-1.0] * 4] * 4, (10, 10))))
    assert builder.check_tree(doc, built.group) != []
    assert {"Invalid", "Error"} & set(terminal(built).State)


def test_a_bad_edit_marks_the_feature_and_a_good_one_heals_it(doc):
    leaf = blade_leaf()
    built = builder.build(doc, document(leaf))
    obj = terminal(built)
    obj.KnotsU = list(leaf["knots_u"])[:-1]  # one knot short
    doc.recompute()
    assert builder.check_tree(doc, built.group) != []
    obj.KnotsU = leaf["knots_u"]
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert obj.Shape.Volume == pytest.approx(volume_under(leaf), rel=1e-6)


def test_a_saved_document_reopens_and_recomputes_the_feature(tmp_path):
    leaf = blade_leaf()
    saved = App.newDocument("nurbs_save")
    built = builder.build(saved, document(leaf))
    edited = raise_pole(terminal(built), leaf, 3, 2, -1.5)
    saved.recompute()
    path = tmp_path / "blade.FCStd"
    saved.saveAs(str(path))
    App.closeDocument(saved.Name)
    with H.reopened(path) as group:
        obj = [o for o in builder.tree_objects(group) if nurbs_feature.is_nurbs_terminal(o)][0]
        assert obj.Shape.Volume == pytest.approx(volume_under(edited), rel=1e-6)
        assert obj.ControlPoints[3 + 15 * 2].z == pytest.approx(
            edited["control_points"][3 + 30][2])


def test_fcstd_writer_writes_a_nurbs_document(doc, tmp_path):
    exe = H.freecadcmd()
    leaf = blade_leaf()
    src = tmp_path / "blade.json"
    src.write_text(json.dumps(document(leaf)))
    out = tmp_path / "blade.FCStd"
    proc = H.run_fcstd_writer(src, out)
    assert proc.returncode == 0, proc.stderr
    with H.reopened(out) as group:
        assert group.CsgFitRoot.Shape.Volume == pytest.approx(volume_under(leaf), rel=1e-6)
    # A fresh FreeCAD with the workbench installed restores the feature's code and recomputes
    # it after an edit. (FreeCAD 0.20.2+dfsg1-4+deb12u1 restores a FeaturePython's class only
    # from a module of FreeCAD's or an installed addon's Mod folder: the installed workbench.)
    script = tmp_path / "reopen.py"
    script.write_text(REOPEN_SCRIPT.format(path=str(out)))
    proc = subprocess.run([exe, str(script)], capture_output=True, text=True, timeout=120,
                          env=H.installed_home(tmp_path))
    assert "CSGFIT_VOLUME=" in proc.stdout, proc.stdout + proc.stderr
    raised = float(proc.stdout.split("CSGFIT_VOLUME=")[1].split()[0])
    assert raised == pytest.approx(volume_under(raise_pole_of(leaf, 7, 1, 2.0)), rel=1e-6)
    # A bad patch: one line, status 2, no file.
    src.write_text(json.dumps(document(blade_leaf(counts=[14, 4]))))
    out.unlink()
    proc = H.run_fcstd_writer(src, out)
    assert proc.returncode == 2 and "csgfit: error:" in proc.stderr, proc.stderr
    assert not out.exists()


def test_optimize_csg_tree_refuses_a_nurbs_terminal_by_name(doc):
    from csgfit_freecad import optimize_tree

    hole = {"type": "box", "center": [30, 10, 2], "size": [20, 30, 2]}
    built = builder.build(doc, document({"op": "difference", "children": [blade_leaf(), hole]}))
    with pytest.raises(ValueError, match=r"NURBS001 \(Part::FeaturePython\) is not a Part "
                                         r"primitive the optimiser knows"):
        optimize_tree.tree_csg(built.root)

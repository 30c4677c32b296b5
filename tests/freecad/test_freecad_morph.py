"""Headless FreeCAD tests of the morph builder (issue 13): one parametric tree whose
dimensions are expressions of the parameter sheet's `morph` cell.

At morph = 0 and 1 the solid's volume is checked against exact formulas of shape A's and B's
primitives (chosen disjoint, holes inside their plates); at 0.5 against builder.build of the
interpolated plain document (every number linear, 3D rotations by slerp), by volume and by
the volume of the symmetric difference, which also catches a wrong placement.
"""

import copy
import json
import math
import os
import subprocess
import sys

import pytest

import fchelpers as H

try:
    import FreeCAD as App  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import builder, morph_builder  # noqa: E402


THICKNESS = 2.0
PI = math.pi


def rect(cx, cy, w, h, angle=0.0):
    return {"type": "rectangle", "cx": cx, "cy": cy, "w": w, "h": h, "angle": angle}


def circle(cx, cy, r):
    return {"type": "circle", "cx": cx, "cy": cy, "r": r}


def doc2d(tree_a, tree_b, leaves):
    return {
        "schema": "csgfit/1", "dimension": 2, "units": "mm", "source": "A.png",
        "canvas": {"width_px": 80, "height_px": 60, "pixel_size": 0.5, "thickness": THICKNESS},
        "tree": tree_a, "stats": {"iou": 0.99, "primitives": len(leaves)},
        "morph": {"source_b": "B.png", "tree_b": tree_b, "stats_b": {"iou": 0.98},
                  "rotate": "shortest", "leaves": leaves},
    }


# A: a turned plate minus a hole and a small hole that B does not have (r = 0 in tree_b),
# an ellipse whose radii cross (rx > ry at A, rx < ry at B), a triangle turning through 360
# and a rectangle that only B has (size 0 in tree). Pieces are disjoint at both ends.
MORPH_2D = doc2d(
    {"op": "union", "children": [
        {"op": "difference", "children": [rect(12, 12, 16, 10, 20), circle(12, 12, 2.5),
                                          circle(16, 13, 1.0)]},
        {"type": "ellipse", "cx": 32, "cy": 12, "rx": 3, "ry": 2, "angle": 10},
        {"type": "triangle", "cx": 30, "cy": 24, "w": 8, "h": 5, "angle": 0, "apex": 1},
        rect(8, 28, 0, 0, 0)]},
    {"op": "union", "children": [
        {"op": "difference", "children": [rect(13, 12, 18, 12, -30), circle(13, 12, 3.0),
                                          circle(16, 13, 0.0)]},
        {"type": "ellipse", "cx": 32, "cy": 12, "rx": 2, "ry": 4, "angle": 40},
        {"type": "triangle", "cx": 30, "cy": 24, "w": 6, "h": 6, "angle": 390, "apex": -0.5},
        rect(8, 28, 4, 3, 30)]},
    [{"in_a": True, "in_b": True}] * 2 + [{"in_a": True, "in_b": False}]
    + [{"in_a": True, "in_b": True}] * 2 + [{"in_a": False, "in_b": True}])
AREA_A = 16 * 10 - PI * 2.5 ** 2 - PI * 1.0 ** 2 + PI * 3 * 2 + 8 * 5 / 2
AREA_B = 18 * 12 - PI * 3.0 ** 2 + PI * 2 * 4 + 6 * 6 / 2 + 4 * 3


# ---- quaternions (w, x, y, z), written out here so the check does not use the builder's ----

def qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def qaxis(axis, degrees):
    n = math.sqrt(sum(c * c for c in axis))
    s = math.sin(math.radians(degrees) / 2)
    return (math.cos(math.radians(degrees) / 2),) + tuple(s * c / n for c in axis)


def qrotate(q, v):
    w, x, y, z = qmul(qmul(q, (0.0,) + tuple(v)), (q[0], -q[1], -q[2], -q[3]))
    return [x, y, z]


def slerp(qa, qb, t):
    """The short-arc spherical interpolation: R(axis, t * angle) * R_A of the spec."""
    dot = sum(a * b for a, b in zip(qa, qb))
    if dot < 0:
        qb, dot = tuple(-c for c in qb), -dot
    omega = math.acos(min(1.0, dot))
    if omega < 1e-12:
        return qa
    ka, kb = math.sin((1 - t) * omega) / math.sin(omega), math.sin(t * omega) / math.sin(omega)
    return tuple(ka * a + kb * b for a, b in zip(qa, qb))


def box(center, size, q):
    return {"type": "box", "center": list(center), "size": list(size), "rotation": list(q)}


def cylinder(center, r, h, q):
    return {"type": "cylinder", "center": list(center), "r": r, "h": h, "rotation": list(q)}


def doc3d(tree_a, tree_b, leaves):
    return {
        "schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "A.stl",
        "grid": {"voxel_size": 0.5, "nx": 100, "ny": 40, "nz": 40},
        "tree": tree_a, "stats": {"iou": 0.97, "primitives": len(leaves)},
        "morph": {"source_b": "B.stl", "tree_b": tree_b, "stats_b": {"iou": 0.96},
                  "leaves": leaves},
    }


# A: a block with a through hole (the hole turns with the block) and a sphere only B has;
# B: other sizes, the block turned by 40 degrees more about (1, 1, 1) (A's block is turned
# already, so the order of R(axis, t * angle) * R_A matters).
Q_A = qaxis((0, 0, 1), 15)
Q_B = qmul(qaxis((1, 1, 1), 40), Q_A)
MORPH_3D = doc3d(
    {"op": "union", "children": [
        {"op": "difference", "children": [box((10, 10, 5), (20, 12, 10), Q_A),
                                          cylinder([a + b for a, b in zip(
                                              (10, 10, 5), qrotate(Q_A, (2, 0, 0)))], 3, 14,
                                              Q_A)]},
        {"type": "sphere", "center": [40, 10, 5], "r": 0.0}]},
    {"op": "union", "children": [
        {"op": "difference", "children": [
            box((11, 10, 6), (24, 14, 8), Q_B),
            cylinder([a + b for a, b in zip((11, 10, 6), qrotate(Q_B, (-2, 1, 0)))], 2.5, 12,
                     Q_B)]},
        {"type": "sphere", "center": [40, 10, 5], "r": 3.0}]},
    [{"in_a": True, "in_b": True}] * 2 + [{"in_a": False, "in_b": True}])
VOLUME_A = 20 * 12 * 10 - PI * 3 ** 2 * 10
VOLUME_B = 24 * 14 * 8 - PI * 2.5 ** 2 * 8 + 4 / 3 * PI * 3 ** 3


def interpolated(result, t):
    """The plain csgfit/1 document of the frame at t: every number linear, rotations by slerp;
    built by builder.build as the reference of the morph at t."""
    def node(a, b):
        if "op" in a:
            return dict(a, children=[node(x, y) for x, y in zip(a["children"], b["children"])])
        out = {}
        for key, va in a.items():
            vb = b[key]
            if key == "rotation":
                out[key] = list(slerp(tuple(va), tuple(vb), t))
            elif isinstance(va, list):
                out[key] = [x + (y - x) * t for x, y in zip(va, vb)]
            elif isinstance(va, (int, float)):
                out[key] = va + (vb - va) * t
            else:
                out[key] = va
        return out

    plain = {k: v for k, v in result.items() if k != "morph"}
    plain["tree"] = node(result["tree"], result["morph"]["tree_b"])
    return plain


@pytest.fixture
def doc():
    d = App.newDocument("csgfit_morph_test")
    yield d
    App.closeDocument(d.Name)


def show_frame(doc, built, t):
    morph_builder.set_morph(built.sheet, t)
    doc.recompute()
    assert builder.check_tree(doc, built.group) == [], t
    return built.root.Shape


def assert_same_solid(shape, reference):
    """Same volume and (almost) no volume in either difference: the same solid, in place."""
    v = reference.Volume
    assert shape.Volume == pytest.approx(v, rel=1e-6)
    assert shape.cut(reference).Volume + reference.cut(shape).Volume < 1e-6 * v


def reference_solid(doc, result, t):
    built = builder.build(doc, interpolated(result, t), label=f"reference_{t}")
    assert builder.check_tree(doc, built.group) == []
    return built.root.Shape


def test_2d_morph_cell_drives_the_whole_tree(doc):
    built = morph_builder.build_morph(doc, MORPH_2D)
    assert built.sheet.get("morph") == 0
    assert float(built.sheet.get("min_size")) == pytest.approx(0.5e-3)
    assert built.group.CsgFitSourceB == "B.png" and built.group.CsgFitIoUB == 0.98
    assert {o.TypeId for o in builder.tree_objects(built.group)} <= set(builder.PARAMETRIC_TYPES)
    assert builder.check_tree(doc, built.group) == []
    assert built.root.Shape.Volume == pytest.approx(AREA_A * THICKNESS, rel=1e-6)
    for t in (0.5, 0.25, 0.8):  # any order: each frame follows the cell alone
        assert_same_solid(show_frame(doc, built, t), reference_solid(doc, MORPH_2D, t))
    assert show_frame(doc, built, 1).Volume == pytest.approx(AREA_B * THICKNESS, rel=1e-6)
    assert show_frame(doc, built, 0).Volume == pytest.approx(AREA_A * THICKNESS, rel=1e-6)


def test_2d_placement_expressions_are_base_and_angle_about_z(doc):
    built = morph_builder.build_morph(doc, MORPH_2D)
    plate = built.primitives[0][1]
    paths = {path.lstrip("."): expr for path, expr in plate.ExpressionEngine}
    assert {"Length", "Width", "Placement.Base.x", "Placement.Base.y",
            "Placement.Rotation.Angle"} <= set(paths)
    assert "cos(" in paths["Placement.Base.x"] and "morph" in paths["Placement.Rotation.Angle"]
    show_frame(doc, built, 0.5)
    rot = plate.Placement.Rotation
    assert abs(rot.Axis.z) == pytest.approx(1.0)
    assert math.degrees(rot.Angle) * rot.Axis.z == pytest.approx(-5.0)  # (20 + -30) / 2
    # A number equal in A and B stays a plain, editable value.
    hole = built.primitives[1][1]
    assert ".Placement.Base.y" not in dict(hole.ExpressionEngine)


def test_3d_morph_turns_the_block_as_the_solver_does(doc):
    built = morph_builder.build_morph(doc, MORPH_3D)
    assert float(built.sheet.get("min_size")) == pytest.approx(0.5e-3)
    assert builder.check_tree(doc, built.group) == []
    assert built.root.Shape.Volume == pytest.approx(VOLUME_A, rel=1e-6)
    for t in (0.5, 0.3):
        assert_same_solid(show_frame(doc, built, t), reference_solid(doc, MORPH_3D, t))
    assert_same_solid(show_frame(doc, built, 1), H.static_shape3d(MORPH_3D["morph"]["tree_b"]))
    assert built.root.Shape.Volume == pytest.approx(VOLUME_B, rel=1e-6)
    assert show_frame(doc, built, 0).Volume == pytest.approx(VOLUME_A, rel=1e-6)


def test_3d_cone_whose_radii_cross_recomputes_at_every_frame(doc):
    cone = {"type": "cone", "center": [0, 0, 0], "r1": 2.0, "r2": 1.0, "h": 4.0}
    result = doc3d(cone, dict(cone, r1=1.0, r2=2.0, rotation=list(qaxis((1, 0, 0), 90))),
                   [{"in_a": True, "in_b": True}])
    built = morph_builder.build_morph(doc, result)
    for t in (0, 0.5, 1):
        shape = show_frame(doc, built, t)
        r1, r2 = 2 - t, 1 + t
        frustum = PI * 4 / 3 * (r1 * r1 + r1 * r2 + r2 * r2)
        # Where the radii meet, Radius2 stays min_size (5e-4 mm) away from Radius1.
        assert shape.Volume == pytest.approx(frustum, rel=1e-6 if t != 0.5 else 1e-3)


def test_structure_mismatch_raises_and_leaves_nothing(doc):
    bad = copy.deepcopy(MORPH_2D)
    bad["morph"]["tree_b"]["children"][1]["type"] = "circle"
    with pytest.raises(builder.BuildError, match="tree_b has 'circle'"):
        morph_builder.build_morph(doc, bad)
    bad = copy.deepcopy(MORPH_2D)
    bad["morph"]["tree_b"]["children"][0]["children"][1]["r"] = -1.0
    with pytest.raises(builder.BuildError, match="must be >= 0"):
        morph_builder.build_morph(doc, bad)
    with pytest.raises(builder.BuildError, match="not a morph"):
        morph_builder.build_morph(doc, interpolated(MORPH_2D, 0.5))
    # Nor interpolates a rounded box's corner: one in a morph document is refused.
    bad = copy.deepcopy(MORPH_3D)
    for tree in (bad["tree"], bad["morph"]["tree_b"]):
        tree["children"][1] = {"type": "rounded_box", "center": [40, 10, 5], "size": [4, 2, 1],
                               "corner": 0.5}
    with pytest.raises(builder.BuildError, match="does not interpolate 'rounded_box'"):
        morph_builder.build_morph(doc, bad)
    # csgfit morph never makes a polygonal cylinder: one in a hand-made document is refused.
    bad = copy.deepcopy(MORPH_3D)
    bad["morph"]["tree_b"]["children"][0]["children"][1]["sides"] = 6
    with pytest.raises(builder.BuildError, match="polygonal"):
        morph_builder.build_morph(doc, bad)
    assert doc.Objects == []


def test_saved_morph_reopens_and_follows_the_cell(tmp_path, doc):
    saved = App.newDocument("morph_save")
    built = morph_builder.build_morph(saved, MORPH_2D)
    show_frame(saved, built, 0.25)
    path = str(tmp_path / "morph.FCStd")
    saved.saveAs(path)
    App.closeDocument(saved.Name)
    with H.reopened(path) as group:
        sheet = next(o for o in group.Group if o.TypeId == "Spreadsheet::Sheet")
        assert_same_solid(group.CsgFitRoot.Shape, reference_solid(doc, MORPH_2D, 0.25))
        morph_builder.set_morph(sheet, 0.5)
        group.Document.recompute()
        assert_same_solid(group.CsgFitRoot.Shape, reference_solid(doc, MORPH_2D, 0.5))


def test_fcstd_writer_builds_a_morph_document(tmp_path, doc):
    src = tmp_path / "in.json"
    src.write_text(json.dumps(MORPH_3D))
    out = tmp_path / "out.FCStd"
    proc = H.run_fcstd_writer(src, out)
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(tmp_path)) == ["in.json", "out.FCStd"]
    with H.reopened(out) as group:
        assert group.CsgFitRoot.Shape.Volume == pytest.approx(VOLUME_A, rel=1e-6)
        sheet = next(o for o in group.Group if o.TypeId == "Spreadsheet::Sheet")
        morph_builder.set_morph(sheet, 1)
        group.Document.recompute()
        assert builder.check_tree(group.Document, group) == []
        assert group.CsgFitRoot.Shape.Volume == pytest.approx(VOLUME_B, rel=1e-6)

    bad = copy.deepcopy(MORPH_3D)
    del bad["morph"]["tree_b"]["children"][1]
    src.write_text(json.dumps(bad))
    out2 = tmp_path / "bad.FCStd"
    proc = H.run_fcstd_writer(src, out2)
    assert proc.returncode == 2 and "structure" in proc.stderr
    assert not out2.exists()


PANEL_CHECK = r"""
import json, sys, types
sys.path.append({lib!r}); sys.path.append({shim!r}); sys.path.insert(0, {workbench!r})
import FreeCAD as App
from csgfit_freecad.qt import QtWidgets
app = QtWidgets.QApplication([])
# FreeCADGui without a main window has no addCommand: a stand-in records what register() adds.
added = {{}}
gui = types.ModuleType("FreeCADGui")
gui.addCommand = lambda name, cmd: added.__setitem__(name, cmd)
gui.Control = types.SimpleNamespace(activeDialog=lambda: False)
sys.modules["FreeCADGui"] = gui
from csgfit_freecad import commands, morph_panel
commands.register()
cmd = added[commands.MORPH_IMAGES]
panel = morph_panel.MorphPanel()
panel.file_edit.setText("")
missing_a = panel.fit_request()
error_a = panel.status.text()
panel.file_edit.setText("a.png")
missing_b = panel.fit_request()
summary = panel.summary({morph!r})
# Export OpenSCAD on a morph group writes the animated model, extruded by the group's cell.
from csgfit_freecad import morph_builder
doc = App.newDocument("export")
built = morph_builder.build_morph(doc, {morph!r})
scad_path = {scad!r}
commands.export_scad(built.group, scad_path)
scad = open(scad_path).read()
print(json.dumps({{"summary": summary, "scad_morph": "morph = -1;" in scad and "mix(" in scad,
                  "scad_extruded": "linear_extrude(height = thickness)" in scad, "commands": commands.COMMANDS, "added": sorted(added),
                  "resources": cmd.GetResources(), "active": cmd.IsActive(),
                  "error_a": error_a, "error_b": panel.status.text(),
                  "requests": [missing_a, missing_b],
                  "rows": [panel.rotate.itemText(i) for i in range(panel.rotate.count())],
                  "presets": [panel.preset.itemText(i) for i in range(panel.preset.count())]}}))
"""


def test_morph_command_is_registered_and_its_panel_builds_without_a_gui(tmp_path):
    code = PANEL_CHECK.format(lib=H.FREECAD_LIB, shim=H.FREECAD_QT_SHIM, workbench=H.WORKBENCH,
                              morph=json.dumps(MORPH_2D), scad=str(tmp_path / "m.scad"))
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", CSGFIT_BUILD_DIR=H.BUILD)
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    r = json.loads(proc.stdout.strip().splitlines()[-1])
    assert "CSGFit_MorphImages" in r["commands"] and "CSGFit_MorphImages" in r["added"]
    assert r["resources"]["MenuText"] == "Morph two images"
    assert os.path.isfile(r["resources"]["Pixmap"]) and r["active"]
    assert r["requests"] == [None, None]
    assert "image A" in r["error_a"] and "image B" in r["error_b"]
    assert r["summary"].startswith("IoU A 0.9900, B 0.9800, 6 primitives")
    assert r["rows"] == ["shortest", "cw", "ccw"] and r["presets"] == ["default", "paper"]
    assert r["scad_morph"] and r["scad_extruded"]

"""Headless FreeCAD tests of the CSG Fit builder and the .FCStd writer.

Run with `/usr/bin/python3 -m pytest tests/freecad` (FreeCAD's Python API is imported from
/usr/lib/freecad-python3/lib). Tests that fit bitmaps need the csgfit module
($CSGFIT_BUILD_DIR/python, default build/python) and ../shared/benchmarks/2d; they skip with
the reason otherwise.
"""

import copy
import json
import math
import os
import subprocess

import pytest

import fchelpers as H

try:
    import FreeCAD as App  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import builder  # noqa: E402

BENCHMARKS = ["part_00", "glyph_P", "topopt_bridge"]
PIXEL = 0.5
WRITER = H.FCSTD_WRITER


@pytest.fixture
def doc():
    d = App.newDocument("csgfit_test")
    yield d
    App.closeDocument(d.Name)


_fits = {}


@pytest.fixture(params=BENCHMARKS)
def fitted(request):
    """(name, csgfit.FitResult) for a benchmark bitmap, fitted once per session."""
    name = request.param
    path = os.path.join(H.BENCH, name + ".png")
    if not os.path.exists(path):
        pytest.skip(f"benchmark {path} not present")
    csgfit = H.csgfit_or_skip()
    if name not in _fits:
        _fits[name] = csgfit.fit_image(path, pixel_size=PIXEL, time=4, seed=1)
    return name, _fits[name]


def thickness_of(built):
    return float(built.sheet.get("thickness"))


ALL_KINDS = {
    "schema": "csgfit/1", "dimension": 2, "units": "mm", "source": "synthetic.png",
    "canvas": {"width_px": 80, "height_px": 60, "pixel_size": 0.5, "thickness": 2.0},
    "tree": {"op": "union", "children": [
        {"op": "difference", "children": [
            {"type": "rectangle", "cx": 12, "cy": 12, "w": 16, "h": 10, "angle": 20},
            {"type": "circle", "cx": 12, "cy": 12, "r": 2.5},
            {"type": "ellipse", "cx": 18, "cy": 12, "rx": 1.5, "ry": 3, "angle": 10},
            {"type": "triangle", "cx": 8, "cy": 14, "w": 4, "h": 3, "angle": 200, "apex": 0.4},
        ]},
        {"op": "intersection", "children": [
            {"type": "circle", "cx": 30, "cy": 20, "r": 6},
            {"type": "rectangle", "cx": 30, "cy": 17, "w": 14, "h": 8, "angle": 0},
        ]},
        {"type": "triangle", "cx": 30, "cy": 6, "w": 8, "h": 5, "angle": 0, "apex": 1},
    ]},
    "stats": {"iou": 1.0, "primitives": 7},
    "alternatives": [],
}


def test_all_kinds_build_parametric_and_match_independent_csg(doc):
    built = builder.build(doc, ALL_KINDS)
    assert builder.check_tree(doc, built.group) == []
    assert built.group.Label == "synthetic"
    assert len(built.primitives) == 7
    types = {o.TypeId for o in built.objects}
    assert types <= set(builder.PARAMETRIC_TYPES)
    assert {"Part::Box", "Part::Cylinder", "Part::Ellipse", "Part::Extrusion", "Part::Wedge",
            "Part::Cut", "Part::MultiCommon", "Part::MultiFuse"} <= types
    expected = H.static_shape(ALL_KINDS["tree"], 2.0)
    assert built.root.Shape.Volume == pytest.approx(expected.Volume, rel=1e-6)
    assert built.root.Shape.common(expected).Volume == pytest.approx(expected.Volume, rel=1e-6)
    # Only the root is shown.
    assert built.root.Visibility
    assert not any(o.Visibility for o in built.objects if o is not built.root)
    # The whole result is kept on the group for "Export OpenSCAD".
    assert json.loads(built.group.CsgFitJson)["tree"] == ALL_KINDS["tree"]


def test_isolated_union_rectangle_length_edit_adds_width_times_height(doc):
    tree = {"op": "union", "children": [
        {"type": "rectangle", "cx": 10, "cy": 10, "w": 8, "h": 5, "angle": 30},
        {"type": "circle", "cx": 40, "cy": 10, "r": 4},
    ]}
    built = builder.build(doc, tree, thickness=3.0, label="edit")
    v0 = built.root.Shape.Volume
    box = built.primitives[0][1]
    assert box.TypeId == "Part::Box"
    box.Length = box.Length.Value + 1.0
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert built.root.Shape.Volume == pytest.approx(v0 + 1.0 * 5 * 3, rel=1e-9)
    circle = built.primitives[1][1]
    circle.Radius = 5.0
    doc.recompute()
    assert built.root.Shape.Volume == pytest.approx(9 * 5 * 3 + math.pi * 25 * 3, rel=1e-9)


def test_thickness_cell_drives_every_height(doc):
    built = builder.build(doc, ALL_KINDS)
    v0 = built.root.Shape.Volume
    assert thickness_of(built) == 2.0
    built.sheet.set("thickness", "=5mm")
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert built.root.Shape.Volume == pytest.approx(v0 * 2.5, rel=1e-6)
    assert built.root.Shape.BoundBox.ZMax == pytest.approx(5.0)


def test_default_thickness_is_ten_pixels(doc):
    result = copy.deepcopy(ALL_KINDS)
    result["canvas"]["thickness"] = 0
    built = builder.build(doc, result)
    assert thickness_of(built) == pytest.approx(10 * 0.5)


def test_bad_input_raises_build_error_and_leaves_nothing(doc):
    bad = copy.deepcopy(ALL_KINDS)
    bad["tree"]["children"][2] = {"type": "hexagon", "cx": 1, "cy": 1}
    with pytest.raises(builder.BuildError, match="hexagon"):
        builder.build(doc, bad)
    assert doc.Objects == []
    with pytest.raises(builder.BuildError, match="schema"):
        builder.build(doc, {"schema": "other/9", "tree": {}})
    with pytest.raises(builder.BuildError, match="cannot read"):
        builder.build(doc, "/nonexistent/result.json")


def test_benchmark_tree_recomputes_to_a_valid_solid_matching_the_bitmap(doc, fitted):
    name, result = fitted
    built = builder.build(doc, result)
    assert doc.recompute() >= 0
    assert builder.check_tree(doc, built.group) == []
    assert built.group.Label == name
    # Only parametric objects: no Part::Feature holding a static shape.
    for obj in built.objects:
        assert obj.TypeId in builder.PARAMETRIC_TYPES, obj.TypeId
    shape = built.root.Shape
    assert shape.isValid() and shape.Solids
    raster = result.raster()
    t = thickness_of(built)
    # Every solid that covers a pixel centre is a separate part of the solver's raster
    # (slivers thinner than a pixel may come on top: the fit cannot see them).
    visible = [s for s in shape.Solids
               if H.section_mask(s, result.width, result.height, PIXEL, t / 2).any()]
    assert 1 <= len(visible) <= H.components(raster)
    section = H.section_mask(shape, result.width, result.height, PIXEL, t / 2)
    assert H.iou(section, raster) >= 0.99, "FreeCAD solid differs from the solver's raster"
    target_iou = H.iou(section, result.target())
    if result.stats.iou < 0.95 and target_iou >= result.stats.iou - 0.005:
        # The FreeCAD tree is faithful; the fit itself is short of the bar.
        pytest.xfail(f"{name}: the solver's fit reaches IoU {result.stats.iou:.4f} < 0.95 in "
                     "the time given; the FreeCAD section matches it")
    assert target_iou >= 0.95, (
        f"{name}: section IoU {target_iou:.4f} vs bitmap (the fit's own IoU is "
        f"{result.stats.iou:.4f})")


def _edited(prim, obj):
    """(edit to apply to the FreeCAD object, the same edit on the JSON primitive); None for a
    dimension a shared cell drives (the cell is what a user edits then)."""
    p = dict(prim)
    bound = {prop for prop, _ in obj.ExpressionEngine}
    if obj.TypeId == "Part::Box" and "Length" not in bound:
        p["w"] += 1.0  # the box stays centred, as the .scad's square(center = true)
        return (lambda: setattr(obj, "Length", obj.Length.Value + 1.0)), p
    if obj.TypeId == "Part::Cylinder" and "Radius" not in bound:
        p["r"] += 0.5
        return (lambda: setattr(obj, "Radius", obj.Radius.Value + 0.5)), p
    return None, None


def _replace(node, old, new):
    if node is old:
        return new
    if "op" in node:
        return {"op": node["op"], "children": [_replace(c, old, new) for c in node["children"]]}
    return node


def test_benchmark_editing_a_primitive_changes_the_solid_accordingly(doc, fitted):
    name, result = fitted
    built = builder.build(doc, result)
    t = thickness_of(built)
    tree = json.loads(built.group.CsgFitJson)["tree"]
    # The builder's primitive list is in pre-order, like the JSON's leaves.
    leaves = [n for n in _walk(tree) if "type" in n]
    assert len(leaves) == len(built.primitives)
    changed = 0
    edits = 0
    for leaf, (prim, holder, _solid) in zip(leaves, built.primitives):
        apply, new_prim = _edited(prim, holder)
        if apply is None:
            continue
        v0 = built.root.Shape.Volume
        apply()
        doc.recompute()
        assert builder.check_tree(doc, built.group) == []
        tree = _replace(tree, leaf, new_prim)
        expected = H.static_shape(tree, t).Volume
        assert built.root.Shape.Volume == pytest.approx(expected, rel=1e-6, abs=1e-6)
        changed += abs(built.root.Shape.Volume - v0) > 1e-3
        edits += 1
        if edits == 4:
            break
    if edits == 0:
        pytest.skip(f"{name}: no box or cylinder in the fitted tree")
    assert changed >= 1


def _walk(node):
    yield node
    for c in node.get("children", []):
        yield from _walk(c)


def test_saved_fcstd_reopens_and_recomputes_the_same(tmp_path, fitted):
    name, result = fitted
    d = App.newDocument("save_test")
    built = builder.build(d, result)
    volume = built.root.Shape.Volume
    group_name = built.group.Name
    path = str(tmp_path / f"{name}.FCStd")
    d.saveAs(path)
    App.closeDocument(d.Name)
    with H.reopened(path) as group:
        assert group.Name == group_name
        assert group.CsgFitRoot.Shape.Volume == pytest.approx(volume, rel=1e-9)


def _check_fcstd(path, volume=None):
    with H.reopened(path) as group:
        if volume is not None:
            assert group.CsgFitRoot.Shape.Volume == pytest.approx(volume, rel=1e-9)


def test_fcstd_writer_under_freecadcmd(tmp_path, doc):
    src = tmp_path / "in.json"
    src.write_text(json.dumps(ALL_KINDS))
    out = tmp_path / "out.FCStd"
    proc = H.run_fcstd_writer(src, out)
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(tmp_path)) == ["in.json", "out.FCStd"]  # no temporary left over
    _check_fcstd(out, builder.build(doc, ALL_KINDS).root.Shape.Volume)

    # Bad input: one line on stderr, status 2, no output file.
    bad = tmp_path / "bad.json"
    bad.write_text('{"schema": "csgfit/1", "tree": {"type": "hexagon"}}')
    out2 = tmp_path / "bad.FCStd"
    proc = H.run_fcstd_writer(bad, out2)
    assert proc.returncode == 2
    assert "csgfit: error:" in proc.stderr and "hexagon" in proc.stderr
    assert not out2.exists()


def test_cli_writes_fcstd(tmp_path, fitted):
    name, result = fitted
    cli = os.path.join(H.BUILD, "bin", "csgfit")
    if not os.path.exists(cli):
        pytest.skip(f"CLI not built at {cli}")
    H.freecadcmd()
    out = tmp_path / f"{name}.FCStd"
    env = dict(os.environ, CSGFIT_FCSTD_WRITER=WRITER)
    proc = subprocess.run([cli, "image", os.path.join(H.BENCH, name + ".png"), "-o", str(out),
                           "--time", "1", "--pixel-size", str(PIXEL)],
                          capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(tmp_path)) == [out.name]
    _check_fcstd(out)


# A plate with two equal holes and a boss with a concentric hole, as the fit writes it.
SHARED = dict(
    ALL_KINDS, source="plate.png",
    canvas={"width_px": 100, "height_px": 60, "pixel_size": 1.0, "thickness": 2.0},
    tree={"op": "difference", "children": [
        {"op": "union", "children": [
            {"type": "rectangle", "cx": 40, "cy": 30, "w": 60, "h": 30, "angle": 0},
            {"type": "circle", "cx": 75, "cy": 30, "r": 15},
        ]},
        {"type": "circle", "cx": 20, "cy": 30, "r": 5},
        {"type": "circle", "cx": 45, "cy": 30, "r": 5},
        {"type": "circle", "cx": 75, "cy": 30, "r": 6},
    ]},
    shared_dimensions=[
        {"name": "centre_x", "value": 75, "uses": [{"leaf": 1, "field": "cx"},
                                                   {"leaf": 4, "field": "cx"}]},
        {"name": "centre_y", "value": 30, "uses": [{"leaf": 1, "field": "cy"},
                                                   {"leaf": 4, "field": "cy"}]},
        {"name": "hole_r", "value": 5, "uses": [{"leaf": 2, "field": "r"},
                                                {"leaf": 3, "field": "r"}]},
    ],
    stats={"iou": 1.0, "primitives": 5})


def test_shared_radius_cell_changes_every_hole(doc):
    built = builder.build(doc, SHARED)
    assert builder.check_tree(doc, built.group) == []
    v0 = built.root.Shape.Volume
    assert float(built.sheet.get("hole_r")) == 5.0
    built.sheet.set("hole_r", "=4mm")
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    radii = [built.primitives[i][1].Radius.Value for i in (2, 3)]
    assert radii == [4.0, 4.0]
    # Two holes shrink from r 5 to 4: the plate gains 2 * pi * (25 - 16) * thickness.
    assert built.root.Shape.Volume == pytest.approx(v0 + 2 * math.pi * 9 * 2.0, rel=1e-9)


def test_shared_centre_moves_concentric_circles_together(doc):
    built = builder.build(doc, SHARED)
    built.sheet.set("centre_x", "=70mm")
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    for i in (1, 4):
        assert built.primitives[i][1].Placement.Base.x == pytest.approx(70.0)
    # The boss and its hole moved together: the ring's volume is unchanged where it stays
    # clear of the plate's holes, so the solid is the same as built from the edited JSON.
    edited = copy.deepcopy(SHARED["tree"])
    edited["children"][0]["children"][1]["cx"] = 70
    edited["children"][3]["cx"] = 70
    expected = H.static_shape(edited, 2.0)
    assert built.root.Shape.Volume == pytest.approx(expected.Volume, rel=1e-6)


def test_shared_dimension_a_member_no_longer_equals_is_not_tied(doc):
    result = copy.deepcopy(SHARED)
    result["tree"]["children"][2]["r"] = 5.5  # edited by hand after the fit
    built = builder.build(doc, result)
    built.sheet.set("hole_r", "=4mm")
    doc.recompute()
    assert built.primitives[2][1].Radius.Value == 4.0
    assert built.primitives[3][1].Radius.Value == 5.5


def test_shared_bar_width_keeps_both_bars_centred(doc):
    # A cross of two bars 4 wide, one turned by 30 degrees, sharing the side cell.
    result = copy.deepcopy(SHARED)
    result["tree"] = {"op": "union", "children": [
        {"type": "rectangle", "cx": 30, "cy": 30, "w": 4, "h": 40, "angle": 30},
        {"type": "rectangle", "cx": 30, "cy": 30, "w": 40, "h": 4, "angle": 30}]}
    result["shared_dimensions"] = [
        {"name": "rect_side", "value": 4, "uses": [{"leaf": 0, "field": "w"},
                                                   {"leaf": 1, "field": "h"}]}]
    built = builder.build(doc, result)
    built.sheet.set("rect_side", "=6mm")
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    bars = [built.primitives[i][1] for i in (0, 1)]
    assert bars[0].Length.Value == 6.0 and bars[1].Width.Value == 6.0
    for bar in bars:
        centre = bar.Shape.BoundBox.Center
        assert (centre.x, centre.y) == (pytest.approx(30.0), pytest.approx(30.0))
    edited = copy.deepcopy(result["tree"])
    edited["children"][0]["w"] = edited["children"][1]["h"] = 6
    expected = H.static_shape(edited, 2.0)
    assert built.root.Shape.Volume == pytest.approx(expected.Volume, rel=1e-6)
    assert built.root.Shape.common(expected).Volume == pytest.approx(expected.Volume, rel=1e-6)

"""Headless FreeCAD tests of "Mesh to CSG": the builder's 3D path, a fitted mesh fixture built
as a parametric tree, and `csgfit mesh -o X.FCStd`.

The fixture (a block with a cylindrical hole through it, fchelpers.make_fixture, also turned and
moved) is made by the test with Part and written as STL through FreeCAD's Mesh module, so the
mesh volume is known.
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
    import Mesh  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import builder, mesh_input, rounded_box_feature  # noqa: E402

R45Z = [math.cos(math.pi / 8), 0, 0, math.sin(math.pi / 8)]        # 45 degrees about z
R30X = [math.cos(math.pi / 12), math.sin(math.pi / 12), 0, 0]      # 30 degrees about x
TILT = [0.9, 0.3, -0.2, 0.25]                                      # not unit: normalised

ALL_KINDS_3D = {
    "schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "synthetic.stl",
    "grid": {"nx": 60, "ny": 50, "nz": 40, "origin": [-5, -5, -5], "voxel_size": 0.5},
    "tree": {"op": "union", "children": [
        {"op": "difference", "children": [
            {"type": "box", "center": [5, 5, 3], "rotation": R45Z, "size": [8, 6, 4]},
            {"type": "cylinder", "center": [5, 5, 3], "rotation": R30X, "r": 1.5, "h": 10},
            {"type": "prism", "center": [8, 5, 4], "rotation": TILT, "w": 3, "h": 2,
             "depth": 6, "apex": 0.4},
        ]},
        {"op": "intersection", "children": [
            {"type": "sphere", "center": [15, 5, 3], "r": 3},
            {"type": "ellipsoid", "center": [15, 5, 4], "rotation": TILT, "radii": [4, 2, 3]},
        ]},
        {"type": "cone", "center": [22, 5, 3], "rotation": R30X, "r1": 2, "r2": 0.5, "h": 5},
        {"type": "cone", "center": [22, 12, 3], "r1": 1.5, "r2": 1.5, "h": 2},
        {"type": "torus", "center": [5, 16, 3], "rotation": TILT, "R": 3, "r": 0.8},
    ]},
    "stats": {"iou": 1.0, "primitives": 9},
}


@pytest.fixture
def doc():
    d = App.newDocument("csgfit_mesh_test")
    yield d
    App.closeDocument(d.Name)


def test_every_3d_kind_is_placed_as_the_solver_defines_it(doc):
    built = builder.build(doc, ALL_KINDS_3D)
    assert builder.check_tree(doc, built.group) == []
    assert built.group.CsgFitDimension == 3
    types = {o.TypeId for o in built.objects}
    assert types <= set(builder.PARAMETRIC_TYPES)
    assert {"Part::Box", "Part::Cylinder", "Part::Cone", "Part::Sphere", "Part::Ellipsoid",
            "Part::Torus", "Part::Wedge", "Part::Cut", "Part::MultiCommon",
            "Part::MultiFuse"} <= types
    # The equal-radius cone is a cylinder (OCC refuses such a cone).
    assert [o.TypeId for _, o, _ in built.primitives].count("Part::Cylinder") == 2
    expected = H.static_shape3d(ALL_KINDS_3D["tree"])
    got = built.root.Shape
    # Part::Ellipsoid is a B-spline approximation (about 0.05 % of the volume).
    assert got.Volume == pytest.approx(expected.Volume, rel=2e-4)
    assert got.common(expected).Volume == pytest.approx(expected.Volume, rel=2e-4)
    # Each leaf on its own lands where the independent construction puts it.
    for prim, _, obj in built.primitives:
        ref = H.static_shape3d(prim)
        assert obj.Shape.common(ref).Volume == pytest.approx(ref.Volume, rel=2e-4), prim["type"]
    assert json.loads(built.group.CsgFitJson)["tree"] == ALL_KINDS_3D["tree"]
    assert not any(o.Visibility for o in built.objects if o is not built.root)


POLYGONAL_3D = {"op": "union", "children": [
    {"type": "cylinder", "center": [0, 0, 0], "rotation": TILT, "r": 3, "h": 5, "sides": 6},
    {"type": "cone", "center": [10, 0, 0], "rotation": R30X, "r1": 3, "r2": 1.5, "h": 4,
     "sides": 8},
    {"type": "cone", "center": [20, 0, 0], "rotation": R45Z, "r1": 2, "r2": 0, "h": 4, "sides": 4},
    {"type": "cone", "center": [30, 0, 0], "rotation": TILT, "r1": 0, "r2": 2, "h": 3, "sides": 5},
    {"type": "cone", "center": [40, 0, 0], "r1": 2, "r2": 2, "h": 3, "sides": 3},
]}


def test_polygonal_cylinders_and_cones_are_their_polygons(doc):
    built = builder.build(doc, POLYGONAL_3D, label="polygons")
    assert builder.check_tree(doc, built.group) == []
    assert [o.TypeId for _, o, _ in built.primitives] == [
        "Part::Prism", "Part::Loft", "Part::Loft", "Part::Loft", "Part::Prism"]
    for prim, _, obj in built.primitives:
        r1 = prim.get("r1", prim.get("r"))
        volume = H.polygonal_volume(prim["sides"], r1, prim.get("r2", r1), prim["h"])
        shape = obj.Shape
        assert shape.isValid() and len(shape.Solids) == 1, prim
        assert shape.Volume == pytest.approx(volume, rel=1e-6), prim
        # Where the solver puts it: its vertices at the angles OpenSCAD's $fn-gon has them.
        ref = H.static_shape3d(prim)
        assert shape.common(ref).Volume == pytest.approx(volume, rel=1e-6), prim
    # The prism stays centred when its height is edited, as a round cylinder does.
    prism = built.primitives[0][1]
    prism.Height = 7.0
    doc.recompute()
    centre = prism.Shape.CenterOfMass
    assert (centre.x, centre.y, centre.z) == pytest.approx((0, 0, 0), abs=1e-9)


def test_bad_sides_raise_build_error(doc):
    for sides in (2, 1001, 6.5, "6", True):
        tree = {"type": "cylinder", "center": [0, 0, 0], "r": 1, "h": 2, "sides": sides}
        with pytest.raises(builder.BuildError, match="sides"):
            builder.build(doc, tree)
        assert doc.Objects == []


ROUNDED_3D = {"op": "union", "children": [
    {"type": "rounded_box", "center": [0, 0, 0], "rotation": TILT, "size": [20, 10, 4],
     "corner": 3},
    {"type": "rounded_box", "center": [30, 0, 0], "rotation": R45Z, "size": [12, 5, 3],
     "corner": 2.5},
    {"type": "rounded-box", "center": [50, 0, 0], "rotation": R30X, "size": [6, 6, 2],
     "corner": 3},
]}


def test_rounded_boxes_are_features_whose_corner_edits(doc):
    # A rounded box, a stadium and a disc.
    built = builder.build(doc, ROUNDED_3D, label="rounded")
    assert builder.check_tree(doc, built.group) == []
    for prim, _, obj in built.primitives:
        assert rounded_box_feature.is_rounded_box(obj)
        volume = H.rounded_box_volume(prim["size"], prim["corner"])
        shape = obj.Shape
        assert shape.isValid() and len(shape.Solids) == 1, prim
        assert shape.Volume == pytest.approx(volume, rel=1e-6), prim
        # Where the solver puts it, built independently from slabs and cylinders.
        assert shape.common(H.static_shape3d(prim)).Volume == pytest.approx(volume, rel=1e-6), prim
    # Editing the corner recomputes: the rounded box becomes a stadium, the stadium gets smaller
    # corners; both stay centred where they were.
    first, stadium = built.primitives[0][1], built.primitives[1][1]
    first.Radius = 5.0
    stadium.Radius = 1.0
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert first.Shape.Volume == pytest.approx(H.rounded_box_volume((20, 10, 4), 5), rel=1e-6)
    assert stadium.Shape.Volume == pytest.approx(H.rounded_box_volume((12, 5, 3), 1), rel=1e-6)
    for obj, centre in ((first, (0, 0, 0)), (stadium, (30, 0, 0))):
        c = obj.Shape.CenterOfMass
        assert (c.x, c.y, c.z) == pytest.approx(centre, abs=1e-9)
    # A corner over half the width does not recompute.
    first.Radius = 5.5
    doc.recompute()
    assert "Invalid" in first.State or "Error" in first.State


def test_bad_rounded_boxes_raise_build_error(doc):
    rounded = {"type": "rounded_box", "center": [0, 0, 0], "size": [4, 2, 1]}
    for extra, match in (({"corner": 0}, "corner"), ({"corner": 1.01}, "Radius"),
                         ({"corner": "1"}, "corner"), ({}, "corner"),
                         ({"corner": 0.5, "sides": 8}, "sides")):
        with pytest.raises(builder.BuildError, match=match):
            builder.build(doc, dict(rounded, **extra))
        assert doc.Objects == []


def test_editing_a_3d_box_and_prism_stays_parametric(doc):
    tree = {"op": "union", "children": [
        {"type": "box", "center": [0, 0, 0], "rotation": R45Z, "size": [4, 3, 2]},
        {"type": "prism", "center": [20, 0, 0], "w": 4, "h": 3, "depth": 2, "apex": 0.5}]}
    built = builder.build(doc, tree, label="edit3d")
    box, prism = built.primitives[0][1], built.primitives[1][1]
    v0 = built.root.Shape.Volume
    assert v0 == pytest.approx(24 + 12, rel=1e-9)
    box.Height = 5.0
    prism.Zmax = prism.Zmax.Value + 2.0  # Z2max follows: still a prism, 2 mm deeper
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert built.root.Shape.Volume == pytest.approx(60 + 6 * 4, rel=1e-9)


def test_bad_3d_input_raises_build_error_and_leaves_nothing(doc):
    for field, value, match in (("size", [1, -1, 1], "size"), ("rotation", [0, 0, 0, 0], "zero"),
                                ("center", [0, 1], "center")):
        bad = copy.deepcopy(ALL_KINDS_3D)
        bad["tree"]["children"][0]["children"][0][field] = value
        with pytest.raises(builder.BuildError, match=match):
            builder.build(doc, bad)
        assert doc.Objects == []


def test_preview_shape_is_the_built_solid_and_leaves_documents_alone(doc):
    before = set(App.listDocuments())
    shape = builder.preview_shape(ALL_KINDS_3D)
    assert set(App.listDocuments()) == before
    assert shape.isValid()
    assert shape.Volume == pytest.approx(builder.build(doc, ALL_KINDS_3D).root.Shape.Volume,
                                         rel=1e-9)


def test_mesh_feature_arrays_keep_global_coordinates(doc, tmp_path):
    volume = H.make_fixture(tmp_path / "part.stl")
    feature = doc.addObject("Mesh::Feature", "Part")
    feature.Mesh = Mesh.Mesh(str(tmp_path / "part.stl"))
    feature.Placement = App.Placement(App.Vector(100, 0, 0), App.Rotation())
    doc.recompute()
    assert mesh_input.is_mesh_object(feature)
    v, t = mesh_input.arrays_from_mesh(feature)
    assert v.shape[1] == 3 and t.shape[1] == 3 and t.max() < len(v)
    assert v[:, 0].min() == pytest.approx(100.0) and v[:, 0].max() == pytest.approx(132.0)
    # Signed volume by the divergence theorem: the same closed solid.
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    signed = float((a * np.cross(b, c)).sum() / 6)
    assert signed == pytest.approx(volume, rel=1e-5)  # STL keeps float32 coordinates


_fit = {}


def fitted_fixture(tmp_path_factory):
    """(stl path, mesh volume, FitResult3D) of the fixture, fitted once."""
    csgfit = H.csgfit_or_skip()
    if not _fit:
        d = tmp_path_factory.mktemp("fixture")
        path = d / "block_with_hole.stl"
        volume = H.make_fixture(path)
        # 64 voxels along the longest side: the search converges in a few seconds.
        _fit["v"] = (path, volume, csgfit.fit_mesh(str(path), resolution=64, time=30, seed=1,
                                                   threads=2))
    return _fit["v"]


def test_fitted_mesh_builds_a_parametric_solid_of_the_mesh_volume(doc, tmp_path_factory):
    path, mesh_volume, result = fitted_fixture(tmp_path_factory)
    assert result.stats.iou >= 0.97, result
    built = builder.build(doc, result)
    assert doc.recompute() >= 0
    assert builder.check_tree(doc, built.group) == []
    assert built.group.Label == "block_with_hole"
    for obj in built.objects:
        assert obj.TypeId in builder.PARAMETRIC_TYPES, obj.TypeId
    shape = built.root.Shape
    assert shape.isValid() and len(shape.Solids) == 1
    # The mesh: within the voxels' resolution (see make_fixture).
    assert shape.Volume == pytest.approx(mesh_volume, rel=0.015)
    # The tree itself, evaluated independently (exactly) and by the solver (its voxels).
    assert shape.Volume == pytest.approx(H.static_shape3d(result.tree.to_dict()).Volume, rel=1e-6)
    assert shape.Volume == pytest.approx(result.volume(), rel=0.01)
    # The hole is a hole: the solid does not contain the cylinder's axis.
    assert not shape.isInside(App.Vector(20, 10, 6), 1e-6, True)
    assert shape.isInside(App.Vector(5, 5, 6), 1e-6, True)


def test_cli_mesh_writes_fcstd_that_reopens_and_recomputes(tmp_path):
    cli = os.path.join(H.BUILD, "bin", "csgfit")
    if not os.path.exists(cli):
        pytest.skip(f"CLI not built at {cli}")
    H.freecadcmd()
    src = tmp_path / "in"
    src.mkdir()
    # Stood on its side (a quarter turn about x) and moved: faces stay on voxel boundaries.
    turned = App.Placement(App.Vector(3, -2, 1), App.Rotation(App.Vector(1, 0, 0), 90))
    mesh_volume = H.make_fixture(src / "turned.stl", turned)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    out = out_dir / "turned.FCStd"
    env = dict(os.environ, CSGFIT_FCSTD_WRITER=os.path.join(H.WORKBENCH, "csgfit_freecad",
                                                            "fcstd_writer.py"))
    proc = subprocess.run([cli, "mesh", str(src / "turned.stl"), "-o", str(out), "--time", "30",
                           "--resolution", "64", "--threads", "2", "-q"], capture_output=True, text=True, timeout=300,
                          env=env)
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(out_dir)) == [out.name]  # no temporary left over
    with H.reopened(out) as group:
        assert group.CsgFitDimension == 3
        shape = group.CsgFitRoot.Shape
        assert shape.Volume == pytest.approx(mesh_volume, rel=0.015)
        assert shape.BoundBox.ZLength == pytest.approx(20, abs=0.5)  # it stands
        tree = json.loads(group.CsgFitJson)["tree"]
        assert shape.Volume == pytest.approx(H.static_shape3d(tree).Volume, rel=1e-6)
    # A mesh output format the command does not know: status 2, one line, nothing written.
    proc = subprocess.run([cli, "mesh", str(src / "turned.stl"), "-o", str(out_dir / "x.step3")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
    assert sorted(os.listdir(out_dir)) == [out.name]


# A plate with two equal through holes, as csgfit mesh writes it (shared_dimensions from snap3d).
HOLED_PLATE_3D = {
    "schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "plate.stl",
    "grid": {"nx": 60, "ny": 40, "nz": 12, "origin": [-2, -2, -2], "voxel_size": 1.0},
    "tree": {"op": "difference", "children": [
        {"type": "box", "center": [25, 15, 3], "size": [50, 30, 6]},
        {"type": "cylinder", "center": [12, 15, 3], "r": 4, "h": 10},
        {"type": "cylinder", "center": [38, 15, 3], "rotation": [0, 0, 0, 1], "r": 4, "h": 10},
    ]},
    "shared_dimensions": [
        {"name": "hole_r", "value": 4, "uses": [{"leaf": 1, "field": "r"},
                                                {"leaf": 2, "field": "r"}]},
        {"name": "hole_h", "value": 10, "uses": [{"leaf": 1, "field": "h"},
                                                 {"leaf": 2, "field": "h"}]},
    ],
    "stats": {"iou": 1.0, "primitives": 3},
}


def test_shared_hole_radius_cell_resizes_both_holes_in_3d(doc):
    built = builder.build(doc, HOLED_PLATE_3D)
    assert builder.check_tree(doc, built.group) == []
    assert built.root.Shape.Volume == pytest.approx(50 * 30 * 6 - 2 * math.pi * 16 * 6, rel=1e-6)
    built.sheet.set("hole_r", "=3mm")
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert [built.primitives[i][1].Radius.Value for i in (1, 2)] == [3.0, 3.0]
    assert built.root.Shape.Volume == pytest.approx(50 * 30 * 6 - 2 * math.pi * 9 * 6, rel=1e-6)


def test_a_polygons_circumradius_is_not_tied_to_a_shared_radius(doc):
    # A hand-edited document: the second hole made a hexagon but still listed under hole_r.
    result = copy.deepcopy(HOLED_PLATE_3D)
    result["tree"]["children"][2]["sides"] = 6
    built = builder.build(doc, result)
    assert builder.check_tree(doc, built.group) == []
    built.sheet.set("hole_r", "=3mm")
    built.sheet.set("hole_h", "=12mm")
    doc.recompute()
    hexagon = built.primitives[2][1]
    assert hexagon.TypeId == "Part::Prism"
    assert (hexagon.Circumradius.Value, hexagon.Height.Value) == (4.0, 12.0)
    assert built.primitives[1][1].Radius.Value == 3.0


def test_shared_height_keeps_cylinders_centred(doc):
    # Holes 4 tall, centred in the plate: blind on both faces until the cell makes them 10.
    result = copy.deepcopy(HOLED_PLATE_3D)
    for leaf in result["tree"]["children"][1:]:
        leaf["h"] = 4
    result["shared_dimensions"][1]["value"] = 4
    built = builder.build(doc, result)
    assert built.root.Shape.Volume == pytest.approx(50 * 30 * 6 - 2 * math.pi * 16 * 4, rel=1e-6)
    built.sheet.set("hole_h", "=10mm")
    doc.recompute()
    for i in (1, 2):
        box = built.primitives[i][1].Shape.BoundBox
        assert (box.ZMin, box.ZMax) == (pytest.approx(-2.0), pytest.approx(8.0))
    assert built.root.Shape.Volume == pytest.approx(50 * 30 * 6 - 2 * math.pi * 16 * 6, rel=1e-6)

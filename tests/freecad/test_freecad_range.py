"""Headless FreeCAD tests of "Range image to CSG": the range JSON of object_b (seed 002's
Fig. 10 part, ../shared/benchmarks/range) built as a parametric tree, and the .FCStd and
.step files of RangeFitResult.save and `csgfit range -o X.FCStd`."""

import json
import os
import subprocess

import pytest

import fchelpers as H

try:
    import FreeCAD as App  # noqa: E402
    import Part  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import builder  # noqa: E402

RANGE = os.path.join(os.path.dirname(H.BENCH), "range")
OBJECT_B = os.path.join(RANGE, "object_b_ortho.png")
_fit = {}


def object_b():
    """object_b's RangeFitResult, fitted once."""
    csgfit = H.csgfit_or_skip()
    if not os.path.exists(OBJECT_B):
        pytest.skip(f"benchmark {OBJECT_B} not present")
    if not _fit:
        _fit["r"] = csgfit.fit_range(OBJECT_B, time=20, seed=1, threads=2)
    return _fit["r"]


@pytest.fixture
def doc():
    d = App.newDocument("csgfit_range_test")
    yield d
    App.closeDocument(d.Name)


def test_range_result_builds_a_valid_solid_of_the_trees_volume(doc):
    result = object_b()
    built = builder.build(doc, result)
    assert builder.check_tree(doc, built.group) == []
    assert built.group.Label == "object_b_ortho" and built.group.CsgFitDimension == 3
    assert len(built.primitives) == 5
    assert {o.TypeId for o in built.objects} <= set(builder.PARAMETRIC_TYPES)
    assert "Part::Cut" in {o.TypeId for o in built.objects}  # the large cylinder is cut
    shape = built.root.Shape
    assert shape.isValid() and shape.Solids
    # The tree evaluated independently of the builder's objects.
    expected = H.static_shape3d(result.tree.to_dict())
    assert shape.Volume == pytest.approx(expected.Volume, rel=1e-6)
    assert shape.common(expected).Volume == pytest.approx(expected.Volume, rel=1e-6)
    # The block is solid where the cut does not reach, and empty on the cut's axis.
    graph = result.precedence_graph
    cut = next(n.primitive for n in graph.nodes if n.sign == "negative")
    assert not shape.isInside(App.Vector(*cut.center), 1e-6, True)
    # The sheet records the segmentation and the view instead of a voxel grid.
    sheet = built.sheet
    assert sheet.get("A1") == "Surface patches" and int(sheet.get("B1")) == len(result.patches)
    assert int(sheet.get("B2")) == graph.subobjects == 2
    assert float(sheet.get("B3")) == pytest.approx(result.views[0].silhouette_iou)
    assert json.loads(built.group.CsgFitJson)["precedence_graph"] == \
        result.document["precedence_graph"]
    assert "cylinder(" in built.group.CsgFitScad  # Export OpenSCAD reads it back


def test_save_writes_fcstd_and_step_of_the_same_solid(tmp_path):
    result = object_b()
    H.freecadcmd()
    volume = H.static_shape3d(result.tree.to_dict()).Volume
    fcstd = result.save(tmp_path / "object_b.FCStd")
    assert sorted(os.listdir(tmp_path)) == ["object_b.FCStd"]  # no temporary left over
    with H.reopened(fcstd) as group:
        assert group.CsgFitRoot.Shape.Volume == pytest.approx(volume, rel=1e-6)
    step = result.save(tmp_path / "object_b.step")
    assert Part.read(step).Volume == pytest.approx(volume, rel=1e-6)


def test_cli_range_writes_fcstd_that_reopens_and_recomputes(tmp_path):
    cli = os.path.join(H.BUILD, "bin", "csgfit")
    if not os.path.exists(cli):
        pytest.skip(f"CLI not built at {cli}")
    if not os.path.exists(OBJECT_B):
        pytest.skip(f"benchmark {OBJECT_B} not present")
    H.freecadcmd()
    out = tmp_path / "object_b.FCStd"
    env = dict(os.environ, CSGFIT_FCSTD_WRITER=os.path.join(H.WORKBENCH, "csgfit_freecad",
                                                            "fcstd_writer.py"))
    proc = subprocess.run([cli, "range", OBJECT_B, "-o", str(out), "--threads", "2", "-q"],
                          capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(tmp_path)) == [out.name]
    with H.reopened(out) as group:
        doc = json.loads(group.CsgFitJson)
        assert doc["precedence_graph"]["subobjects"] == 2
        assert len(doc["precedence_graph"]["nodes"]) == 5
        shape = group.CsgFitRoot.Shape
        assert shape.Volume == pytest.approx(H.static_shape3d(doc["tree"]).Volume, rel=1e-6)

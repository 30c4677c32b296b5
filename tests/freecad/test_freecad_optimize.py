"""Headless FreeCAD tests of "Optimize CSG tree": a Part boolean tree with redundant parts is
optimised beside itself into a smaller parametric tree that recomputes to a valid solid of the
same volume, the original kept, and one undo step takes it all back."""

import pytest

import fchelpers as H

try:
    import FreeCAD as App  # noqa: E402
    import Part  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import optimize_tree  # noqa: E402


@pytest.fixture
def doc():
    d = App.newDocument("csgfit_optimize_test")
    d.UndoMode = 1
    yield d
    App.closeDocument(d.Name)


def redundant_tree(doc):
    """(box - cylinder) fused with a sphere inside the box and a copy of the box: 4 leaves, of
    which two add nothing to the solid."""
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 20, 16, 10
    cyl = doc.addObject("Part::Cylinder", "Hole")
    cyl.Radius, cyl.Height = 3, 30
    cyl.Placement.Base = App.Vector(10, 8, -10)
    cut = doc.addObject("Part::Cut", "Cut")
    cut.Base, cut.Tool = box, cyl
    ball = doc.addObject("Part::Sphere", "Ball")
    ball.Radius = 2
    ball.Placement.Base = App.Vector(4, 4, 5)
    again = doc.addObject("Part::Box", "Again")
    again.Length, again.Width, again.Height = 5, 5, 5
    fuse = doc.addObject("Part::MultiFuse", "Fuse")
    fuse.Shapes = [cut, ball, again]
    doc.recompute()
    return fuse


def leaves(obj):
    if obj.TypeId in optimize_tree.BOOLEAN_TYPES or obj.TypeId == "Part::MultiFuse":
        kids = list(getattr(obj, "Shapes", None) or []) or [obj.Base, obj.Tool]
        return [leaf for k in kids for leaf in leaves(k)]
    return [obj]


def test_optimised_tree_is_smaller_same_volume_and_one_undo_step(doc):
    H.csgfit_or_skip()
    tree = redundant_tree(doc)
    volume = tree.Shape.Volume
    count = len(doc.Objects)
    root, result = optimize_tree.optimize_object(tree)
    assert result.primitives_before == 4 and result.primitives_after == 2
    assert root.Shape.isValid() and abs(root.Shape.Volume - volume) < 1e-3 * volume
    assert len(leaves(root)) == 2
    assert tree in doc.Objects and tree.Shape.isValid()  # the original stays
    assert root.Label == "Fuse (optimized)"
    doc.undo()
    assert len(doc.Objects) == count


def test_a_tree_that_is_already_minimal_comes_back_the_same_size(doc):
    H.csgfit_or_skip()
    box = doc.addObject("Part::Box", "Box")
    cyl = doc.addObject("Part::Cylinder", "Hole")
    cyl.Radius, cyl.Height = 0.3, 3
    cyl.Placement.Base = App.Vector(0.5, 0.5, -1)
    cut = doc.addObject("Part::Cut", "Cut")
    cut.Base, cut.Tool = box, cyl
    doc.recompute()
    root, result = optimize_tree.optimize_object(cut)
    assert result.size_after == result.size_before == 3
    assert abs(root.Shape.Volume - cut.Shape.Volume) < 1e-6

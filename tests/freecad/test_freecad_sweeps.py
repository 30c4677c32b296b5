"""Headless FreeCAD tests of sweeps (csgfit_freecad/sweep_objects.py): the subtrees of a 3D
document's "sweeps" built as a Part::Extrusion or Part::Revolution of a profile of faces, which
must recompute to a valid solid of the tree's own volume, evaluated independently with Part's
primitives (fchelpers.static_shape3d). The documents' sweeps come from csgfit.find_sweeps (the
C++ analysis the JSON writer uses); hand-made parts and random sweeps, a new seed every run
(CSGFIT_TEST_SEED replays one).
"""

import copy
import math
import os
import random

import pytest

import fchelpers as H

try:
    import FreeCAD as App  # noqa: E402
except ImportError as e:  # pragma: no cover
    pytest.skip(f"FreeCAD Python API not available ({e})", allow_module_level=True)

from csgfit_freecad import builder, rounded_box_feature  # noqa: E402

doc = H.document_fixture("csgfit_sweeps_test")

#: The tree's volume, as the brief asks of every FreeCAD tree: within 1e-4 of it.
REL = 1e-4


def q_axis(axis, degrees):
    """Unit quaternion [w, x, y, z] of a turn about a unit axis."""
    h = math.radians(degrees) / 2
    return [math.cos(h)] + [math.sin(h) * a for a in axis]


def q_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return [w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2]


def q_rotate(q, v):
    w, x, y, z = q
    p = q_mul(q_mul(q, [0.0] + list(v)), [w, -x, -y, -z])
    return p[1:]


# The parts of tests/cpp/sweep_parts.h, as JSON trees.
PLATE = {"op": "difference", "children": [
    {"type": "box", "center": [16, 16, 10], "size": [26, 18, 4]},
    {"type": "cylinder", "center": [8, 11, 10], "r": 2.5, "h": 8},
    {"type": "cylinder", "center": [24, 11, 10], "r": 2.5, "h": 8},
    {"type": "cylinder", "center": [16, 20, 10], "rotation": q_axis((0, 0, 1), 10), "r": 3,
     "h": 4, "sides": 6}]}
ROUNDED_PLATE = {"op": "difference", "children": [
    {"type": "rounded_box", "center": [16, 16, 10], "rotation": q_axis((0, 0, 1), 90),
     "size": [18, 26, 4], "corner": 4},
    {"type": "cylinder", "center": [9, 16, 10], "r": 2.5, "h": 8},
    {"type": "rounded_box", "center": [22, 16, 10], "rotation": q_axis((0, 0, 1), 30),
     "size": [8, 3, 6], "corner": 1.5}]}
BRACKET = {"op": "union", "children": [
    {"type": "box", "center": [16, 16, 6], "size": [24, 14, 4]},
    {"type": "box", "center": [6, 16, 15], "size": [4, 14, 22]}]}
TURNED = {"op": "union", "children": [
    {"op": "difference", "children": [
        {"type": "cylinder", "center": [16, 16, 16], "r": 9, "h": 12},
        {"type": "cylinder", "center": [16, 16, 16], "r": 4, "h": 16}]},
    {"type": "torus", "center": [16, 16, 16], "R": 9, "r": 2}]}
STEPS = {"op": "union", "children": [
    {"type": "box", "center": [10, 16, 6], "size": [12, 12, 4]},
    {"type": "box", "center": [22, 16, 8], "size": [12, 8, 8]}]}
# A tilted knob: a cone upside down, a sphere, a torus near its axis (its profile is a
# polygon, a half disc and a circle) and a flipped triangular prism plate beside it.
TILT = q_axis((0.6, 0.8, 0), 25)
FLIP = q_mul(TILT, q_axis((1, 0, 0), 180))
KNOB = {"op": "union", "children": [
    {"type": "cylinder", "center": [0, 0, 0], "rotation": TILT, "r": 3, "h": 4},
    {"type": "cone", "center": q_rotate(TILT, (0, 0, 4)), "rotation": FLIP, "r1": 3, "r2": 1,
     "h": 4},
    {"type": "sphere", "center": q_rotate(TILT, (0, 0, 7)), "r": 2},
    {"type": "torus", "center": q_rotate(TILT, (0, 0, -2)), "rotation": TILT, "R": 3, "r": 2}]}


def leaf_count(tree):
    return sum(leaf_count(c) for c in tree["children"]) if "op" in tree else 1


def document(tree, shared=()):
    csgfit = H.csgfit_or_skip()
    return {"schema": "csgfit/1", "dimension": 3, "units": "mm", "source": "part.stl",
            "tree": tree, "shared_dimensions": list(shared), "sweeps": csgfit.find_sweeps(tree),
            "stats": {}}


def check_built(doc, tree, label):
    """Builds the tree's document; the solid is valid and is the tree (static_shape3d of it),
    leaf for leaf registered; returns (BuildResult, the types of its objects)."""
    built = builder.build(doc, document(tree), label=label)
    assert builder.check_tree(doc, built.group) == [], label
    expected = H.static_shape3d(tree)
    shape = built.root.Shape
    assert shape.Volume == pytest.approx(expected.Volume, rel=REL), label
    assert shape.common(expected).Volume == pytest.approx(expected.Volume, rel=REL), label
    assert len(built.primitives) == leaf_count(tree), label
    return built, {o.TypeId for o in built.objects}


@pytest.mark.parametrize("tree, label, sweep", [
    (PLATE, "plate", "Part::Extrusion"), (ROUNDED_PLATE, "rounded_plate", "Part::Extrusion"),
    (BRACKET, "bracket", "Part::Extrusion"),
    (TURNED, "turned", "Part::Revolution"), (KNOB, "knob", "Part::Revolution")])
def test_hand_made_sweeps_are_swept_profiles_of_the_trees_volume(doc, tree, label, sweep):
    built, types = check_built(doc, tree, label)
    # The sweep, fused with itself: one solid however its profile's faces were split.
    assert built.root.TypeId == "Part::MultiFuse" and built.root.Shapes[0].TypeId == sweep
    assert len(built.root.Shape.Solids) == 1
    # Sections are faces, not solids: no Part::Box or Part::Cylinder is left.
    assert not types & {"Part::Box", "Part::Cylinder", "Part::Cone", "Part::Sphere",
                        "Part::Torus", "Part::Prism", "Part::Wedge"}
    assert types <= set(builder.PARAMETRIC_TYPES)


def test_a_tree_without_sweeps_is_built_from_solids(doc):
    built, types = check_built(doc, STEPS, "steps")
    assert "Part::Extrusion" not in types and "Part::Box" in types


def test_a_sweep_beside_other_solids_is_one_input_of_their_boolean(doc):
    tree = {"op": "union", "children": [copy.deepcopy(PLATE),
                                        {"type": "sphere", "center": [16, 16, 14], "r": 3}]}
    built, types = check_built(doc, tree, "plate_and_ball")
    assert [o.TypeId for o in built.root.Shapes] == ["Part::MultiFuse", "Part::Sphere"]
    assert "Part::Extrusion" in types


def test_shared_hole_radius_cell_resizes_both_holes_of_an_extrusion(doc):
    shared = [{"name": "hole_r", "value": 2.5,
               "uses": [{"leaf": 1, "field": "r"}, {"leaf": 2, "field": "r"}]}]
    built = builder.build(doc, document(PLATE, shared), label="plate")
    v0 = built.root.Shape.Volume
    built.sheet.set("hole_r", "=3mm")
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    assert [built.primitives[i][1].Radius.Value for i in (1, 2)] == [3.0, 3.0]
    assert built.root.Shape.Volume == pytest.approx(v0 - 2 * math.pi * (9 - 6.25) * 4, rel=1e-9)


def test_editing_a_section_keeps_it_centred_and_a_revolved_band_on_its_axis(doc):
    built = builder.build(doc, document(copy.deepcopy(TURNED)), label="turned")
    band = built.primitives[0][1]  # the outer cylinder's band [0, 9] x [10, 22]
    assert band.TypeId == "Part::Plane"
    band.Width = 14.0  # its height: 2 more, 1 each way
    band.Length = 10.0  # its radius
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    wider = copy.deepcopy(TURNED)
    wider["children"][0]["children"][0].update(r=10, h=14)
    expected = H.static_shape3d(wider)
    assert built.root.Shape.common(expected).Volume == pytest.approx(expected.Volume, rel=REL)
    assert built.root.Shape.Volume == pytest.approx(expected.Volume, rel=REL)
    plate = builder.build(doc, document(copy.deepcopy(PLATE)), label="plate")
    rectangle = plate.primitives[0][1]
    rectangle.Length = 30.0
    doc.recompute()
    box = plate.root.Shape.BoundBox
    assert (box.XMin, box.XMax) == (pytest.approx(1.0), pytest.approx(31.0))


def test_a_rounded_boxs_section_is_a_rounded_rectangle_whose_radius_edits(doc):
    built = builder.build(doc, document(copy.deepcopy(ROUNDED_PLATE)), label="rounded_plate")
    plate, slot = built.primitives[0][1], built.primitives[2][1]
    assert rounded_box_feature.is_rounded_rectangle(plate)
    # The plane sees the plate's long side first; the slot is a stadium.
    assert (plate.Length.Value, plate.Width.Value, plate.Radius.Value) == (26, 18, 4)
    assert (slot.Length.Value, slot.Width.Value, slot.Radius.Value) == (8, 3, 1.5)
    plate.Radius = 9.0  # the plate becomes a stadium too
    doc.recompute()
    assert builder.check_tree(doc, built.group) == []
    rounder = copy.deepcopy(ROUNDED_PLATE)
    rounder["children"][0]["corner"] = 9
    expected = H.static_shape3d(rounder)
    assert built.root.Shape.Volume == pytest.approx(expected.Volume, rel=REL)
    assert built.root.Shape.common(expected).Volume == pytest.approx(expected.Volume, rel=REL)
    # Its centre stays where it was.
    box = built.root.Shape.BoundBox
    assert (box.XMin, box.XMax, box.YMin, box.YMax) == \
        tuple(pytest.approx(v) for v in (3, 29, 7, 25))
    # A corner over half the smaller side is refused, as the rounded box's own is.
    stale = document(copy.deepcopy(ROUNDED_PLATE))
    stale["sweeps"][0]["sections"][0]["r"] = 10
    stale["tree"]["children"][0]["corner"] = 10
    with pytest.raises(builder.BuildError, match="Radius must be"):
        builder.build(doc, stale)


def test_sweeps_that_do_not_describe_the_tree_are_refused(doc):
    good = document(copy.deepcopy(PLATE))
    edited = copy.deepcopy(good)
    edited["tree"]["children"][1]["r"] = 3.5  # a hole widened by hand, its sweep left as it was
    moved = copy.deepcopy(good)
    moved["tree"]["children"][3]["center"][0] += 1  # the hexagonal hole moved
    bad_node = copy.deepcopy(good)
    bad_node["sweeps"][0]["node"] = 1  # a leaf
    bad_count = copy.deepcopy(good)
    del bad_count["sweeps"][0]["sections"][3]
    for bad, match in ((edited, "does not describe leaf 1"),
                       (moved, "does not describe leaf 3"), (bad_node, "operator"),
                       (bad_count, "one section per leaf")):
        with pytest.raises(builder.BuildError, match=match):
            builder.build(doc, bad)
        assert doc.Objects == []


# ---- random sweeps ----------------------------------------------------------------------------

def random_frame(rng):
    if rng.random() < 0.5:
        axis, angle = rng.choice([((1, 0, 0), 0), ((1, 0, 0), 180), ((1, 0, 0), 90),
                                  ((1, 0, 0), -90), ((0, 1, 0), 90), ((0, 1, 0), -90)])
        return q_axis(axis, angle)
    q = [rng.gauss(0, 1) for _ in range(4)]
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def placed(rng, leaf, frame, local, to_axis=(1, 0, 0, 0)):
    """The leaf turned about the frame's axis, upside down half the time, at frame * local."""
    turn = q_axis((0, 0, 1), rng.uniform(-180, 180))
    flip = q_axis((1, 0, 0), 180) if rng.random() < 0.5 else [1, 0, 0, 0]
    leaf["rotation"] = q_mul(q_mul(q_mul(frame, turn), flip), list(to_axis))
    leaf["center"] = [16 + c for c in q_rotate(frame, local)]
    return leaf


def prism_leaf(rng, frame, subtracted):
    """A prism along the frame's z over [-4.5, 4.5] (a subtracted one may reach beyond): a box,
    a round or polygonal cylinder, a triangular prism or a rounded box."""
    lo, hi = -4.5, 4.5
    if subtracted and rng.random() < 0.5:
        lo, hi = lo - rng.uniform(0.5, 3), hi + rng.uniform(0.5, 3)
    local = (rng.uniform(-5, 5), rng.uniform(-5, 5), (lo + hi) / 2)

    def dim():
        return rng.uniform(2, 8)

    kind = rng.randrange(5)
    if kind == 0:
        k = rng.randrange(3)
        size = [dim(), dim(), dim()]
        size[k] = hi - lo
        to_axis = (q_axis((0, 1, 0), -90), q_axis((1, 0, 0), 90), [1, 0, 0, 0])[k]
        return placed(rng, {"type": "box", "size": size}, frame, local, to_axis)
    if kind == 3:
        return placed(rng, {"type": "prism", "w": dim(), "h": dim(), "depth": hi - lo,
                            "apex": rng.uniform(-1.2, 1.2)}, frame, local)
    if kind == 4:  # a rounded box, a stadium one time in five
        sx, sy = dim(), dim()
        u = rng.random()
        corner = min(sx, sy) / 2 * (1 if u < 0.2 else 0.1 + 0.8 * u)
        return placed(rng, {"type": "rounded_box", "size": [sx, sy, hi - lo], "corner": corner},
                      frame, local)
    leaf = {"type": "cylinder", "r": dim() / 2, "h": hi - lo}
    if kind == 2:
        leaf["sides"] = rng.randrange(3, 9)
    return placed(rng, leaf, frame, local)


def round_leaf(rng, frame, subtracted):
    """A solid round about the frame's z axis through (16, 16, 16)."""
    local = (0, 0, rng.uniform(-5, 5))
    size = rng.uniform(2, 8)
    kind = rng.randrange(4)
    if kind == 0:
        leaf = {"type": "cylinder", "r": size / 2, "h": rng.uniform(2, 8)}
    elif kind == 1:
        leaf = {"type": "cone", "r1": size / 2, "h": rng.uniform(2, 8),
                "r2": 0 if rng.random() < 0.3 else rng.uniform(0.7, 2.7)}
    elif kind == 2:
        leaf = {"type": "torus", "R": size / 2, "r": size / 2 * rng.uniform(0.25, 0.85)}
    else:
        leaf = {"type": "sphere", "r": size / 2}
    return placed(rng, leaf, frame, local)


def random_tree(rng, depth, subtracted, make_leaf):
    if depth <= 0 or rng.random() < 1 / 3:
        return make_leaf(rng, subtracted)
    op = rng.choice(["union", "union", "difference", "intersection"])
    children = [random_tree(rng, depth - 1, subtracted != (op == "difference" and i > 0),
                            make_leaf) for i in range(rng.randrange(2, 4))]
    return {"op": op, "children": children}


def random_sweep(rng, linear):
    """(tree, frame): a tree that is one sweep as a whole, as tests/cpp/random_sweeps.h makes
    them, and the frame it was made in."""
    frame = random_frame(rng)
    if linear:
        return random_tree(rng, 2, False, lambda g, s: prism_leaf(g, frame, s)), frame
    torus = placed(rng, {"type": "torus", "R": 2.5, "r": 1.25}, frame, (0, 0, rng.uniform(-5, 5)))
    return {"op": "union", "children": [
        random_tree(rng, 2, False, lambda g, s: round_leaf(g, frame, s)), torus]}, frame


def leaves(tree):
    return [x for c in tree["children"] for x in leaves(c)] if "op" in tree else [tree]


def sectioned_volume(tree, frame, linear):
    """The volume of a random sweep (made in `frame`, centred on (16, 16, 16)) from its leaves'
    exact sections: each leaf's solid cut by the frame's mid-plane (a linear sweep: the
    profile's area times its height, 9) or by the plane through its axis, on the half x >= 0
    (a revolution: 2 pi times the profile's area times its centroid's distance from the axis),
    combined by 2D booleans. OCC does those reliably; its 3D booleans on these trees, whose
    prisms share their end planes, lose whole pieces now and then (static_shape3d found an
    intersection of three parallel cylinders empty)."""
    import Part

    centre = App.Vector(16, 16, 16)
    x, y, z = (App.Vector(*q_rotate(frame, e)) for e in ((1, 0, 0), (0, 1, 0), (0, 0, 1)))
    normal = z if linear else y
    half = Part.Face(Part.makePolygon([centre + x * a + z * b for a, b in
                                       ((0, -50), (50, -50), (50, 50), (0, 50), (0, -50))]))

    def section(node):
        if "op" in node:
            faces = [section(c) for c in node["children"]]
            out = faces[0]
            for f in faces[1:]:
                out = {"union": out.fuse, "intersection": out.common,
                       "difference": out.cut}[node["op"]](f)
            return out
        wires = H.static_shape3d(node).slice(normal, normal.dot(centre))
        face = Part.makeCompound([Part.Face(w) for w in wires])
        return face if linear else face.common(half)

    faces = section(tree).Faces
    area = sum(f.Area for f in faces)
    if linear or area == 0:
        return area * 9
    # Pappus: each face's area times the circle its centroid runs round the axis.
    return 2 * math.pi * sum(f.Area * abs((f.CenterOfMass - centre).dot(x)) for f in faces)


def agrees_pointwise(shape, tree, rng, points=300):
    """Points where `shape` and the tree's leaves, each classified on its own, disagree."""
    solids = [(leaf, H.static_shape3d(leaf)) for leaf in leaves(tree)]
    inside_leaf = {id(leaf): s for leaf, s in solids}

    def inside(node, p):
        if "op" not in node:
            return inside_leaf[id(node)].isInside(p, 1e-9, True)
        vals = [inside(c, p) for c in node["children"]]
        return {"union": any(vals), "intersection": all(vals),
                "difference": vals[0] and not any(vals[1:])}[node["op"]]

    box = shape.BoundBox
    wrong = []
    for _ in range(points):
        p = App.Vector(rng.uniform(box.XMin, box.XMax), rng.uniform(box.YMin, box.YMax),
                       rng.uniform(box.ZMin, box.ZMax))
        if inside(tree, p) != shape.isInside(p, 1e-9, True):
            wrong.append(p)
    return wrong


def test_random_sweeps_recompute_to_the_trees_volume(doc):
    csgfit = H.csgfit_or_skip()
    seed = int(os.environ.get("CSGFIT_TEST_SEED") or random.SystemRandom().randrange(2 ** 63))
    rng = random.Random(seed)
    built = 0
    while built < 12:
        linear = built % 2 == 0
        tree, frame = random_sweep(rng, linear)
        volume = sectioned_volume(tree, frame, linear)
        # Trees that draw almost nothing (an empty intersection) say little.
        if leaf_count(tree) < 2 or volume < 5:
            continue
        where = f"random{built} (CSGFIT_TEST_SEED={seed}): {tree}"
        assert [s["node"] for s in csgfit.find_sweeps(tree)] == [0], where
        result = builder.build(doc, document(tree), label=f"random{built}")
        assert builder.check_tree(doc, result.group) == [], where
        shape = result.root.Shape
        assert shape.Volume == pytest.approx(volume, rel=REL), where
        assert len(shape.Solids) >= 1
        assert agrees_pointwise(shape, tree, rng) == [], where
        assert ("Part::Extrusion" if linear else "Part::Revolution") in \
            {o.TypeId for o in result.objects}, where
        built += 1

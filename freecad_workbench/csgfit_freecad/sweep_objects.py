"""Sweeps of a 3D tree (the JSON's "sweeps", written by csgfit; docs/JSON_SCHEMA.md): subtrees
a designer draws as a 2D profile swept along an axis (OpenSCAD's linear_extrude) or about one
(rotate_extrude), built so: each leaf's section is a Part face in the sweep's plane, the faces
are combined as the subtree combines its leaves, one Part::Extrusion or Part::Revolution sweeps
the result, and a refined Part::MultiFuse of it with itself makes that one solid.

  section          face                                          holds the leaf's
  rectangle        Part::Plane (Length = w, Width = h)           w, h (a cylinder's r and h)
  rounded          Part::FeaturePython "csgfit rounded rectangle"  w, h = Length, Width and
  rectangle        (rounded_box_feature.py), centred             r = Radius (a rounded box's)
  circle           Part::Face of a Part::Circle                  Radius
  circle, sides    Part::Face of a Part::RegularPolygon          Polygon, Circumradius
  triangle         Part::Face of a closed Part::Polygon          its corners (Nodes)
  polygon          Part::Face of a closed Part::Polygon          its corners (a cone's profile)
  half_disc        Part::MultiCommon of a circle's face and a Part::Plane on its x >= cx side
  union / intersection / difference of faces: Part::MultiFuse / Part::MultiCommon / Part::Cut

A linear sweep's plane is its frame's local xy plane, extruded along local z over [0, height];
a revolution's profile lies in the frame's local xz plane (x >= 0, x the distance from the axis)
and turns about local z.
"""

from __future__ import annotations

import math
from typing import Any, Dict, Iterator, List, Tuple

import FreeCAD as App

from . import rounded_box_feature
from .part_objects import BuildError, _number, _sides, _vector, rotation3d

LINEAR, REVOLUTION = "linear_extrude", "rotate_extrude"

#: The section each leaf has in each kind of sweep, and the section's numbers that are the
#: leaf's own (a hand-edited tree whose sweeps no longer describe it is refused by them).
_SECTION = {
    (LINEAR, "box"): "rectangle", (LINEAR, "cylinder"): "circle", (LINEAR, "prism"): "triangle",
    (LINEAR, "rounded_box"): "rounded_rectangle",
    (REVOLUTION, "cylinder"): "rectangle", (REVOLUTION, "cone"): "polygon",
    (REVOLUTION, "torus"): "circle", (REVOLUTION, "sphere"): "half_disc",
}


def _same_sizes(kind: str, leaf: Dict[str, Any], s: Dict[str, Any]) -> bool:
    """Whether the section's sizes are the leaf's."""
    def near(a, b):
        return isinstance(a, (int, float)) and isinstance(b, (int, float)) and \
            math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12)

    t = leaf["type"]
    if t == "box":
        size = leaf.get("size") or []
        return all(any(near(s.get(k), v) for v in size) for k in ("w", "h"))
    if t == "rounded_box":
        size = (leaf.get("size") or [])[:2]
        return len(size) == 2 and near(s.get("r"), leaf.get("corner")) and \
            any(near(s.get("w"), a) and near(s.get("h"), b) for a, b in (size, size[::-1]))
    if t == "prism":
        return all(near(s.get(k), leaf.get(k)) for k in ("w", "h")) and \
            near(abs(s.get("apex", 0.0)), abs(leaf.get("apex", 0.0)))
    if t == "cylinder" and kind == LINEAR:
        return near(s.get("r"), leaf.get("r")) and s.get("sides") == leaf.get("sides")
    if t == "cylinder":
        return near(s.get("w"), leaf.get("r")) and near(s.get("h"), leaf.get("h"))
    if t == "torus":
        return near(s.get("cx"), leaf.get("R")) and near(s.get("r"), leaf.get("r"))
    if t == "sphere":
        return near(s.get("r"), leaf.get("r"))
    xs = [p[0] for p in s.get("points") or [] if isinstance(p, list) and p]
    return bool(xs) and near(max(xs), max(leaf.get("r1", 0.0), leaf.get("r2", 0.0)))


def _same_place(kind: str, leaf: Dict[str, Any], s: Dict[str, Any], frame) -> bool:
    """Whether the section is where the leaf is: at its centre in the sweep's plane, or (a
    revolution's) at its height along the axis."""
    try:
        at = frame.inverse().multVec(App.Vector(*_vector(leaf, "center", 3, "leaf")))
    except BuildError:
        return False
    tolerance = 1e-9 * (1 + max(abs(at.x), abs(at.y), abs(at.z)))

    def near(a, b):
        return isinstance(a, (int, float)) and not isinstance(a, bool) and \
            math.isclose(a, b, rel_tol=0, abs_tol=tolerance)

    if kind == LINEAR:
        return near(s.get("cx"), at.x) and near(s.get("cy"), at.y)
    if s.get("type") == "polygon":
        ys = [p[1] for p in s.get("points") or [] if isinstance(p, list) and len(p) > 1]
        return bool(ys) and near((min(ys) + max(ys)) / 2, at.z)
    return near(s.get("cy"), at.z)


def _preorder(tree: Any) -> List[Tuple[Any, int, int]]:
    """(node, its first leaf's index, its number of leaves) for every node, in pre-order."""
    out: List[Tuple[Any, int, int]] = []

    def walk(d, first_leaf):
        entry = [d, first_leaf, 0]
        out.append(entry)
        if isinstance(d, dict) and isinstance(d.get("children"), list) and "op" in d:
            n = 0
            for c in d["children"]:
                n += walk(c, first_leaf + n)
            entry[2] = n
        else:
            entry[2] = 1
        return entry[2]

    walk(tree, 0)
    return [tuple(e) for e in out]


def node_count(d: Any) -> int:
    """Nodes of a subtree, itself included."""
    return len(_preorder(d))


def sweeps_by_node(sweeps: Any, tree: Any) -> Dict[int, Dict[str, Any]]:
    """The document's sweeps keyed by the pre-order index of their node. Raises BuildError on a
    sweep that does not describe the tree (its node, leaves, sections, their sizes or places
    differ): the block is derived from the tree when written, so a tree edited by hand must
    lose it (or get it again from csgfit.find_sweeps)."""
    if sweeps is None:
        return {}
    if not isinstance(sweeps, list):
        raise BuildError("'sweeps' must be an array")
    nodes = _preorder(tree)
    leaves = [d for d, _, n in nodes if not (isinstance(d, dict) and "op" in d)]
    out = {}
    for i, sweep in enumerate(sweeps):
        where = f"sweeps[{i}]"
        if not isinstance(sweep, dict) or sweep.get("kind") not in (LINEAR, REVOLUTION):
            raise BuildError(f"{where}: 'kind' must be {LINEAR!r} or {REVOLUTION!r}")
        node = sweep.get("node")
        if not isinstance(node, int) or isinstance(node, bool) or not 0 <= node < len(nodes) \
                or "op" not in nodes[node][0]:
            raise BuildError(f"{where}: 'node' must be the index of an operator of the tree")
        frame = App.Placement(App.Vector(*_vector(sweep, "center", 3, where)),
                              rotation3d(sweep, where))
        if sweep["kind"] == LINEAR:
            _number(sweep, "height", where, positive=True)
        _check_sections(sweep, frame, leaves, nodes[node][1], nodes[node][2], where)
        out[node] = sweep
    return out


def _check_sections(sweep, frame, leaves, first, count, where):
    sections = sweep.get("sections")
    if not isinstance(sections, list) or len(sections) != count:
        raise BuildError(f"{where}: 'sections' must have one section per leaf of its node")
    for k, s in enumerate(sections):
        leaf = leaves[first + k]
        expected = _SECTION.get((sweep["kind"], leaf.get("type") if isinstance(leaf, dict) else None))
        if expected is None or not isinstance(s, dict) or s.get("leaf") != first + k \
                or s.get("type") != expected or not _same_sizes(sweep["kind"], leaf, s) \
                or not _same_place(sweep["kind"], leaf, s, frame):
            raise BuildError(f"{where}.sections[{k}] does not describe leaf {first + k} of the "
                             "tree (the tree was edited after csgfit wrote it: drop 'sweeps')")


# ---- building ----------------------------------------------------------------------------------

def build(tree, d: Dict[str, Any], sweep: Dict[str, Any], where: str):
    """The subtree d as the Part::Extrusion or Part::Revolution of its profile, made one solid
    (tree: the PartTree building the document, whose primitives get each leaf in pre-order,
    its section's objects standing for it)."""
    z = App.Vector(0, 0, 1)
    frame = App.Placement(App.Vector(*_vector(sweep, "center", 3, where)), rotation3d(sweep, where))
    linear = sweep["kind"] == LINEAR
    # A revolution's profile is drawn in the frame's xz plane: its y runs up the axis.
    plane = frame if linear else frame.multiply(
        App.Placement(App.Vector(), App.Rotation(App.Vector(1, 0, 0), 90)))
    profile = _profile(tree, d, iter(sweep["sections"]), plane, not linear, where)
    axis = frame.Rotation.multVec(z)
    if linear:
        obj = tree._add("Part::Extrusion", "Extrusion")
        obj.Base = profile
        obj.DirMode = "Custom"
        obj.Dir = axis
        obj.LengthFwd = float(sweep["height"])
    else:
        obj = tree._add("Part::Revolution", "Revolution")
        obj.Source = profile
        obj.Base = frame.Base
        obj.Axis = axis
        obj.Angle = 360.0
    obj.Solid = True
    # FreeCAD 0.20 refines no compound of faces: the profile stays split where its pieces
    # met, and its sweep is a compound of solids touching there. Fused with itself (a fuse of
    # one shape is refused when that compound holds one solid) and refined, it is one solid,
    # as the subtree is.
    solid = tree._add("Part::MultiFuse", "Extruded" if linear else "Revolved")
    solid.Shapes = [obj, obj]
    solid.Refine = True
    return solid


def _profile(tree, d, sections: Iterator[Dict[str, Any]], plane, revolved: bool, where: str):
    if "op" in d:
        op, kids = tree.operator_parts(d, where)
        return tree.combine(op, [_profile(tree, c, sections, plane, revolved,
                                          f"{where}.children[{i}]") for i, c in enumerate(kids)])
    section = next(sections)
    holder, face = _FACES[section["type"]](tree, section, plane, revolved,
                                           f"{where} ({section['type']})")
    tree.primitives.append((d, holder, face))
    return face


def _at(plane, x: float, y: float, angle: float = 0.0, offset=(0.0, 0.0)):
    """The placement of a shape drawn about its own origin (offset: where that is in the
    shape's own axes), turned by `angle` degrees and put at (x, y) of the sweep's plane."""
    return plane.multiply(App.Placement(App.Vector(x, y, 0), App.Rotation(App.Vector(0, 0, 1), angle))) \
        .multiply(App.Placement(App.Vector(offset[0], offset[1], 0), App.Rotation()))


def _keep_placed(obj, anchor, lengthwise: bool) -> None:
    """Ties a Part::Plane's corner to its Width (and Length when `lengthwise`) so that its
    middle stays at `anchor` when they change: a revolution's band keeps its edge on the axis
    and grows away from it."""
    u = obj.Placement.Rotation.multVec(App.Vector(1, 0, 0))
    v = obj.Placement.Rotation.multVec(App.Vector(0, 1, 0))
    for c, a, b, name in zip((anchor.x, anchor.y, anchor.z), (u.x, u.y, u.z), (v.x, v.y, v.z), "xyz"):
        length = f" - Length / 2 * ({a!r})" if lengthwise else ""
        obj.setExpression(f"Placement.Base.{name}", f"{c!r}mm{length} - Width / 2 * ({b!r})")


def _face(tree, edge, label: str):
    face = tree._add("Part::Face", label)
    face.Sources = [edge]
    return face


def _rectangle(tree, s, plane, revolved, where):
    w, h = (_number(s, k, where, positive=True) for k in ("w", "h"))
    cx, cy, angle = (_number(s, k, where, default=0.0) for k in ("cx", "cy", "angle"))
    obj = tree._add("Part::Plane", "RectangleSection")
    obj.Length, obj.Width = w, h
    obj.Placement = _at(plane, cx, cy, angle, (-w / 2, -h / 2))
    # A revolution's band [0, r] stays on the axis; a box's section stays centred.
    anchor = _at(plane, 0.0 if revolved else cx, cy).Base
    _keep_placed(obj, anchor, lengthwise=not revolved)
    return obj, obj


def _rounded_rectangle(tree, s, plane, revolved, where):
    w, h, r = (_number(s, k, where, positive=True) for k in ("w", "h", "r"))
    cx, cy, angle = (_number(s, k, where, default=0.0) for k in ("cx", "cy", "angle"))
    try:
        obj = tree._add(rounded_box_feature.TYPE_ID, "RoundedRectangleSection",
                        lambda doc, name: rounded_box_feature.make_rounded_rectangle(
                            doc, name, w, h, r))
    except rounded_box_feature.OutlineError as e:
        raise BuildError(f"{where}: {e} (w {w}, h {h}, r {r})") from None
    # Centred on its own origin, so it stays centred when its sizes change.
    obj.Placement = _at(plane, cx, cy, angle)
    return obj, obj


def _circle(tree, s, plane, revolved, where):
    r = _number(s, "r", where, positive=True)
    cx, cy, angle = (_number(s, k, where, default=0.0) for k in ("cx", "cy", "angle"))
    sides = _sides(s, where)
    if sides:
        edge = tree._add("Part::RegularPolygon", "PolygonSection")
        edge.Polygon, edge.Circumradius = sides, r
    else:
        edge = tree._add("Part::Circle", "CircleSection")
        edge.Radius = r
    edge.Placement = _at(plane, cx, cy, angle)
    return edge, _face(tree, edge, "SectionFace")


def _corners(tree, points, placement, label: str):
    wire = tree._add("Part::Polygon", label)
    wire.Nodes = [App.Vector(x, y, 0) for x, y in points]
    wire.Close = True
    wire.Placement = placement
    return wire, _face(tree, wire, "SectionFace")


def _triangle(tree, s, plane, revolved, where):
    w, h = (_number(s, k, where, positive=True) for k in ("w", "h"))
    cx, cy, angle, apex = (_number(s, k, where, default=0.0) for k in ("cx", "cy", "angle", "apex"))
    points = [(-w / 2, -h / 2), (w / 2, -h / 2), (apex * w / 2, h / 2)]
    return _corners(tree, points, _at(plane, cx, cy, angle), "TriangleSection")


def _polygon(tree, s, plane, revolved, where):
    points = s.get("points")
    if not isinstance(points, list) or len(points) < 3:
        raise BuildError(f"{where}: 'points' must be an array of at least 3 points")
    pts = [_vector({"p": p}, "p", 2, where) for p in points]
    return _corners(tree, pts, plane, "PolygonSection")


def _half_disc(tree, s, plane, revolved, where):
    circle, disc = _circle(tree, s, plane, revolved, where)
    r = _number(s, "r", where, positive=True)
    cx, cy = (_number(s, k, where, default=0.0) for k in ("cx", "cy"))
    # Twice the disc's reach each way, so that a larger radius stays a half disc.
    half = tree._add("Part::Plane", "HalfPlane")
    half.Length, half.Width = 2 * r, 4 * r
    half.Placement = _at(plane, cx, cy - 2 * r)
    obj = tree._add("Part::MultiCommon", "HalfDisc")
    obj.Shapes = [disc, half]
    return circle, obj


_FACES = {"rectangle": _rectangle, "rounded_rectangle": _rounded_rectangle, "circle": _circle,
          "triangle": _triangle, "polygon": _polygon, "half_disc": _half_disc}

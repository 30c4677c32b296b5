"""JSON primitives and operators -> parametric FreeCAD Part objects: where a primitive of the
solver becomes a FreeCAD object (builder.py puts them in a group with their parameters).

Mapping of a 2D result (model units, y up, angles in degrees counter-clockwise; extruded from
z = 0 to z = thickness):

  rectangle  Part::Box       Length = w, Width = h, Placement: centre at (cx, cy), rotated about z
                             (its corner an expression of Length and Width: it stays centred)
  circle     Part::Cylinder  Radius = r, Placement at (cx, cy)
  ellipse    Part::Ellipse (MajorRadius, MinorRadius, Placement) + Part::Extrusion (Solid)
  triangle   Part::Wedge     base Xmin..Xmax at Ymin, apex X2min (= X2max) at Ymax
  union          Part::MultiFuse
  intersection   Part::MultiCommon
  difference     Part::Cut(first, rest) with rest = Part::MultiFuse of the subtracted children
                 when there are several

Every height is an expression on the thickness cell of a spreadsheet in the group, so changing
one cell changes the extrusion of the whole tree. Nothing is baked into a static shape.

A 3D result ("dimension": 3, from csgfit mesh / csgfit.fit_mesh) keeps the mesh's coordinates.
Each primitive of the solver is centred on its local origin and turned by its quaternion
(primitive3d.h); FreeCAD's Box grows from a corner and Cylinder / Cone from the base, so their
Placement is centre + R * (local offset of that corner or base), rotation = the quaternion:

  box        Part::Box        Length, Width, Height = size; offset (-x/2, -y/2, -z/2)
  sphere     Part::Sphere     Radius
  cylinder   Part::Cylinder   Radius, Height; offset (0, 0, -h/2), an expression of Height (it
                              stays centred when the height changes)
  cone       Part::Cone       Radius1 (bottom) = r1, Radius2 = r2, Height; offset as a cylinder's
                              (a Part::Cylinder when r1 == r2: OCC refuses such a cone)
  cylinder   Part::Prism      with "sides": Polygon = sides, Circumradius = r, Height; offset as a
                              round cylinder's; its vertex 0 on local +x, as OpenSCAD's $fn-gon,
                              so the rotation's turn about the axis is the polygon's phase
  cone       Part::Loft       with "sides" (r1 != r2): Solid, Ruled, of two Part::RegularPolygon
                              (Polygon = sides, Circumradius = r1 / r2) placed at local z = -h/2
                              and +h/2, or a Part::Vertex at a pointed end
  ellipsoid  Part::Ellipsoid  Radius2 = rx, Radius3 = ry, Radius1 = rz (FreeCAD's Radius1 is z)
  torus      Part::Torus      Radius1 = R, Radius2 = r
  prism      Part::Wedge      the 2D triangle's wedge over z in [-depth/2, depth/2]; X2max and
                              Z2min/Z2max are expressions on X2min and Zmin/Zmax
  nurbs      Part::FeaturePython "csgfit NURBS terminal" (nurbs_feature.py): DegreeU/V, CountU/V,
                              KnotsU/V, ControlPoints (local), SizeX/Y; the local origin is the
                              centre, on the floor z = 0 under the patch
  rounded_box  Part::FeaturePython "csgfit rounded box" (rounded_box_feature.py): Length, Width,
                              Height = size, Radius = corner; centred on its local origin (a
                              Part::Fillet of a box cannot make the stadium, Radius = Width / 2)

A subtree the document lists in "sweeps" (a profile extruded along an axis or turned about one)
is built by sweep_objects.py instead: its leaves' sections as faces, one Part::Extrusion or
Part::Revolution.
"""

from __future__ import annotations

import math
from typing import Any, Dict, List, Optional, Tuple

import FreeCAD as App

from . import nurbs_feature, rounded_box_feature

PRIMITIVE_TYPES = ("Part::Box", "Part::Cylinder", "Part::Ellipse", "Part::Extrusion",
                   "Part::Wedge", "Part::Sphere", "Part::Cone", "Part::Ellipsoid", "Part::Torus",
                   "Part::Prism", "Part::RegularPolygon", "Part::Vertex", "Part::Loft",
                   nurbs_feature.TYPE_ID,
                   # A sweep's sections and its sweep (sweep_objects.py).
                   "Part::Plane", "Part::Circle", "Part::Polygon", "Part::Face",
                   "Part::Revolution")
BOOLEAN_TYPES = ("Part::MultiFuse", "Part::MultiCommon", "Part::Cut", "Part::Fuse",
                 "Part::Common")
#: Every object type the builder creates (besides the group and its spreadsheet).
PARAMETRIC_TYPES = PRIMITIVE_TYPES + BOOLEAN_TYPES


class BuildError(ValueError):
    """The result cannot be turned into a FreeCAD tree (malformed JSON, unknown node)."""


def _number(d: Dict[str, Any], key: str, where: str, positive: bool = False,
            default: Optional[float] = None) -> float:
    if key not in d:
        if default is not None:
            return default
        raise BuildError(f"{where}: missing '{key}'")
    v = d[key]
    if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
        raise BuildError(f"{where}: '{key}' must be a finite number")
    if positive and v <= 0:
        raise BuildError(f"{where}: '{key}' must be > 0")
    return float(v)


def _placement(cx: float, cy: float, angle: float, local: Tuple[float, float] = (0.0, 0.0)):
    """Placement that puts local point `local` of a shape rotated by `angle` about z at
    (cx, cy) + R(angle) * local; i.e. the shape's local origin ends up at that point."""
    a = math.radians(angle)
    c, s = math.cos(a), math.sin(a)
    x, y = local
    base = App.Vector(cx + c * x - s * y, cy + s * x + c * y, 0.0)
    return App.Placement(base, App.Rotation(App.Vector(0, 0, 1), angle))


def _keep_box_centred(obj, cx: float, cy: float, angle: float) -> None:
    """Ties a Part::Box's corner to its Length and Width so that it stays centred on (cx, cy)
    when they change (as OpenSCAD's square(center = true) does): a corner-anchored box would
    grow lopsided when the user edits a side."""
    a = f"({angle!r})"
    obj.setExpression("Placement.Base.x",
                      f"{cx!r}mm - Length / 2 * cos{a} + Width / 2 * sin{a}")
    obj.setExpression("Placement.Base.y",
                      f"{cy!r}mm - Length / 2 * sin{a} - Width / 2 * cos{a}")


def _keep_centred_on_axis(obj, centre) -> None:
    """Ties a Part::Cylinder's or Cone's base to its Height so that it stays centred on
    `centre` along its axis when the height changes (as the .scad's center = true does)."""
    axis = obj.Placement.Rotation.multVec(App.Vector(0, 0, 1))
    for c, a, name in zip(centre, (axis.x, axis.y, axis.z), "xyz"):
        obj.setExpression(f"Placement.Base.{name}", f"{c!r}mm - Height / 2 * ({a!r})")


def _vector(d: Dict[str, Any], key: str, n: Optional[int], where: str,
            positive: bool = False) -> List[float]:
    """d[key] as an array of n finite numbers (any number of them when n is None)."""
    return _numbers(d.get(key), n, f"{where}: '{key}'", positive)


def _numbers(v: Any, n: Optional[int], what: str, positive: bool = False) -> List[float]:
    if not isinstance(v, list) or (n is not None and len(v) != n):
        raise BuildError(f"{what} must be an array of {n or 'finite'} numbers")
    for x in v:
        if not isinstance(x, (int, float)) or isinstance(x, bool) or not math.isfinite(x):
            raise BuildError(f"{what} must hold finite numbers")
    if positive and v and min(v) <= 0:
        raise BuildError(f"{what} must be > 0")
    return [float(x) for x in v]


def rotation3d(d: Dict[str, Any], where: str = "primitive"):
    """The primitive's unit quaternion [w, x, y, z] (local -> model) as an App.Rotation;
    identity when absent."""
    if "rotation" not in d:
        return App.Rotation()
    w, x, y, z = _vector(d, "rotation", 4, where)
    norm = math.sqrt(w * w + x * x + y * y + z * z)
    if norm < 1e-12:
        raise BuildError(f"{where}: 'rotation' is a zero quaternion")
    return App.Rotation(x / norm, y / norm, z / norm, w / norm)  # FreeCAD's order: x, y, z, w


def placement3d(center, rotation, local=(0.0, 0.0, 0.0)):
    """Placement putting the object's own origin at local point `local` of a primitive centred
    at `center` and turned by `rotation`: base = center + R * local."""
    offset = rotation.multVec(App.Vector(*local))
    return App.Placement(App.Vector(*center) + offset, rotation)


class PartTree:
    """Makes the Part objects of one tree (2D when thickness_expr is given, else 3D) and keeps
    what it made, for build() and for undoing a failed build."""

    def __init__(self, doc, group, sheet, thickness_expr: str):
        self.doc = doc
        self.group = group
        self.sheet = sheet
        self.t = thickness_expr
        self.created: List[Any] = []
        self.primitives: List[Tuple[Dict[str, Any], Any, Any]] = []
        self.counts: Dict[str, int] = {}
        #: Subtrees built as sweeps (sweep_objects.sweeps_by_node), by pre-order node index.
        self.sweeps: Dict[int, Dict[str, Any]] = {}
        self._next_node = 0  # pre-order index of the next node node() builds

    def _add(self, type_name: str, label: str, make=None):
        """A new object of the tree, labelled label001, label002, ...; make(doc, name) makes it
        when it is not a plain addObject (a FeaturePython)."""
        n = self.counts.get(label, 0) + 1
        self.counts[label] = n
        obj = make(self.doc, label) if make else self.doc.addObject(type_name, label)
        obj.Label = f"{label}{n:03d}"
        self.created.append(obj)
        return obj

    def node(self, d: Any, where: str):
        if not isinstance(d, dict):
            raise BuildError(f"{where}: a node must be an object")
        index = self._next_node
        self._next_node += 1
        if index in self.sweeps:
            from . import sweep_objects  # it builds on this module

            self._next_node += sweep_objects.node_count(d) - 1
            return sweep_objects.build(self, d, self.sweeps[index], where)
        if "op" in d:
            return self.operator(d, where)
        if "type" in d:
            return self.primitive(d, where)
        raise BuildError(f"{where}: a node needs 'op' or 'type'")

    def operator(self, d: Dict[str, Any], where: str):
        op, kids = self.operator_parts(d, where)
        return self.combine(op, [self.node(c, f"{where}.children[{i}]") for i, c in enumerate(kids)])

    @staticmethod
    def operator_parts(d: Dict[str, Any], where: str):
        """(op, children) of an operator node, checked."""
        op = d["op"]
        kids = d.get("children")
        if not isinstance(kids, list) or not kids:
            raise BuildError(f"{where}: '{op}' needs a non-empty 'children' array")
        if op not in ("union", "difference", "intersection"):
            raise BuildError(f"{where}: unknown op {op!r}")
        return op, kids

    def combine(self, op: str, children):
        """The boolean `op` of built objects (solids, or a sweep's faces)."""
        if len(children) == 1:
            return children[0]
        if op == "union":
            return self.fuse(children, "Union")
        if op == "intersection":
            obj = self._add("Part::MultiCommon", "Intersection")
            obj.Shapes = children
            return obj
        tool = children[1] if len(children) == 2 else self.fuse(children[1:], "Subtracted")
        obj = self._add("Part::Cut", "Difference")
        obj.Base = children[0]
        obj.Tool = tool
        return obj

    def fuse(self, children, label: str):
        obj = self._add("Part::MultiFuse", label)
        obj.Shapes = children
        return obj

    def primitive(self, d: Dict[str, Any], where: str):
        """A leaf: a 2D primitive extruded to the thickness expression, or a 3D one placed."""
        kind = d["type"]
        where = f"{where} ({kind})"
        makers = _MAKERS_2D if self.t is not None else _MAKERS_3D
        if kind not in makers:
            raise BuildError(f"{where}: unknown primitive type {kind!r}")
        holder, obj = makers[kind](self, d, where)
        self.primitives.append((d, holder, obj))
        return obj

    def _wedge(self, label: str, w: float, h: float, apex: float):
        """A Part::Wedge whose cross-section is the solver's triangle (base from (-w/2, -h/2)
        to (w/2, -h/2), apex at (apex * w/2, h/2)); the caller sets its z extent."""
        obj = self._add("Part::Wedge", label)
        obj.Xmin, obj.Xmax = -w / 2, w / 2
        obj.Ymin, obj.Ymax = -h / 2, h / 2
        obj.X2min = obj.X2max = apex * w / 2
        # The wedge's top edge degenerates to the apex; tying X2max to X2min keeps it a
        # triangle when the user moves the apex.
        obj.setExpression("X2max", "X2min")
        return obj

    # ---- 2D: extruded from z = 0 to the thickness cell -----------------------------------

    def _rectangle(self, d, where):
        w, h = _sizes(d, where, "w", "h")
        obj = self._add("Part::Box", "Rectangle")
        obj.Length, obj.Width = w, h
        obj.setExpression("Height", self.t)
        centre, angle = _centre(d, where), _angle(d, where)
        obj.Placement = _placement(*centre, angle, (-w / 2, -h / 2))
        _keep_box_centred(obj, *centre, angle)
        return obj, obj

    def _circle(self, d, where):
        obj = self._add("Part::Cylinder", "Circle")
        obj.Radius = _number(d, "r", where, True)
        obj.setExpression("Height", self.t)
        obj.Placement = _placement(*_centre(d, where), 0.0)
        return obj, obj

    def _ellipse(self, d, where):
        rx, ry = _sizes(d, where, "rx", "ry")
        angle = _angle(d, where)
        # Part::Ellipse wants MajorRadius >= MinorRadius along its local x axis.
        if rx < ry:
            rx, ry, angle = ry, rx, angle + 90.0
        curve = self._add("Part::Ellipse", "EllipseCurve")
        curve.MajorRadius, curve.MinorRadius = rx, ry
        curve.Placement = _placement(*_centre(d, where), angle)
        obj = self._add("Part::Extrusion", "Ellipse")
        obj.Base = curve
        obj.DirMode = "Custom"
        obj.Dir = App.Vector(0, 0, 1)
        obj.Solid = True
        obj.setExpression("LengthFwd", self.t)
        return curve, obj

    def _triangle(self, d, where):
        w, h = _sizes(d, where, "w", "h")
        obj = self._wedge("Triangle", w, h, _number(d, "apex", where, default=0.0))
        obj.Zmin = obj.Z2min = 0.0
        obj.setExpression("Zmax", self.t)
        obj.setExpression("Z2max", self.t)
        obj.Placement = _placement(*_centre(d, where), _angle(d, where))
        return obj, obj

    # ---- 3D: centred on "center", turned by "rotation" -----------------------------------

    def _box(self, d, where):
        sx, sy, sz = _vector(d, "size", 3, where, True)
        obj = self._add("Part::Box", "Box")
        obj.Length, obj.Width, obj.Height = sx, sy, sz
        obj.Placement = _placement3d(d, where, (-sx / 2, -sy / 2, -sz / 2))
        return obj, obj

    def _sphere(self, d, where):
        obj = self._add("Part::Sphere", "Sphere")
        obj.Radius = _number(d, "r", where, True)
        obj.Placement = _placement3d(d, where)
        return obj, obj

    def _cylinder(self, d, where, radius="r"):
        r, h = _sizes(d, where, radius, "h")
        sides = _sides(d, where)
        if sides:
            obj = self._add("Part::Prism", "PolygonalCylinder")
            obj.Polygon, obj.Circumradius, obj.Height = sides, r, h
        else:
            obj = self._add("Part::Cylinder", "Cylinder")
            obj.Radius, obj.Height = r, h
        obj.Placement = _placement3d(d, where, (0.0, 0.0, -h / 2))
        _keep_centred_on_axis(obj, _vector(d, "center", 3, where))
        return obj, obj

    def _cone(self, d, where):
        if d.get("r1") == d.get("r2"):
            return self._cylinder(d, where, "r1")  # OCC refuses a cone with equal radii
        r1 = _number(d, "r1", where)
        r2 = _number(d, "r2", where)
        h = _number(d, "h", where, True)
        if r1 < 0 or r2 < 0 or max(r1, r2) <= 0:
            raise BuildError(f"{where}: 'r1' and 'r2' must be >= 0, one of them > 0")
        sides = _sides(d, where)
        if sides:
            return self._pyramid_frustum(d, where, sides, (r1, r2), h)
        obj = self._add("Part::Cone", "Cone")
        obj.Radius1, obj.Radius2, obj.Height = r1, r2, h
        obj.Placement = _placement3d(d, where, (0.0, 0.0, -h / 2))
        _keep_centred_on_axis(obj, _vector(d, "center", 3, where))
        return obj, obj

    def _pyramid_frustum(self, d, where, sides, radii, h):
        """The ruled loft between the end polygons (their vertices at the same angles, as
        OpenSCAD's cylinder($fn) has them); a pointed end is a vertex."""
        ends = []
        for r, z, label in zip(radii, (-h / 2, h / 2), ("ConeBottom", "ConeTop")):
            if r > 0:
                end = self._add("Part::RegularPolygon", label)
                end.Polygon, end.Circumradius = sides, r
            else:
                end = self._add("Part::Vertex", label)
            end.Placement = _placement3d(d, where, (0.0, 0.0, z))
            ends.append(end)
        obj = self._add("Part::Loft", "PolygonalCone")
        obj.Sections = ends
        obj.Solid = obj.Ruled = True
        return obj, obj

    def _ellipsoid(self, d, where):
        rx, ry, rz = _vector(d, "radii", 3, where, True)
        obj = self._add("Part::Ellipsoid", "Ellipsoid")
        # FreeCAD's Radius1 is along local z, Radius2 along x, Radius3 along y.
        obj.Radius1, obj.Radius2, obj.Radius3 = rz, rx, ry
        obj.Placement = _placement3d(d, where)
        return obj, obj

    def _torus(self, d, where):
        obj = self._add("Part::Torus", "Torus")
        obj.Radius1, obj.Radius2 = _sizes(d, where, "R", "r")
        obj.Placement = _placement3d(d, where)
        return obj, obj

    def _prism(self, d, where):
        w, h, depth = _sizes(d, where, "w", "h", "depth")
        obj = self._wedge("Prism", w, h, _number(d, "apex", where, default=0.0))
        obj.Zmin, obj.Zmax = -depth / 2, depth / 2
        obj.Z2min, obj.Z2max = -depth / 2, depth / 2
        # The far face follows when the user edits Zmin or Zmax: still a triangular prism.
        obj.setExpression("Z2min", "Zmin")
        obj.setExpression("Z2max", "Zmax")
        obj.Placement = _placement3d(d, where)
        return obj, obj

    def _rounded_box(self, d, where):
        size = _vector(d, "size", 3, where, True)
        corner = _number(d, "corner", where, True)
        if "sides" in d:
            raise BuildError(f"{where}: a rounded box has round corners only, no 'sides'")
        try:
            obj = self._add(rounded_box_feature.TYPE_ID, "RoundedBox",
                            lambda doc, name: rounded_box_feature.make_rounded_box(
                                doc, name, size, corner))
        except rounded_box_feature.OutlineError as e:
            raise BuildError(f"{where}: {e} (size {size}, corner {corner})") from None
        # Centred on its local origin: no offset, unlike the Part::Box's corner.
        obj.Placement = _placement3d(d, where)
        return obj, obj

    def _nurbs(self, d, where):
        leaf = _nurbs_leaf(d, where)
        try:
            obj = self._add(nurbs_feature.TYPE_ID, "NURBS",
                            lambda doc, name: nurbs_feature.make_nurbs(doc, name, leaf))
        except nurbs_feature.NetError as e:
            raise BuildError(f"{where}: {e}") from None
        # The local origin is the centre on the floor: no offset, unlike the box's corner.
        obj.Placement = _placement3d(d, where)
        return obj, obj


def _integers(d: Dict[str, Any], key: str, n: int, where: str) -> List[int]:
    """d[key] as n positive integers (integral floats, as some writers emit, included)."""
    v = _vector(d, key, n, where, True)
    if any(x != int(x) for x in v):
        raise BuildError(f"{where}: '{key}' must hold integers")
    return [int(x) for x in v]


def _nurbs_leaf(d: Dict[str, Any], where: str) -> Dict[str, Any]:
    """The patch of a "nurbs" leaf with its shapes checked: degree and counts pairs of
    integers, the knot vectors' numbers, nu x nv control points of three numbers each and the
    rectangle's positive size (the size's third number, the top, is information only). Whether
    the knots make a clamped B-spline is the feature's own check."""
    nu, nv = _integers(d, "counts", 2, where)
    size = _vector(d, "size", None, where)
    if len(size) not in (2, 3) or min(size[:2]) <= 0:
        raise BuildError(f"{where}: 'size' must be [sx, sy, top] with sx, sy > 0")
    points = d.get("control_points")
    if not isinstance(points, list) or len(points) != nu * nv:
        raise BuildError(f"{where}: 'control_points' must be an array of {nu} x {nv} points")
    return {"degree": _integers(d, "degree", 2, where), "counts": [nu, nv], "size": size[:2],
            "knots_u": _vector(d, "knots_u", None, where),
            "knots_v": _vector(d, "knots_v", None, where),
            "control_points": [_numbers(p, 3, f"{where}: control point {k}")
                               for k, p in enumerate(points)]}


#: The most sides a polygonal cylinder or cone may have (Primitive3D::kMaxSides).
MAX_SIDES = 1000


def _sides(d: Dict[str, Any], where: str) -> int:
    """A cylinder's or cone's "sides": 0 when it is round (no "sides"), else its polygon's."""
    if "sides" not in d:
        return 0
    v = d["sides"]
    if not isinstance(v, int) or isinstance(v, bool) or not 3 <= v <= MAX_SIDES:
        raise BuildError(f"{where}: 'sides' must be an integer from 3 to {MAX_SIDES}")
    return v


def _sizes(d: Dict[str, Any], where: str, *keys: str) -> List[float]:
    """The positive numbers d[key] for each key."""
    return [_number(d, key, where, True) for key in keys]


def _centre(d: Dict[str, Any], where: str) -> Tuple[float, float]:
    return _number(d, "cx", where), _number(d, "cy", where)


def _angle(d: Dict[str, Any], where: str) -> float:
    return _number(d, "angle", where, default=0.0)


def _placement3d(d: Dict[str, Any], where: str, local=(0.0, 0.0, 0.0)):
    return placement3d(_vector(d, "center", 3, where), rotation3d(d, where), local)


# The JSON names of each dimension's primitives (and the aliases the readers accept).
_MAKERS_2D = {"rectangle": PartTree._rectangle, "rect": PartTree._rectangle,
              "circle": PartTree._circle, "ellipse": PartTree._ellipse,
              "triangle": PartTree._triangle}
_MAKERS_3D = {"box": PartTree._box, "cube": PartTree._box, "sphere": PartTree._sphere,
              "cylinder": PartTree._cylinder, "cone": PartTree._cone, "frustum": PartTree._cone,
              "ellipsoid": PartTree._ellipsoid, "torus": PartTree._torus,
              "prism": PartTree._prism, "wedge": PartTree._prism,
              "triangular_prism": PartTree._prism, "nurbs": PartTree._nurbs,
              "rounded_box": PartTree._rounded_box, "rounded-box": PartTree._rounded_box,
              "roundedbox": PartTree._rounded_box}

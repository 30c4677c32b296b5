"""Builds a morph between two shapes (csgfit morph, issue 13) as ONE parametric Part tree.

A morph document is a csgfit/1 result of shape A with a "morph" key holding tree B (same
operators and primitive types, leaf for leaf). The tree is built with the structure of tree A
by the ordinary builder (builder.assemble, part_objects.PartTree); every number of a primitive
that differs between A and B becomes a FreeCAD expression of the parameter sheet's cell
`morph` (0 = A, 1 = B):  value_A + (value_B - value_A) * morph, exactly as the solver
interpolates (model/interpolate.cpp). Numbers equal in A and B stay plain values, so they
can still be edited.

Placement follows the solver's interpolation at every frame:
  2D  Base.x / Base.y = centre + R(angle) * (local corner offset), with cos/sin of the
      interpolated angle; Rotation.Angle = the interpolated angle about +z. Tree B's angles
      already end the chosen turn, so the plain linear angle is the morph.
      An ellipse takes max/min of its radii and adds 90 degrees while rx < ry
      (Part::Ellipse wants MajorRadius >= MinorRadius).
  3D  the whole Placement is one expression (FreeCAD 0.20's create(<<placement>>; ...),
      create(<<rotation>>; ...), rotation * rotation, placement * placement):
          create(<<placement>>; centre; R(axis, morph * angle) * R_A)
              * create(<<placement>>; local offset of the corner or base; identity)
      with (axis, angle) the short-arc turn from R_A to R_B. This is exact.

Sizes: a primitive seen in one shape only has size 0 at that end, and OpenCASCADE refuses
zero-size solids, so every size is max(value, <sheet>.min_size). min_size is 1e-3 pixel
(2D) or voxel (3D): the sliver left at that end changes the area or volume by about
min_size^2 (min_size^3), far below what the fit resolves. A cone whose radii meet keeps
Radius2 min_size away from Radius1 (Part::Cone refuses equal radii).
"""

from __future__ import annotations

import functools
import math
from typing import Any, Dict, List, Optional, Tuple

from . import builder
from .part_objects import _MAKERS_2D, _MAKERS_3D, BuildError, PartTree, _number, _vector

MORPH_CELL = "morph"
MIN_SIZE_CELL = "min_size"
#: The size floor, as a fraction of a pixel (2D) or voxel (3D).
MIN_SIZE_FRACTION = 1e-3


def load_morph(source: Any) -> Dict[str, Any]:
    """The morph document (see builder.load_result for what `source` may be); BuildError when
    it has no "morph" with a "tree_b"."""
    result = builder.load_result(source)
    morph = result.get("morph")
    if not isinstance(morph, dict) or not isinstance(morph.get("tree_b"), dict):
        raise BuildError("not a morph document (no 'morph' with a 'tree_b')")
    return result


def is_morph(result: Dict[str, Any]) -> bool:
    """Whether a loaded csgfit/1 document is a morph."""
    return isinstance(result.get("morph"), dict)


def paired_leaves(a: Any, b: Any, where: str = "tree") -> List[Dict[str, Any]]:
    """Tree B's leaves in pre-order, after checking that B has A's structure and primitive
    types leaf for leaf (BuildError naming the first difference)."""
    if not isinstance(a, dict) or not isinstance(b, dict):
        raise BuildError(f"{where}: a node must be an object")
    if "op" in a:
        kids_a, kids_b = a.get("children"), b.get("children")
        if b.get("op") != a["op"] or not isinstance(kids_b, list) or not isinstance(kids_a, list) \
                or len(kids_a) != len(kids_b):
            raise BuildError(f"{where}: tree_b differs from tree in structure")
        leaves = []
        for i, (ca, cb) in enumerate(zip(kids_a, kids_b)):
            leaves += paired_leaves(ca, cb, f"{where}.children[{i}]")
        return leaves
    if "sides" in a or "sides" in b:  # csgfit morph never makes one
        raise BuildError(f"{where}: a polygonal cylinder or cone is not morphed")
    makers = {**_MAKERS_2D, **_MAKERS_3D}
    maker = makers.get(a.get("type"))  # an unknown type is MorphTree.primitive's error
    if "op" in b or (maker is not None and maker is not makers.get(b.get("type"))):
        raise BuildError(f"{where}: tree_b has {b.get('type') or b.get('op')!r} where tree has "
                         f"{a.get('type')!r}")
    return [b]


def min_size(result: Dict[str, Any]) -> float:
    """The size floor in mm: MIN_SIZE_FRACTION of a pixel or voxel."""
    if builder.dimension(result) == 2:
        cell = float((result.get("canvas") or {}).get("pixel_size") or 1.0)
    else:
        cell = float((result.get("grid") or {}).get("voxel_size") or 1.0)
    return MIN_SIZE_FRACTION * cell


def build_morph(doc, source: Any, *, thickness: Optional[float] = None,
                label: Optional[str] = None, recompute: bool = True) -> builder.BuildResult:
    """Adds the morph's tree to `doc`: one parametric Part tree with tree A's structure whose
    dimensions and placements are expressions of the parameter sheet's cell `morph`
    (default 0 = shape A; 1 = shape B; 0.3 shows that frame).

    source: a morph document (dict, JSON text, path, or an object with to_json()).
    thickness, label: as builder.build. The sheet also gets the `min_size` cell (the floor of
    every size, see the module's docstring); the group records tree B's source
    (CsgFitSourceB) and IoU (CsgFitIoUB) besides build()'s record of shape A.
    Raises BuildError on malformed input (nothing is left in the document then).
    """
    result = load_morph(source)
    morph = result["morph"]
    leaves_b = paired_leaves(result["tree"], morph["tree_b"])
    floor = min_size(result)
    rows = [("Morph (0 = A, 1 = B)", "0", MORPH_CELL),
            ("Smallest size (mm)", f"={floor!r}mm", MIN_SIZE_CELL)]
    make_tree = functools.partial(MorphTree, leaves_b=leaves_b, floor=floor)
    built = builder.assemble(doc, result, result["tree"], result.get("stats") or {},
                             thickness=thickness, label=label, recompute=False,
                             make_tree=make_tree, extra_rows=rows)
    _record_b(built.group, morph)
    if recompute:
        doc.recompute()
    return built


def set_morph(sheet, value: float) -> None:
    """Shows the frame at `value` (0 = A, 1 = B) once the document recomputes."""
    sheet.set(MORPH_CELL, repr(float(value)))


def _record_b(group, morph: Dict[str, Any]) -> None:
    """Shape B's side of the record (build()'s properties describe shape A)."""
    for kind, pname, text, value in (
            ("App::PropertyString", "CsgFitSourceB", "Input of shape B (morph = 1)",
             morph.get("source_b") or ""),
            ("App::PropertyFloat", "CsgFitIoUB", "IoU of tree B against shape B",
             float((morph.get("stats_b") or {}).get("iou") or 0.0))):
        group.addProperty(kind, pname, "CSG Fit", text)
        setattr(group, pname, value)
        group.setEditorMode(pname, 1)


def _mm(v: float, unit: str) -> str:
    text = f"{v!r} {unit}".rstrip()
    return f"({text})" if v < 0 else text


class MorphTree(PartTree):
    """A PartTree whose leaves pair tree A's primitive with tree B's (in pre-order): each is
    made by PartTree's own maker from A's values (sizes floored) and then given expressions
    of the morph cell."""

    def __init__(self, doc, group, sheet, thickness_expr, *, leaves_b, floor):
        super().__init__(doc, group, sheet, thickness_expr)
        self.leaves_b = leaves_b
        self.floor = floor
        self.m = f"{sheet.Name}.{MORPH_CELL}"
        self.floor_expr = f"{sheet.Name}.{MIN_SIZE_CELL}"

    def primitive(self, d, where):
        kind = d["type"]
        where = f"{where} ({kind})"
        makers = _MORPH_2D if self.t is not None else _MORPH_3D
        if kind not in makers and kind in _MAKERS_3D:
            raise BuildError(f"{where}: a morph does not interpolate {kind!r} leaves")
        if kind not in makers:
            raise BuildError(f"{where}: unknown primitive type {kind!r}")
        holder, obj = makers[kind](self, d, self.leaves_b[len(self.primitives)], where)
        self.primitives.append((d, holder, obj))
        return obj

    # ---- expressions --------------------------------------------------------------------

    def lerp(self, a, b, key, where, unit="mm", index=None, default=None):
        """value_A + (value_B - value_A) * morph of a number (or of element `index` of an
        array), with its unit; a plain value when A and B agree."""
        va, vb = (_element(d, key, index, w, default)
                  for d, w in ((a, where), (b, where + " of tree_b")))
        if va == vb:
            return _mm(va, unit)
        return f"({_mm(va, unit)} + {_mm(vb - va, unit)} * {self.m})"

    def size(self, a, b, key, where, index=None):
        """A size: lerp, floored at min_size (0 at one end for a one-shape primitive)."""
        for d, w in ((a, where), (b, where + " of tree_b")):
            if _element(d, key, index, w) < 0:
                raise BuildError(f"{w}: '{key}' must be >= 0")
        return f"max({self.lerp(a, b, key, where, index=index)}; {self.floor_expr})"

    def bind(self, obj, prop, expr):
        """The expression on obj.prop, when it depends on the morph (constants stay the
        maker's plain values, which equal them)."""
        if self.m in expr:
            obj.setExpression(prop, expr)

    def floored(self, d, *keys):
        """A copy of leaf d with its sizes at least the floor, for PartTree's makers (which
        refuse zero sizes); the expressions replace these values at recompute."""
        out = dict(d)
        for key in keys:
            v = out[key]
            out[key] = [max(x, self.floor) for x in v] if isinstance(v, list) \
                else max(v, self.floor)
        return out

    def place2d(self, obj, a, b, where, local=None, turn=None):
        """Base = centre + R(angle) * local, Rotation.Angle = angle (+ turn) about +z."""
        cx, cy = (self.lerp(a, b, k, where) for k in ("cx", "cy"))
        angle = self.lerp(a, b, "angle", where, "deg", default=0.0)
        if local is not None:
            lx, ly = local
            cx = f"{cx} + cos({angle}) * ({lx}) - sin({angle}) * ({ly})"
            cy = f"{cy} + sin({angle}) * ({lx}) + cos({angle}) * ({ly})"
        self.bind(obj, "Placement.Base.x", cx)
        self.bind(obj, "Placement.Base.y", cy)
        self.bind(obj, "Placement.Rotation.Angle", angle + (turn or ""))

    def rotation3d(self, a, b, where):
        """R(axis, morph * angle) * R_A, the solver's turn from R_A to R_B (interpolate.cpp)."""
        qa, qb = _quaternion(a, where), _quaternion(b, where + " of tree_b")
        r_a = "create(<<rotation>>; {1!r}; {2!r}; {3!r}; {0!r})".format(*qa)
        axis, degrees = relative_turn(qa, qb)
        if degrees == 0:
            return r_a
        return ("create(<<rotation>>; create(<<vector>>; {!r}; {!r}; {!r}); ".format(*axis)
                + f"{degrees!r} deg * {self.m}) * {r_a}")

    def place3d(self, obj, a, b, where, local=None):
        """Placement = (centre, R_t) * (local offset of the object's origin, identity)."""
        centre = "create(<<vector>>; {}; {}; {})".format(
            *(self.lerp(a, b, "center", where, index=i) for i in range(3)))
        expr = f"create(<<placement>>; {centre}; {self.rotation3d(a, b, where)})"
        if local is not None:
            expr += (" * create(<<placement>>; create(<<vector>>; {}; {}; {}); "
                     "create(<<rotation>>))".format(*local))
        self.bind(obj, "Placement", expr)

    # ---- 2D -------------------------------------------------------------------------------

    def _morph_rectangle(self, a, b, where):
        w, h = self.size(a, b, "w", where), self.size(a, b, "h", where)
        holder, obj = self._rectangle(self.floored(a, "w", "h"), where)
        self.bind(obj, "Length", w)
        self.bind(obj, "Width", h)
        self.place2d(obj, a, b, where, (f"-({w}) / 2", f"-({h}) / 2"))
        return holder, obj

    def _morph_circle(self, a, b, where):
        r = self.size(a, b, "r", where)
        holder, obj = self._circle(self.floored(a, "r"), where)
        self.bind(obj, "Radius", r)
        self.place2d(obj, dict(a, angle=0.0), dict(b, angle=0.0), where)
        return holder, obj

    def _morph_ellipse(self, a, b, where):
        rx, ry = self.size(a, b, "rx", where), self.size(a, b, "ry", where)
        curve, obj = self._ellipse(self.floored(a, "rx", "ry"), where)
        self.bind(curve, "MajorRadius", f"max({rx}; {ry})")
        self.bind(curve, "MinorRadius", f"min({rx}; {ry})")
        self.place2d(curve, a, b, where, turn=f" + ({rx} < {ry} ? 90 deg : 0 deg)")
        return curve, obj

    def _morph_triangle(self, a, b, where):
        w, h = self.size(a, b, "w", where), self.size(a, b, "h", where)
        apex = self.lerp(a, b, "apex", where, "", default=0.0)
        holder, obj = self._triangle(self.floored(a, "w", "h"), where)
        self.bind(obj, "Xmin", f"-({w}) / 2")
        self.bind(obj, "Xmax", f"({w}) / 2")
        self.bind(obj, "Ymin", f"-({h}) / 2")
        self.bind(obj, "Ymax", f"({h}) / 2")
        self.bind(obj, "X2min", f"{apex} * ({w}) / 2")
        self.place2d(obj, a, b, where)
        return holder, obj

    # ---- 3D -------------------------------------------------------------------------------

    def _morph_box(self, a, b, where):
        sizes = [self.size(a, b, "size", where, i) for i in range(3)]
        holder, obj = self._box(self.floored(a, "size"), where)
        for prop, s in zip(("Length", "Width", "Height"), sizes):
            self.bind(obj, prop, s)
        self.place3d(obj, a, b, where, [f"-({s}) / 2" for s in sizes])
        return holder, obj

    def _morph_sphere(self, a, b, where):
        r = self.size(a, b, "r", where)
        holder, obj = self._sphere(self.floored(a, "r"), where)
        self.bind(obj, "Radius", r)
        self.place3d(obj, a, b, where)
        return holder, obj

    def _morph_cylinder(self, a, b, where, radius="r"):
        r, h = self.size(a, b, radius, where), self.size(a, b, "h", where)
        holder, obj = self._cylinder(self.floored(a, radius, "h"), where, radius)
        self.bind(obj, "Radius", r)
        self.bind(obj, "Height", h)
        self.place3d(obj, a, b, where, ("0 mm", "0 mm", f"-({h}) / 2"))
        return holder, obj

    def _morph_cone(self, a, b, where):
        if a.get("r1") == a.get("r2") and b.get("r1") == b.get("r2"):
            return self._morph_cylinder(a, b, where, "r1")  # a cylinder all the way
        r1, r2 = self.size(a, b, "r1", where), self.size(a, b, "r2", where)
        h = self.size(a, b, "h", where)
        start = self.floored(a, "r1", "r2", "h")
        if start["r1"] == start["r2"]:  # equal at A only: the maker would make a cylinder
            start["r2"] += self.floor
        holder, obj = self._cone(start, where)
        self.bind(obj, "Radius1", r1)
        # Part::Cone refuses equal radii: where they meet, Radius2 keeps min_size away.
        self.bind(obj, "Radius2", f"(abs({r1} - {r2}) < {self.floor_expr} ? "
                                  f"{r1} + {self.floor_expr} : {r2})")
        self.bind(obj, "Height", h)
        self.place3d(obj, a, b, where, ("0 mm", "0 mm", f"-({h}) / 2"))
        return holder, obj

    def _morph_ellipsoid(self, a, b, where):
        rx, ry, rz = (self.size(a, b, "radii", where, i) for i in range(3))
        holder, obj = self._ellipsoid(self.floored(a, "radii"), where)
        # FreeCAD's Radius1 is along local z, Radius2 along x, Radius3 along y.
        for prop, r in (("Radius1", rz), ("Radius2", rx), ("Radius3", ry)):
            self.bind(obj, prop, r)
        self.place3d(obj, a, b, where)
        return holder, obj

    def _morph_torus(self, a, b, where):
        big, small = self.size(a, b, "R", where), self.size(a, b, "r", where)
        holder, obj = self._torus(self.floored(a, "R", "r"), where)
        self.bind(obj, "Radius1", big)
        self.bind(obj, "Radius2", small)
        self.place3d(obj, a, b, where)
        return holder, obj

    def _morph_prism(self, a, b, where):
        w, h = self.size(a, b, "w", where), self.size(a, b, "h", where)
        depth = self.size(a, b, "depth", where)
        apex = self.lerp(a, b, "apex", where, "", default=0.0)
        holder, obj = self._prism(self.floored(a, "w", "h", "depth"), where)
        for prop, expr in (("Xmin", f"-({w}) / 2"), ("Xmax", f"({w}) / 2"),
                           ("Ymin", f"-({h}) / 2"), ("Ymax", f"({h}) / 2"),
                           ("X2min", f"{apex} * ({w}) / 2"),
                           ("Zmin", f"-({depth}) / 2"), ("Zmax", f"({depth}) / 2")):
            self.bind(obj, prop, expr)
        self.place3d(obj, a, b, where)
        return holder, obj


def _element(d, key, index, where, default=None) -> float:
    """d[key] (a number) or d[key][index] (an array of 3), checked finite."""
    if index is None:
        return _number(d, key, where, default=default)
    return _vector(d, key, 3, where)[index]


def _quaternion(d, where) -> Tuple[float, float, float, float]:
    """The leaf's unit quaternion (w, x, y, z); identity when absent."""
    if "rotation" not in d:
        return (1.0, 0.0, 0.0, 0.0)
    w, x, y, z = _vector(d, "rotation", 4, where)
    n = math.sqrt(w * w + x * x + y * y + z * z)
    if n < 1e-12:
        raise BuildError(f"{where}: 'rotation' is a zero quaternion")
    return (w / n, x / n, y / n, z / n)


def relative_turn(qa, qb) -> Tuple[Tuple[float, float, float], float]:
    """(axis, degrees) of the short-arc turn from qa to qb (w, x, y, z): q_rel = qb * conj(qa)
    flipped to w >= 0, as the solver's relative_turn (degrees 0 and axis +z when none)."""
    aw, ax, ay, az = qa[0], -qa[1], -qa[2], -qa[3]
    bw, bx, by, bz = qb
    w = bw * aw - bx * ax - by * ay - bz * az
    x = bw * ax + bx * aw + by * az - bz * ay
    y = bw * ay - bx * az + by * aw + bz * ax
    z = bw * az + bx * ay - by * ax + bz * aw
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    s = math.sqrt(x * x + y * y + z * z)
    if s < 1e-12:
        return (0.0, 0.0, 1.0), 0.0
    return (x / s, y / s, z / s), math.degrees(2 * math.atan2(s, min(1.0, w)))


_MORPH_2D = {"rectangle": MorphTree._morph_rectangle, "rect": MorphTree._morph_rectangle,
             "circle": MorphTree._morph_circle, "ellipse": MorphTree._morph_ellipse,
             "triangle": MorphTree._morph_triangle}
_MORPH_3D = {"box": MorphTree._morph_box, "cube": MorphTree._morph_box,
             "sphere": MorphTree._morph_sphere, "cylinder": MorphTree._morph_cylinder,
             "cone": MorphTree._morph_cone, "frustum": MorphTree._morph_cone,
             "ellipsoid": MorphTree._morph_ellipsoid, "torus": MorphTree._morph_torus,
             "prism": MorphTree._morph_prism, "wedge": MorphTree._morph_prism,
             "triangular_prism": MorphTree._morph_prism}

"""CSG trees in model units: operator Nodes over 2D Primitive or 3D Primitive3D leaves.

Both dimensions answer the same questions the same way (to_dict, count, walk, str), so code
that walks a tree need not know which kind of fit made it.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, fields
from typing import Callable, Iterator, List, Optional, Tuple, Union


def _number(v) -> str:
    if isinstance(v, (tuple, list)):
        return "(" + ", ".join(f"{x:.4g}" for x in v) + ")"
    return f"{v:.4g}"


class _Leaf:
    """What every primitive answers, whatever its dimension."""

    type: str

    @property
    def op(self) -> str:
        """Always "primitive" (lets code walk a tree without isinstance checks)."""
        return "primitive"

    @property
    def children(self) -> List["Node"]:
        """Always empty."""
        return []

    def count(self) -> int:
        """Number of primitives in this subtree (1)."""
        return 1

    def walk(self) -> Iterator[Union["Node", "_Leaf"]]:
        """Yields this node (pre-order traversal of a leaf)."""
        yield self

    def _shown(self) -> List[tuple]:
        """(name, value) pairs that __str__ shows."""
        return [(k, v) for k, v in self.to_dict().items() if k != "type"]

    def __str__(self) -> str:
        return f"{self.type}({', '.join(f'{k}={_number(v)}' for k, v in self._shown())})"


@dataclass
class Primitive(_Leaf):
    """A 2D leaf, in model units (pixel units times pixel_size), y up.

    type: "rectangle", "circle", "ellipse" or "triangle".
    cx, cy: centre. angle: rotation in degrees counter-clockwise about the centre.
    w, h: extent in the primitive's own frame (rectangle sides, ellipse diameters,
        triangle base width and height).
    r: radius (circles; None otherwise). rx, ry: semi-axes (ellipses and circles).
    apex: triangles only: the apex sits at (apex * w/2, h/2) in the local frame, whose base
        runs from (-w/2, -h/2) to (w/2, -h/2); 0 = isosceles, +-1 = right-angled.
    """

    type: str
    cx: float
    cy: float
    w: float
    h: float
    angle: float = 0.0
    apex: float = 0.0

    @property
    def r(self) -> Optional[float]:
        """Radius of a circle, None for other types."""
        return self.w / 2 if self.type == "circle" else None

    @property
    def rx(self) -> Optional[float]:
        """Semi-axis along the local x axis (ellipses and circles)."""
        return self.w / 2 if self.type in ("circle", "ellipse") else None

    @property
    def ry(self) -> Optional[float]:
        """Semi-axis along the local y axis (ellipses and circles)."""
        return self.h / 2 if self.type in ("circle", "ellipse") else None

    def vertices(self) -> List[tuple]:
        """Triangle corners (counter-clockwise) in model coordinates; [] for other types."""
        if self.type != "triangle":
            return []
        a = math.radians(self.angle)
        c, s = math.cos(a), math.sin(a)
        local = [(-self.w / 2, -self.h / 2), (self.w / 2, -self.h / 2),
                 (self.apex * self.w / 2, self.h / 2)]
        return [(self.cx + c * x - s * y, self.cy + s * x + c * y) for x, y in local]

    def to_dict(self) -> dict:
        """Plain dict (the JSON form) with the type-specific fields."""
        d = {"type": self.type, "cx": self.cx, "cy": self.cy}
        if self.type == "circle":
            d["r"] = self.r
        elif self.type == "ellipse":
            d.update(rx=self.rx, ry=self.ry, angle=self.angle)
        elif self.type == "rectangle":
            d.update(w=self.w, h=self.h, angle=self.angle)
        else:
            d.update(w=self.w, h=self.h, angle=self.angle, apex=self.apex)
        return d


Vec3 = Tuple[float, float, float]

#: The size fields of each 3D type, as the JSON schema names and orders them.
SIZE_FIELDS_3D = {
    "box": ("size",),
    "sphere": ("r",),
    "cylinder": ("r", "h"),
    "cone": ("r1", "r2", "h"),
    "ellipsoid": ("radii",),
    "torus": ("R", "r"),
    "prism": ("w", "h", "depth", "apex"),
    "nurbs": ("size", "degree", "counts", "knots_u", "knots_v", "control_points"),
    "rounded_box": ("size", "corner"),
}


@dataclass
class Primitive3D(_Leaf):
    """A 3D leaf in the input's own units, centred on `center` and turned by `rotation`.

    type: one of SIZE_FIELDS_3D. rotation: unit quaternion (w, x, y, z), local -> model;
    euler_deg: the same rotation as OpenSCAD's rotate([a, b, c]) (about x, then y, then z).
    Sizes (None where the type has none, docs/JSON_SCHEMA.md "3D documents"): box `size`
    (x, y, z); sphere `r`; cylinder `r`, `h` (axis along local z); cone `r1` (bottom, local
    z = -h/2), `r2`, `h`; ellipsoid `radii` (x, y, z); torus `R` (major), `r` (minor); prism
    `w`, `h`, `apex` (its triangle, as in 2D) and `depth` along local z; nurbs (seed 004's
    NURBS terminal) `size` (sx, sy, top), `degree`, `counts`, `knots_u`, `knots_v` and
    `control_points` (local, u index fastest; the solid lies between local z = 0 and the patch);
    rounded_box `size` (x, y, z) and `corner`, the radius of its four edges along local z (half
    the smaller of x and y: a stadium).
    sides: a cylinder's or cone's regular polygon (OpenSCAD's `$fn`, its vertices on the
    circle of the radius, vertex 0 on local +x), None when it is round.
    """

    type: str
    center: Vec3
    rotation: Tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    euler_deg: Vec3 = (0.0, 0.0, 0.0)
    size: Optional[Vec3] = None
    r: Optional[float] = None
    h: Optional[float] = None
    r1: Optional[float] = None
    r2: Optional[float] = None
    radii: Optional[Vec3] = None
    R: Optional[float] = None
    w: Optional[float] = None
    depth: Optional[float] = None
    apex: Optional[float] = None
    degree: Optional[Tuple[int, int]] = None
    counts: Optional[Tuple[int, int]] = None
    knots_u: Optional[Tuple[float, ...]] = None
    knots_v: Optional[Tuple[float, ...]] = None
    control_points: Optional[Tuple[Vec3, ...]] = None
    corner: Optional[float] = None
    sides: Optional[int] = None

    @classmethod
    def from_dict(cls, d: dict) -> "Primitive3D":
        """A primitive from its JSON form (lists become tuples)."""
        names = {f.name for f in fields(cls)}
        return cls(**{k: tuple(v) if isinstance(v, list) else v
                      for k, v in d.items() if k in names})

    def to_dict(self) -> dict:
        """Plain dict, the JSON form: type, center, rotation, euler_deg, the sizes, then sides
        when the section is a polygon."""
        d = {"type": self.type, "center": list(self.center), "rotation": list(self.rotation),
             "euler_deg": list(self.euler_deg)}
        for name in SIZE_FIELDS_3D.get(self.type, ()):
            v = getattr(self, name)
            d[name] = list(v) if isinstance(v, tuple) else v
        if self.sides is not None:
            d["sides"] = self.sides
        return d

    def _shown(self) -> List[tuple]:
        # The quaternion says the same as euler_deg, less readably; no turn is not worth a word.
        shown = [(k, v) for k, v in self.to_dict().items()
                 if k not in ("type", "rotation", "euler_deg")]
        if any(abs(a) > 1e-9 for a in self.euler_deg):
            shown.append(("euler_deg", self.euler_deg))
        return shown


Leaf = Union[Primitive, Primitive3D]


@dataclass
class Node:
    """An operator node: op is "union", "difference" (first child minus all others) or
    "intersection"; children are Node, Primitive (2D) or Primitive3D (3D) objects."""

    op: str
    children: List[Union["Node", Leaf]] = field(default_factory=list)

    def to_dict(self) -> dict:
        """Plain nested dict: {"op": ..., "children": [...]}."""
        return {"op": self.op, "children": [c.to_dict() for c in self.children]}

    def count(self) -> int:
        """Number of primitives in this subtree."""
        return sum(c.count() for c in self.children)

    def walk(self) -> Iterator[Union["Node", Leaf]]:
        """Yields every node of the subtree in pre-order."""
        yield self
        for c in self.children:
            yield from c.walk()

    def __str__(self) -> str:
        return f"{self.op}({', '.join(str(c) for c in self.children)})"


def _tree(d: dict, leaf: Callable[[dict], Leaf]) -> Union[Node, Leaf]:
    if "op" in d:
        return Node(d["op"], [_tree(c, leaf) for c in d["children"]])
    return leaf(d)


def tree_from_pixels(d: dict, pixel_size: float) -> Union[Node, Primitive]:
    """A 2D tree from the native module's pixel-unit dicts, in model units."""
    def leaf(p: dict) -> Primitive:
        return Primitive(type=p["type"], cx=p["cx"] * pixel_size, cy=p["cy"] * pixel_size,
                         w=p["w"] * pixel_size, h=p["h"] * pixel_size, angle=p["angle"],
                         apex=p["apex"])

    return _tree(d, leaf)


def tree_from_json3d(d: dict) -> Union[Node, Primitive3D]:
    """A 3D tree from the "tree" of a 3D JSON document."""
    return _tree(d, Primitive3D.from_dict)


def find_sweeps(tree) -> List[dict]:
    """The subtrees of a 3D tree that are a 2D profile swept along an axis or about one: what
    the .scad writes as linear_extrude / rotate_extrude and the FreeCAD builder as
    Part::Extrusion / Part::Revolution. Returned as the "sweeps" block of a 3D document
    (docs/JSON_SCHEMA.md: each sweep's node, kind, frame, height and leaf sections); [] when
    there is none. tree: a Node or Primitive3D, or a 3D JSON tree (dict)."""
    from . import _csgfit  # the tree's value types above need no native module; this does

    d = tree.to_dict() if hasattr(tree, "to_dict") else tree
    document = {"schema": "csgfit/1", "dimension": 3, "units": "mm", "tree": d}
    return json.loads(_csgfit.sweeps_json(json.dumps(document)))

"""Builds a parametric FreeCAD Part tree from a csgfit result.

Works headless (freecadcmd or /usr/bin/python3 with FreeCAD's lib on sys.path) and does not need
the native csgfit module: the input is the result's JSON (schema csgfit/1, docs/JSON_SCHEMA.md),
as a dict, as text, as a path, or a csgfit.FitResult.

Mapping of a 2D result (model units, y up, angles in degrees counter-clockwise; extruded from
z = 0 to z = thickness):

  rectangle  Part::Box       Length = w, Width = h, Placement: centre at (cx, cy), rotated about z
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
  cylinder   Part::Cylinder   Radius, Height; offset (0, 0, -h/2)
  cone       Part::Cone       Radius1 (bottom) = r1, Radius2 = r2, Height; offset (0, 0, -h/2)
                              (a Part::Cylinder when r1 == r2: OCC refuses such a cone)
  ellipsoid  Part::Ellipsoid  Radius2 = rx, Radius3 = ry, Radius1 = rz (FreeCAD's Radius1 is z)
  torus      Part::Torus      Radius1 = R, Radius2 = r
  prism      Part::Wedge      the 2D triangle's wedge over z in [-depth/2, depth/2]; X2max and
                              Z2min/Z2max are expressions on X2min and Zmin/Zmax
"""

from __future__ import annotations

import json
import math
import os
import re
from typing import Any, Dict, List, Optional, Tuple

import FreeCAD as App

SCHEMA = "csgfit/1"
#: Thickness used when the result has none: this many pixels.
DEFAULT_THICKNESS_PIXELS = 10.0

PRIMITIVE_TYPES = ("Part::Box", "Part::Cylinder", "Part::Ellipse", "Part::Extrusion",
                   "Part::Wedge", "Part::Sphere", "Part::Cone", "Part::Ellipsoid", "Part::Torus")
BOOLEAN_TYPES = ("Part::MultiFuse", "Part::MultiCommon", "Part::Cut", "Part::Fuse",
                 "Part::Common")
#: Every object type the builder creates (besides the group and its spreadsheet).
PARAMETRIC_TYPES = PRIMITIVE_TYPES + BOOLEAN_TYPES


class BuildError(ValueError):
    """The result cannot be turned into a FreeCAD tree (malformed JSON, unknown node)."""


class BuildResult:
    """What build() made: the group, the root solid, the parameter sheet, and per-primitive
    objects in tree pre-order (each entry: (primitive dict, the object holding its dimensions,
    the object carrying the solid))."""

    def __init__(self, group, root, sheet, primitives, objects):
        self.group = group
        self.root = root
        self.sheet = sheet
        self.primitives = primitives
        #: Every object of the tree (not the group or the sheet), in creation order.
        self.objects = objects


def load_result(source: Any) -> Dict[str, Any]:
    """Normalises a result to the csgfit/1 JSON dict.

    source: a dict (the parsed JSON), JSON text, a path to a .json file, or an object with a
    to_json() method (csgfit.FitResult). A bare tree dict ({"op": ...} or {"type": ...}) is
    accepted too (pixel size 1, no canvas).
    """
    if hasattr(source, "to_json"):
        source = source.to_json()
    if isinstance(source, (bytes, os.PathLike)):
        source = os.fsdecode(source)
    if isinstance(source, str):
        text = source
        if not text.lstrip().startswith("{"):
            try:
                with open(text, encoding="utf-8") as f:
                    text = f.read()
            except OSError as e:
                raise BuildError(f"cannot read {source}: {e.strerror}") from None
        try:
            source = json.loads(text)
        except json.JSONDecodeError as e:
            raise BuildError(f"JSON: {e}") from None
    if not isinstance(source, dict):
        raise BuildError("expected a csgfit result (dict, JSON text or path)")
    if "schema" not in source and ("op" in source or "type" in source):
        dim = 3 if _is_3d_tree(source) else 2
        envelope = {"schema": SCHEMA, "dimension": dim, "units": "mm", "source": ""}
        if dim == 2:
            envelope["canvas"] = {"pixel_size": 1.0, "thickness": 0.0}
        source = dict(envelope, tree=source)
    if source.get("schema") != SCHEMA:
        raise BuildError(f"unsupported schema {source.get('schema')!r} (expected {SCHEMA!r})")
    if source.get("dimension", 2) not in (2, 3):
        raise BuildError(f"unsupported dimension {source.get('dimension')!r} (expected 2 or 3)")
    if "tree" not in source:
        raise BuildError("the result has no 'tree'")
    return source


def _is_3d_tree(node: Any) -> bool:
    """Whether a bare tree is 3D (its first leaf has a 3D "center")."""
    while isinstance(node, dict) and "op" in node and node.get("children"):
        node = node["children"][0]
    return isinstance(node, dict) and "center" in node


def dimension(result: Dict[str, Any]) -> int:
    """2 or 3."""
    return int(result.get("dimension", 2))


def default_thickness(result: Dict[str, Any]) -> float:
    """The result's own thickness if it has one, else DEFAULT_THICKNESS_PIXELS pixels."""
    canvas = result.get("canvas", {})
    t = float(canvas.get("thickness") or 0.0)
    if t > 0:
        return t
    return DEFAULT_THICKNESS_PIXELS * float(canvas.get("pixel_size") or 1.0)


def _object_name(text: str) -> str:
    """A FreeCAD object name (identifier) derived from free text."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", text).strip("_") or "result"
    return name


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


def _vector(d: Dict[str, Any], key: str, n: int, where: str) -> List[float]:
    v = d.get(key)
    if not isinstance(v, list) or len(v) != n:
        raise BuildError(f"{where}: '{key}' must be an array of {n} numbers")
    for x in v:
        if not isinstance(x, (int, float)) or isinstance(x, bool) or not math.isfinite(x):
            raise BuildError(f"{where}: '{key}' must hold finite numbers")
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


class _Builder:
    def __init__(self, doc, group, sheet, thickness_expr: str):
        self.doc = doc
        self.group = group
        self.sheet = sheet
        self.t = thickness_expr
        self.created: List[Any] = []
        self.primitives: List[Tuple[Dict[str, Any], Any, Any]] = []
        self.counts: Dict[str, int] = {}

    def _add(self, type_name: str, label: str):
        n = self.counts.get(label, 0) + 1
        self.counts[label] = n
        obj = self.doc.addObject(type_name, label)
        obj.Label = f"{label}{n:03d}"
        self.created.append(obj)
        return obj

    def node(self, d: Any, where: str):
        if not isinstance(d, dict):
            raise BuildError(f"{where}: a node must be an object")
        if "op" in d:
            return self.operator(d, where)
        if "type" in d:
            return self.primitive(d, where)
        raise BuildError(f"{where}: a node needs 'op' or 'type'")

    def operator(self, d: Dict[str, Any], where: str):
        op = d["op"]
        kids = d.get("children")
        if not isinstance(kids, list) or not kids:
            raise BuildError(f"{where}: '{op}' needs a non-empty 'children' array")
        if op not in ("union", "difference", "intersection"):
            raise BuildError(f"{where}: unknown op {op!r}")
        children = [self.node(c, f"{where}.children[{i}]") for i, c in enumerate(kids)]
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
        if self.t is None:
            return self.primitive3d(d, where)
        kind = d["type"]
        where = f"{where} ({kind})"
        cx = _number(d, "cx", where)
        cy = _number(d, "cy", where)
        if kind in ("rectangle", "rect"):
            w = _number(d, "w", where, True)
            h = _number(d, "h", where, True)
            angle = _number(d, "angle", where, default=0.0)
            obj = self._add("Part::Box", "Rectangle")
            obj.Length = w
            obj.Width = h
            obj.setExpression("Height", self.t)
            obj.Placement = _placement(cx, cy, angle, (-w / 2, -h / 2))
            self.primitives.append((d, obj, obj))
            return obj
        if kind == "circle":
            r = _number(d, "r", where, True)
            obj = self._add("Part::Cylinder", "Circle")
            obj.Radius = r
            obj.setExpression("Height", self.t)
            obj.Placement = _placement(cx, cy, 0.0)
            self.primitives.append((d, obj, obj))
            return obj
        if kind == "ellipse":
            rx = _number(d, "rx", where, True)
            ry = _number(d, "ry", where, True)
            angle = _number(d, "angle", where, default=0.0)
            # Part::Ellipse wants MajorRadius >= MinorRadius along its local x axis.
            if rx < ry:
                rx, ry, angle = ry, rx, angle + 90.0
            curve = self._add("Part::Ellipse", "EllipseCurve")
            curve.MajorRadius = rx
            curve.MinorRadius = ry
            curve.Placement = _placement(cx, cy, angle)
            obj = self._add("Part::Extrusion", "Ellipse")
            obj.Base = curve
            obj.DirMode = "Custom"
            obj.Dir = App.Vector(0, 0, 1)
            obj.Solid = True
            obj.setExpression("LengthFwd", self.t)
            self.primitives.append((d, curve, obj))
            return obj
        if kind == "triangle":
            w = _number(d, "w", where, True)
            h = _number(d, "h", where, True)
            angle = _number(d, "angle", where, default=0.0)
            apex = _number(d, "apex", where, default=0.0)
            obj = self._add("Part::Wedge", "Triangle")
            obj.Xmin, obj.Xmax = -w / 2, w / 2
            obj.Ymin, obj.Ymax = -h / 2, h / 2
            obj.Zmin = 0.0
            obj.Z2min = 0.0
            obj.setExpression("Zmax", self.t)
            obj.setExpression("Z2max", self.t)
            obj.X2min = apex * w / 2
            # The top edge of the wedge degenerates to the apex; tying X2max to X2min keeps
            # it a triangle when the user moves the apex.
            obj.setExpression("X2max", "X2min")
            obj.Placement = _placement(cx, cy, angle)
            self.primitives.append((d, obj, obj))
            return obj
        raise BuildError(f"{where}: unknown primitive type {kind!r}")

    def primitive3d(self, d: Dict[str, Any], where: str):
        kind = d["type"]
        where = f"{where} ({kind})"
        c = _vector(d, "center", 3, where)
        rot = rotation3d(d, where)
        if kind in ("box", "cube"):
            sx, sy, sz = _vector(d, "size", 3, where)
            if min(sx, sy, sz) <= 0:
                raise BuildError(f"{where}: 'size' must be > 0")
            obj = self._add("Part::Box", "Box")
            obj.Length, obj.Width, obj.Height = sx, sy, sz
            obj.Placement = placement3d(c, rot, (-sx / 2, -sy / 2, -sz / 2))
        elif kind == "sphere":
            obj = self._add("Part::Sphere", "Sphere")
            obj.Radius = _number(d, "r", where, True)
            obj.Placement = placement3d(c, rot)
        elif kind == "cylinder" or (kind == "cone" and d.get("r1") == d.get("r2")):
            r = _number(d, "r" if kind == "cylinder" else "r1", where, True)
            h = _number(d, "h", where, True)
            obj = self._add("Part::Cylinder", "Cylinder")
            obj.Radius, obj.Height = r, h
            obj.Placement = placement3d(c, rot, (0.0, 0.0, -h / 2))
        elif kind in ("cone", "frustum"):
            r1 = _number(d, "r1", where)
            r2 = _number(d, "r2", where)
            h = _number(d, "h", where, True)
            if r1 < 0 or r2 < 0 or max(r1, r2) <= 0:
                raise BuildError(f"{where}: 'r1' and 'r2' must be >= 0, one of them > 0")
            obj = self._add("Part::Cone", "Cone")
            obj.Radius1, obj.Radius2, obj.Height = r1, r2, h
            obj.Placement = placement3d(c, rot, (0.0, 0.0, -h / 2))
        elif kind == "ellipsoid":
            rx, ry, rz = _vector(d, "radii", 3, where)
            if min(rx, ry, rz) <= 0:
                raise BuildError(f"{where}: 'radii' must be > 0")
            obj = self._add("Part::Ellipsoid", "Ellipsoid")
            # FreeCAD's Radius1 is along local z, Radius2 along x, Radius3 along y.
            obj.Radius1, obj.Radius2, obj.Radius3 = rz, rx, ry
            obj.Placement = placement3d(c, rot)
        elif kind == "torus":
            major = _number(d, "R", where, True)
            minor = _number(d, "r", where, True)
            obj = self._add("Part::Torus", "Torus")
            obj.Radius1, obj.Radius2 = major, minor
            obj.Placement = placement3d(c, rot)
        elif kind in ("prism", "wedge", "triangular_prism"):
            w = _number(d, "w", where, True)
            h = _number(d, "h", where, True)
            depth = _number(d, "depth", where, True)
            apex = _number(d, "apex", where, default=0.0)
            obj = self._add("Part::Wedge", "Prism")
            obj.Xmin, obj.Xmax = -w / 2, w / 2
            obj.Ymin, obj.Ymax = -h / 2, h / 2
            obj.Zmin, obj.Zmax = -depth / 2, depth / 2
            obj.Z2min, obj.Z2max = -depth / 2, depth / 2
            obj.X2min = obj.X2max = apex * w / 2
            # The wedge's far face degenerates to the apex edge; the expressions keep it a
            # triangular prism when the user edits X2min, Zmin or Zmax.
            obj.setExpression("X2max", "X2min")
            obj.setExpression("Z2min", "Zmin")
            obj.setExpression("Z2max", "Zmax")
            obj.Placement = placement3d(c, rot)
        else:
            raise BuildError(f"{where}: unknown primitive type {kind!r}")
        self.primitives.append((d, obj, obj))
        return obj


def build(doc, source: Any, *, thickness: Optional[float] = None, label: Optional[str] = None,
          alternative: int = -1, recompute: bool = True) -> BuildResult:
    """Adds the result's tree to `doc` as parametric Part objects inside a new group.

    source: see load_result (2D or 3D). thickness: extrusion height in mm of a 2D result
    (default: the result's thickness, else 10 pixels; ignored in 3D). label: the group's label
    (default: the input file's stem).
    alternative: -1 for the best tree, 0.. for one of the result's alternatives.
    The group gets a spreadsheet "<label> parameters" (2D: its 'thickness' cell drives every
    height; 3D: a record of the voxel grid), and read-only properties with the result's JSON
    (CsgFitJson), source, dimension and stats.
    Raises BuildError on malformed input (nothing is left in the document then).
    """
    result = load_result(source)
    tree = result["tree"]
    if alternative != -1:
        alts = result.get("alternatives") or []
        if not 0 <= alternative < len(alts):
            raise BuildError(f"no alternative {alternative} (the result has {len(alts)})")
        tree = alts[alternative]["tree"]
        stats = alts[alternative].get("stats") or {}
    else:
        stats = result.get("stats") or {}
    dim = dimension(result)
    t = None
    if dim == 2:
        t = default_thickness(result) if thickness is None else float(thickness)
        if not (math.isfinite(t) and t > 0):
            raise BuildError("thickness must be > 0")
    if label is None:
        src = result.get("source") or ""
        label = os.path.splitext(os.path.basename(src))[0] or "csgfit"

    name = "CSGFit_" + _object_name(label)
    group = doc.addObject("App::DocumentObjectGroup", name)
    group.Label = label
    sheet = doc.addObject("Spreadsheet::Sheet", name + "_parameters")
    sheet.Label = f"{label} parameters"
    if dim == 2:
        sheet.set("A1", "Thickness (mm)")
        sheet.set("B1", f"={t!r}mm")
        sheet.setAlias("B1", "thickness")
        sheet.set("A2", "Pixel size (mm)")
        pixel_size = float(result.get("canvas", {}).get("pixel_size") or 1.0)
        sheet.set("B2", f"={pixel_size!r}mm")
        sheet.setAlias("B2", "pixel_size")
    else:
        # A record of the grid the fit was scored on (3D primitives carry their own sizes).
        grid = result.get("grid") or {}
        sheet.set("A1", "Voxel size (mm)")
        sheet.set("B1", f"={float(grid.get('voxel_size') or 0.0)!r}mm")
        sheet.setAlias("B1", "voxel_size")
        sheet.set("A2", "Grid (voxels)")
        sheet.set("B2", "'{} x {} x {}".format(grid.get("nx", 0), grid.get("ny", 0),
                                             grid.get("nz", 0)))

    builder = _Builder(doc, group, sheet, f"{sheet.Name}.thickness" if dim == 2 else None)
    try:
        root = builder.node(tree, "tree")
    except Exception:
        for obj in reversed(builder.created):
            doc.removeObject(obj.Name)
        doc.removeObject(sheet.Name)
        doc.removeObject(group.Name)
        raise
    # The group holds the sheet and the root; the root's boolean claims its inputs, so the tree
    # view nests the whole CSG tree under it (listing every object in the group as well would
    # show each one twice).
    group.addObjects([sheet, root])

    def prop(kind, pname, doc_text, value):
        group.addProperty(kind, pname, "CSG Fit", doc_text)
        setattr(group, pname, value)
        group.setEditorMode(pname, 1)  # read-only in the property editor

    prop("App::PropertyString", "CsgFitJson", "The fitted result (csgfit/1 JSON)",
         json.dumps(result))
    prop("App::PropertyString", "CsgFitSource", "Input image or mesh", result.get("source") or "")
    prop("App::PropertyInteger", "CsgFitDimension", "2 (bitmap) or 3 (mesh, voxels)", dim)
    prop("App::PropertyInteger", "CsgFitAlternative", "Tree shown (-1 = best)", alternative)
    prop("App::PropertyFloat", "CsgFitIoU", "IoU of the fit on the pixel or voxel grid",
         float(stats.get("iou") or 0.0))
    prop("App::PropertyInteger", "CsgFitPrimitives", "Primitives in the tree",
         len(builder.primitives))
    prop("App::PropertyLink", "CsgFitRoot", "The root solid of the tree", root)
    if dim == 3 and hasattr(source, "to_scad"):
        # 3D JSON cannot be read back natively yet; Export OpenSCAD writes this text.
        prop("App::PropertyString", "CsgFitScad", "The fitted tree as OpenSCAD source",
             source.to_scad())

    # Only the root is shown; the inputs of booleans stay hidden as the Part commands do.
    for obj in builder.created:
        if obj is not root:
            _hide(obj)
    if recompute:
        doc.recompute()
    return BuildResult(group, root, sheet, builder.primitives, builder.created)


def preview_shape(source: Any):
    """The solid the builder would make for `source` (see load_result), without touching any
    open document: the tree is built in a hidden temporary document and its root's shape
    copied out. For previews (the Mesh to CSG panel shows it in the 3D view)."""
    previous = App.ActiveDocument
    doc = App.newDocument("CSGFitPreview", hidden=True, temp=True)
    try:
        built = build(doc, source, label="preview")
        return built.root.Shape.copy()
    finally:
        App.closeDocument(doc.Name)
        if previous is not None:  # the new document became the active one
            App.setActiveDocument(previous.Name)
            if App.GuiUp:
                import FreeCADGui

                FreeCADGui.ActiveDocument = FreeCADGui.getDocument(previous.Name)


def _hide(obj) -> None:
    if App.GuiUp and getattr(obj, "ViewObject", None) is not None:
        obj.ViewObject.Visibility = False
    else:
        obj.Visibility = False


def find_groups(doc) -> List[Any]:
    """The csgfit groups of a document (those carrying a CsgFitJson property)."""
    return [o for o in doc.Objects if hasattr(o, "CsgFitJson")]


def tree_objects(group) -> List[Any]:
    """The objects of a group's CSG tree: the root and everything it depends on, except the
    parameter sheet."""
    root = group.CsgFitRoot
    if root is None:
        return []
    return [root] + [o for o in root.OutListRecursive if o.TypeId != "Spreadsheet::Sheet"]


def check_tree(doc, group) -> List[str]:
    """Problems with a built tree, [] when it is sound: every object recomputed, only
    parametric types, a valid non-empty solid at the root."""
    problems = []
    for obj in list(group.Group) + tree_objects(group):
        if "Invalid" in obj.State or "Error" in obj.State:
            problems.append(f"{obj.Label}: {', '.join(obj.State)}")
        if obj.TypeId not in PARAMETRIC_TYPES + ("Spreadsheet::Sheet",):
            problems.append(f"{obj.Label}: unexpected type {obj.TypeId}")
    root = group.CsgFitRoot
    if root is None:
        problems.append("no root")
    else:
        shape = root.Shape
        if shape.isNull() or not shape.isValid():
            problems.append("root shape is not valid")
        elif not shape.Solids:
            problems.append("root shape has no solid")
    return problems

"""Builds a parametric FreeCAD Part tree from a csgfit result.

Works headless (freecadcmd or /usr/bin/python3 with FreeCAD's lib on sys.path) and does not need
the native csgfit module: the input is the result's JSON (schema csgfit/1, docs/JSON_SCHEMA.md),
as a dict, as text, as a path, or a csgfit.FitResult / FitResult3D.

The Part objects of each primitive and operator are made by part_objects.py (its docstring
has the mapping); this module reads results, groups the objects with their parameter sheet and
records the result on the group.
"""

from __future__ import annotations

import json
import math
import os
import re
from typing import Any, Dict, List, Optional

import FreeCAD as App

from . import shared_dimensions, sweep_objects
from .part_objects import PARAMETRIC_TYPES, BuildError, PartTree

SCHEMA = "csgfit/1"
#: Thickness used when the result has none: this many pixels.
DEFAULT_THICKNESS_PIXELS = 10.0


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


def object_name(text: str) -> str:
    """A FreeCAD object name (identifier) derived from free text."""
    name = re.sub(r"[^A-Za-z0-9_]", "_", text).strip("_") or "result"
    return name


def _chosen_tree(result: Dict[str, Any], alternative: int):
    """(tree, stats, shared dimensions, sweeps) of the best tree (-1) or of an alternative."""
    chosen = result
    if alternative != -1:
        alts = result.get("alternatives") or []
        if not 0 <= alternative < len(alts):
            raise BuildError(f"no alternative {alternative} (the result has {len(alts)})")
        chosen = alts[alternative]
    shared = chosen.get("shared_dimensions")
    return (chosen["tree"], chosen.get("stats") or {}, shared if isinstance(shared, list) else [],
            chosen.get("sweeps"))


def _parameter_sheet(doc, name: str, label: str, result: Dict[str, Any],
                     thickness: Optional[float], extra_rows=()):
    """The group's spreadsheet: 2D, the thickness cell every height refers to and the pixel
    size; 3D (thickness None), a record of the grid the fit was scored on (3D primitives carry
    their own sizes). extra_rows: more (title, value, alias or None) rows after those."""
    sheet = doc.addObject("Spreadsheet::Sheet", name + "_parameters")
    sheet.Label = f"{label} parameters"
    if thickness is not None:
        rows = [("Thickness (mm)", f"={thickness!r}mm", "thickness"),
                ("Pixel size (mm)",
                 f"={float(result.get('canvas', {}).get('pixel_size') or 1.0)!r}mm",
                 "pixel_size")]
    elif "precedence_graph" in result:
        rows = _range_rows(result)
    else:
        grid = result.get("grid") or {}
        rows = [("Voxel size (mm)", f"={float(grid.get('voxel_size') or 0.0)!r}mm",
                 "voxel_size"),
                ("Grid (voxels)", "'{} x {} x {}".format(grid.get("nx", 0), grid.get("ny", 0),
                                                        grid.get("nz", 0)), None)]
    for row, (title, value, alias) in enumerate(rows + list(extra_rows), start=1):
        sheet.set(f"A{row}", title)
        sheet.set(f"B{row}", value)
        if alias:
            sheet.setAlias(f"B{row}", alias)
    return sheet


def _range_rows(result: Dict[str, Any]):
    """A range fit (seed 002) was scored against its views, not on a grid: the sheet records
    the segmentation, the precedence graph and how each view agrees with the tree."""
    graph = result.get("precedence_graph") or {}
    rows = [("Surface patches", str(len(result.get("patches") or [])), None),
            ("Subobjects", str(int(graph.get("subobjects") or 0)), None)]
    for view in result.get("views") or []:
        name = os.path.basename(view.get("source") or "view")
        rows.append((f"{name}: silhouette IoU", repr(float(view.get("silhouette_iou") or 0.0)),
                     None))
        rows.append((f"{name}: depth error (mm)", f"={float(view.get('depth_error') or 0.0)!r}mm",
                     None))
    return rows


def _record(group, result: Dict[str, Any], stats: Dict[str, Any], alternative: int,
            built: PartTree, root, scad: Optional[str]) -> None:
    """The result on the group as read-only properties (Export OpenSCAD reads them back)."""
    def prop(kind, pname, doc_text, value):
        group.addProperty(kind, pname, "CSG Fit", doc_text)
        setattr(group, pname, value)
        group.setEditorMode(pname, 1)  # read-only in the property editor

    prop("App::PropertyString", "CsgFitJson", "The fitted result (csgfit/1 JSON)",
         json.dumps(result))
    prop("App::PropertyString", "CsgFitSource", "Input image or mesh", result.get("source") or "")
    prop("App::PropertyInteger", "CsgFitDimension", "2 (bitmap) or 3 (mesh, voxels, range)",
         dimension(result))
    prop("App::PropertyInteger", "CsgFitAlternative", "Tree shown (-1 = best)", alternative)
    prop("App::PropertyFloat", "CsgFitIoU",
         "IoU of the fit on the pixel or voxel grid (range: the views' silhouette IoU)",
         float(stats.get("iou") or 0.0))
    prop("App::PropertyInteger", "CsgFitPrimitives", "Primitives in the tree",
         len(built.primitives))
    prop("App::PropertyLink", "CsgFitRoot", "The root solid of the tree", root)
    if scad is not None:
        # 3D JSON cannot be read back natively yet; Export OpenSCAD writes this text.
        prop("App::PropertyString", "CsgFitScad", "The fitted tree as OpenSCAD source", scad)


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
    tree, stats, shared, sweeps = _chosen_tree(result, alternative)
    scad = source.to_scad() if dimension(result) == 3 and hasattr(source, "to_scad") else None
    return assemble(doc, result, tree, stats, thickness=thickness, label=label,
                    alternative=alternative, scad=scad, recompute=recompute, shared=shared,
                    sweeps=sweeps)


def extrusion_thickness(result: Dict[str, Any], thickness: Optional[float]) -> Optional[float]:
    """The 2D extrusion height (the argument, else the result's default); None in 3D."""
    if dimension(result) != 2:
        return None
    t = default_thickness(result) if thickness is None else float(thickness)
    if not (math.isfinite(t) and t > 0):
        raise BuildError("thickness must be > 0")
    return t


def assemble(doc, result: Dict[str, Any], tree: Dict[str, Any], stats: Dict[str, Any], *,
             thickness: Optional[float] = None, label: Optional[str] = None,
             alternative: int = -1, scad: Optional[str] = None, recompute: bool = True,
             make_tree=PartTree, extra_rows=(), shared=(), sweeps=None) -> BuildResult:
    """build() once the tree is chosen: the group, its parameter sheet (plus extra_rows and a
    cell per shared dimension), the Part objects of `tree` made by make_tree(doc, group, sheet,
    thickness expression or None) (a PartTree; morph_builder passes its own) with the shared
    dimensions tied to their cells and a 3D tree's sweeps (the JSON's "sweeps") built as
    extrusions and revolutions of their profile, the record on the group.
    Raises BuildError on malformed input (nothing is left in the document then)."""
    dim = dimension(result)
    t = extrusion_thickness(result, thickness)
    by_node = sweep_objects.sweeps_by_node(sweeps, tree) if dim == 3 else {}
    if label is None:
        src = result.get("source") or ""
        label = os.path.splitext(os.path.basename(src))[0] or "csgfit"

    name = "CSGFit_" + object_name(label)
    group = doc.addObject("App::DocumentObjectGroup", name)
    group.Label = label
    sheet = _parameter_sheet(doc, name, label, result, t,
                             list(extra_rows) + shared_dimensions.sheet_rows(shared))
    builder = make_tree(doc, group, sheet, f"{sheet.Name}.thickness" if dim == 2 else None)
    builder.sweeps = by_node
    try:
        root = builder.node(tree, "tree")
        shared_dimensions.bind(sheet, shared, builder.primitives)
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
    _record(group, result, stats, alternative, builder, root, scad)
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

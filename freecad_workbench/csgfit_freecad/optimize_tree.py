"""'Optimize CSG tree': a selected Part boolean tree through seed 001's optimiser (csgfit.optimize),
built beside it as a new parametric tree; the original is hidden, not deleted, and the whole
change is one undo step.

The tree goes out as OpenSCAD CSG written here (FreeCAD 0.20's exportCSG writes a sphere's radius
with its unit, "r = 2.0 mm", and leaves a sphere's multmatrix open over its next sibling, so it
cannot be trusted with a tree) and comes back through FreeCAD's own CSG importer (the OpenSCAD
workbench's importCSG), which builds Part primitives with placements under Part booleans."""

import os
import sys
import tempfile

import FreeCAD as App

from . import import_csgfit

OPENSCAD_MOD = os.path.join(App.getResourceDir(), "Mod", "OpenSCAD")
BOOLEAN_TYPES = ("Part::Cut", "Part::Fuse", "Part::MultiFuse", "Part::Common", "Part::MultiCommon")


def _openscad_importer():
    if OPENSCAD_MOD not in sys.path:
        sys.path.append(OPENSCAD_MOD)
    import importCSG
    return importCSG


def _mm(quantity):
    return "%.12g" % float(getattr(quantity, "Value", quantity))


def _placed(obj, call):
    """The call under the object's placement, as OpenSCAD's multmatrix."""
    m = obj.Placement.toMatrix()
    rows = [[m.A11, m.A12, m.A13, m.A14], [m.A21, m.A22, m.A23, m.A24], [m.A31, m.A32, m.A33, m.A34]]
    text = ", ".join("[%s]" % ", ".join("%.12g" % v for v in row) for row in rows)
    return "multmatrix([%s, [0, 0, 0, 1]]) {\n%s\n}" % (text, call)


def _primitive_csg(obj):
    t = obj.TypeId
    if t == "Part::Box":
        return "cube(size = [%s, %s, %s], center = false);" % (_mm(obj.Length), _mm(obj.Width), _mm(obj.Height))
    if t == "Part::Sphere":
        return "sphere($fn = 0, $fa = 12, $fs = 2, r = %s);" % _mm(obj.Radius)
    if t == "Part::Cylinder":
        return "cylinder($fn = 0, $fa = 12, $fs = 2, h = %s, r1 = %s, r2 = %s, center = false);" % (
            _mm(obj.Height), _mm(obj.Radius), _mm(obj.Radius))
    if t == "Part::Cone":
        return "cylinder($fn = 0, $fa = 12, $fs = 2, h = %s, r1 = %s, r2 = %s, center = false);" % (
            _mm(obj.Height), _mm(obj.Radius1), _mm(obj.Radius2))
    if t == "Part::Ellipsoid":  # FreeCAD's Radius1 is along z
        return ("multmatrix([[%s, 0, 0, 0], [0, %s, 0, 0], [0, 0, %s, 0], [0, 0, 0, 1]]) {\n"
                "sphere($fn = 0, $fa = 12, $fs = 2, r = 1);\n}" % (_mm(obj.Radius2), _mm(obj.Radius3), _mm(obj.Radius1)))
    return None


def tree_csg(obj):
    """The Part tree under obj as OpenSCAD CSG text; ValueError naming the first object that is
    neither a Part boolean nor a box, sphere, cylinder, cone or ellipsoid."""
    t = obj.TypeId
    if t in ("Part::Cut", "Part::Fuse", "Part::Common"):
        kids = [obj.Base, obj.Tool]
    elif t in ("Part::MultiFuse", "Part::MultiCommon"):
        kids = list(obj.Shapes)
    else:
        call = _primitive_csg(obj)
        if call is None:
            raise ValueError(f"{obj.Label} ({t}) is not a Part primitive the optimiser knows "
                             "(box, sphere, cylinder, cone, ellipsoid) nor a Part boolean")
        return _placed(obj, call)
    op = {"Part::Cut": "difference", "Part::Common": "intersection", "Part::MultiCommon": "intersection"}.get(t, "union")
    return "%s() {\n%s\n}" % (op, "\n".join(tree_csg(k) for k in kids))


def is_boolean_tree(obj):
    """Whether obj is a Part boolean or primitive that tree_csg writes."""
    return obj.TypeId in BOOLEAN_TYPES or _primitive_csg(obj) is not None


def _top_level(new_objects):
    """The new objects that no other new object uses: the roots of the imported tree."""
    names = {o.Name for o in new_objects}
    return [o for o in new_objects if not any(p.Name in names for p in o.InList)]


def optimize_object(obj, method="auto", proximity_weight=2.0, seed=1):
    """Optimises the tree under `obj`; returns (root of the new tree, csgfit.OptimizeResult).
    Raises csgfit.InputError when the tree is not CSG the optimiser can read."""
    csgfit = import_csgfit()
    import_csg = _openscad_importer()
    doc = obj.Document
    with tempfile.TemporaryDirectory(prefix="csgfit_optimize_") as tmp:
        result = csgfit.optimize(tree_csg(obj) + "\n", method=method, proximity_weight=proximity_weight,
                                 seed=seed)
        target = os.path.join(tmp, "optimized.csg")
        result.save(target)
        before = {o.Name for o in doc.Objects}
        doc.openTransaction("Optimize CSG tree")
        try:
            import_csg.insert(target, doc.Name)
            new = [o for o in doc.Objects if o.Name not in before]
            roots = _top_level(new)
            if len(roots) == 1:
                root = roots[0]
            else:
                root = doc.addObject("Part::MultiFuse", "Optimized")
                root.Shapes = roots
            root.Label = obj.Label + " (optimized)"
            if App.GuiUp:
                obj.ViewObject.Visibility = False
            doc.recompute()
        except Exception:
            doc.abortTransaction()
            raise
        doc.commitTransaction()
    return root, result

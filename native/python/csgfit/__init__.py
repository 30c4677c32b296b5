"""csgfit: turn bitmaps, meshes and voxel grids into compact, editable CSG trees.

    >>> import csgfit
    >>> result = csgfit.fit_image("part.png", pixel_size=0.5, time=2)
    >>> result.stats.iou, result.stats.primitives
    >>> print(result.tree)            # Node / Primitive objects in model units (mm)
    >>> open("part.scad", "w").write(result.to_scad())

3D: ``csgfit.fit_mesh("part.stl", time=20)`` or ``csgfit.fit_voxels(bool_array, ...)`` return a
FitResult3D, the same kind of object: its ``tree`` is Node / Primitive3D objects in the mesh's
units, and its ``document`` is the dimension-3 JSON document of ``csgfit mesh -o x.json``.

Two shapes (seed 000's morphing): ``csgfit.morph("b.png", "i.png", time=20)`` returns a
MorphResult: two trees of one structure (``tree_a``, ``tree_b``), ``frame(t)``, and ``to_scad()``
with a ``morph`` parameter that OpenSCAD animates.

An OpenSCAD program (seed 001): ``csgfit.optimize("part.scad")`` returns an OptimizeResult, the
same solid from a smaller tree, as ``scad`` and ``csg`` text with its sizes and proximity.

Range images (seed 002): ``csgfit.fit_range("part.png")`` (a path or a list of views of one
part; point files too) or ``csgfit.fit_range_points(xyz_array)`` return a RangeFitResult: the
tree, its ``precedence_graph`` (subobjects, orders, signs), ``report()``, ``views``,
``patches``, ``save_preview(png)`` and ``save(path)`` (.scad, .json, .step, .FCStd).

Scanned point clouds (seed 004): ``csgfit.fit_points("scan.xyz", time=30)`` or
``csgfit.fit_points(xyz_array)`` run ``csgfit points``' GP/ES with NURBS terminals and return a
PointsFitResult: the tree, ``fitness`` (seed 004's terms), ``report()`` and ``save(path)``.

Coordinates follow the project's contract: an image of W x H pixels with pixel size s covers
[0, W*s] x [0, H*s] with y pointing up; angles are degrees counter-clockwise.

Image convention: for files and uint8 grey arrays, dark pixels are the shape (Otsu threshold
unless ``threshold`` is given; ``invert=True`` makes light pixels the shape). For bool arrays,
True is the shape (``invert=True`` flips it). Row 0 of an array is the top row of the image.
"""

from __future__ import annotations

from . import _csgfit
from .bitmaps import fit_image, load_bitmap, load_json
from .meshes import fit_mesh, fit_voxels, load_mesh, load_voxels, voxelize
from .morphs import MorphResult, morph
from .optimize import OptimizeResult, optimize
from .options import (DEFAULT_PRIMITIVES_3D, PRIMITIVE_TYPES, PRIMITIVE_TYPES_3D, QUALITIES,
                      CancelToken, FitProgress, InputError, set_max_memory)
from .points import DEFAULT_PRIMITIVES_POINTS, PointFitness, PointsFitResult, fit_points
from .ranges import (DEFAULT_PRIMITIVES_RANGE, CloudResult, GraphArc, GraphNode,
                     PrecedenceGraph, RangeFitResult, SurfacePatch, ViewAgreement,
                     fit_range, fit_range_points)
from .results import Alternative, FitResult, FitResult3D, FitStats, GridResult, Result
from .tree import SIZE_FIELDS_3D, Node, Primitive, Primitive3D, find_sweeps

__all__ = [
    "DEFAULT_PRIMITIVES_3D",
    "DEFAULT_PRIMITIVES_POINTS",
    "DEFAULT_PRIMITIVES_RANGE",
    "PRIMITIVE_TYPES",
    "PRIMITIVE_TYPES_3D",
    "QUALITIES",
    "SIZE_FIELDS_3D",
    "Alternative",
    "CancelToken",
    "CloudResult",
    "FitProgress",
    "FitResult",
    "FitResult3D",
    "FitStats",
    "GraphArc",
    "GraphNode",
    "GridResult",
    "InputError",
    "MorphResult",
    "Node",
    "OptimizeResult",
    "PointFitness",
    "PointsFitResult",
    "Primitive",
    "PrecedenceGraph",
    "Primitive3D",
    "RangeFitResult",
    "Result",
    "SurfacePatch",
    "ViewAgreement",
    "default_k",
    "find_sweeps",
    "fit_image",
    "fit_mesh",
    "fit_points",
    "fit_range",
    "fit_range_points",
    "fit_voxels",
    "load_bitmap",
    "load_json",
    "load_mesh",
    "morph",
    "load_voxels",
    "optimize",
    "set_max_memory",
    "voxelize",
]

default_k = _csgfit.default_k

"""What the fits return: FitResult (2D) and FitResult3D (3D), the same kind of object over a
shared base, with the tree in model units and the solver's stats."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Optional

from .options import integer, number
from .tree import tree_from_json3d, tree_from_pixels


@dataclass
class FitStats:
    """How good a tree is and what the search did.

    iou: intersection over union of the tree's raster and the target.
    primitives: leaves in the tree. excess / uncovered: pixels (3D: voxels) wrongly inside /
        outside. score: excess + uncovered + k * primitives (lower is better). k: the size
        weight used. evaluations: tree evaluations; trees: trees searched; seconds: wall time.
    stop_reason: "converged", "time", "max-trees" or "cancelled".
    """

    iou: float = 0.0
    primitives: int = 0
    evaluations: int = 0
    trees: int = 0
    seconds: float = 0.0
    score: float = 0.0
    excess: int = 0
    uncovered: int = 0
    k: float = 0.0
    stop_reason: str = ""

    @classmethod
    def _from_dict(cls, d: dict) -> "FitStats":
        names = cls.__dataclass_fields__.keys()
        # JSON writes a non-finite statistic as null; read it back as 0 (the schema says so).
        return cls(**{k: (v if v is not None else cls.__dataclass_fields__[k].default)
                      for k, v in d.items() if k in names})


class Result:
    """What FitResult, FitResult3D and RangeFitResult share.

    tree: the best tree (Node over Primitive or Primitive3D leaves, model units).
    stats: its FitStats. source: the input's file name ('' for arrays).
    """

    #: The default $fn of to_scad.
    SCAD_FN = 96

    def __init__(self, native, tree, stats: FitStats):
        self._native = native
        self.tree = tree
        self.stats = stats

    source = property(lambda self: self._native.source, doc="Input file name ('' for arrays).")

    def to_json(self) -> str:
        """The result as JSON text (schema csgfit/1: docs/JSON_SCHEMA.md)."""
        return self._native.to_json()

    def to_scad(self, fn: Optional[int] = None) -> str:
        """The best tree as OpenSCAD 2021.01 source in model units; fn is $fn for round
        primitives (default SCAD_FN)."""
        return self._native.to_scad(fn=self.SCAD_FN if fn is None else integer("fn", fn, "fn"))

    def to_dict(self) -> dict:
        """The JSON document as plain dicts (what the FreeCAD builder consumes)."""
        return json.loads(self.to_json())

    def __repr__(self) -> str:
        return (f"{type(self).__name__}(primitives={self.stats.primitives}, "
                f"iou={self.stats.iou:.4f}, seconds={self.stats.seconds:.2f}, "
                f"stop_reason={self.stats.stop_reason!r})")


class GridResult(Result):
    """A result fitted on a pixel or voxel grid: raster() and target() show both on it."""

    def raster(self):
        """The solver's raster of the best tree on the target's grid: a bool numpy array,
        (height, width) with row 0 on top in 2D, [i, j, k] = voxel (x, y, z) in 3D."""
        return self._native.raster()

    def target(self):
        """What was fitted, as raster() shows it (True = shape); None for a loaded 2D JSON."""
        return self._native.target()


class Alternative:
    """A structurally different runner-up tree: .tree, .stats, .raster(), .to_scad()."""

    def __init__(self, native, index: int):
        self._native = native
        self._index = index
        self.tree = tree_from_pixels(native.tree(index), native.pixel_size)
        self.stats = FitStats._from_dict(native.stats(index))

    def raster(self):
        """The solver's raster of this tree: bool numpy array (height, width), row 0 on top."""
        return self._native.raster(self._index)

    def to_scad(self, fn: int = 96) -> str:
        """OpenSCAD source of this tree (model units; linear_extrude if thickness > 0)."""
        return self._native.to_scad(self._index, fn)

    def __repr__(self) -> str:
        return (f"Alternative(primitives={self.stats.primitives}, iou={self.stats.iou:.4f}, "
                f"tree={self.tree})")


class FitResult(GridResult):
    """The outcome of fit_image (or load_json).

    tree: Node / Primitive objects in model units. alternatives: list of Alternative, best
    first. width, height: canvas in pixels; pixel_size, thickness: model frame. to_scad()
    extrudes with linear_extrude when thickness > 0.
    """

    def __init__(self, native):
        super().__init__(native, tree_from_pixels(native.tree(), native.pixel_size),
                         FitStats._from_dict(native.stats()))
        self.alternatives = [Alternative(native, i) for i in range(native.alternative_count)]

    width = property(lambda self: self._native.width, doc="Canvas width in pixels.")
    height = property(lambda self: self._native.height, doc="Canvas height in pixels.")
    pixel_size = property(lambda self: self._native.pixel_size, doc="Model units per pixel.")

    @property
    def thickness(self) -> float:
        """Extrusion height in model units (0 = 2D); affects to_scad / to_json."""
        return self._native.thickness

    @thickness.setter
    def thickness(self, value: float) -> None:
        self._native.thickness = number("thickness", value, "thickness")

    def to_dict(self) -> dict:
        """Model-unit tree and stats as plain dicts, with the canvas."""
        return {"tree": self.tree.to_dict(), "stats": vars(self.stats).copy(),
                "pixel_size": self.pixel_size, "thickness": self.thickness,
                "width": self.width, "height": self.height, "source": self.source}


class FitResult3D(GridResult):
    """The outcome of fit_mesh / fit_voxels.

    tree: Node / Primitive3D objects in the input's own units. document: the dimension-3 JSON
        document as a dict, exactly what `csgfit mesh IN -o OUT.json` writes (to_dict() returns
        a copy). stats: FitStats (excess / uncovered in voxels).
    shape, origin, voxel_size: the grid of target() and raster(): the input in its own axes
        at the voxel size the fit ended on; voxel (i, j, k)'s centre is
        origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size.
    warning: what is wrong with the input mesh (open, non-manifold, inverted...), '' if nothing.
    """

    SCAD_FN = 64

    def __init__(self, native):
        document = json.loads(native.to_json())
        super().__init__(native, tree_from_json3d(document["tree"]),
                         FitStats._from_dict(document.get("stats") or {}))
        self.document = document

    shape = property(lambda self: tuple(self._native.shape), doc="Grid size (nx, ny, nz).")
    origin = property(lambda self: tuple(self._native.origin),
                      doc="Model coordinates of the grid's low corner.")
    voxel_size = property(lambda self: self._native.voxel_size, doc="Voxel edge (model units).")
    warning = property(lambda self: self._native.warning, doc="Mesh diagnosis ('' = fine).")

    def volume(self) -> float:
        """The tree's volume as the solver sees it: its voxels times the voxel volume."""
        return float(self.raster().sum()) * self.voxel_size ** 3

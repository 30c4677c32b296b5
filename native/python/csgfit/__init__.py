"""csgfit: turn bitmaps, meshes and voxel grids into compact, editable CSG trees.

    >>> import csgfit
    >>> result = csgfit.fit_image("part.png", pixel_size=0.5, time=2)
    >>> result.stats.iou, result.stats.primitives
    >>> print(result.tree)            # Node / Primitive objects in model units (mm)
    >>> open("part.scad", "w").write(result.to_scad())

3D: ``csgfit.fit_mesh("part.stl", time=20)`` or ``csgfit.fit_voxels(bool_array, ...)`` return a
FitResult3D whose ``document`` is the dimension-3 JSON document of ``csgfit mesh -o x.json``.

Coordinates follow the project's contract: an image of W x H pixels with pixel size s covers
[0, W*s] x [0, H*s] with y pointing up; angles are degrees counter-clockwise.

Image convention: for files and uint8 grey arrays, dark pixels are the shape (Otsu threshold
unless ``threshold`` is given; ``invert=True`` makes light pixels the shape). For bool arrays,
True is the shape (``invert=True`` flips it). Row 0 of an array is the top row of the image.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Callable, Iterator, List, Optional, Sequence, Union

from . import _csgfit

__all__ = [
    "CancelToken",
    "FitProgress",
    "FitResult",
    "FitResult3D",
    "FitStats",
    "InputError",
    "Node",
    "Primitive",
    "default_k",
    "fit_image",
    "fit_mesh",
    "fit_voxels",
    "load_bitmap",
    "load_json",
    "load_mesh",
    "load_voxels",
    "voxelize",
]

CancelToken = _csgfit.CancelToken
FitProgress = _csgfit.FitProgress
#: Raised for bad input or options; a subclass of ValueError with a one-line message.
InputError = _csgfit.InputError
default_k = _csgfit.default_k

PRIMITIVE_TYPES = ("rectangle", "circle", "ellipse", "triangle")
#: 3D primitive names (JSON "type"); "prism" is the triangular prism.
PRIMITIVE_TYPES_3D = ("box", "sphere", "cylinder", "cone", "ellipsoid", "torus", "prism")
#: What fit_mesh / fit_voxels use by default (the CLI's default: no torus).
DEFAULT_PRIMITIVES_3D = ("box", "sphere", "cylinder", "cone", "ellipsoid", "prism")
QUALITIES = ("fast", "default", "best", "paper")


@dataclass
class Primitive:
    """A leaf of the tree, in model units (pixel units times pixel_size), y up.

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
    def op(self) -> str:
        """Always "primitive" (lets code walk a tree without isinstance checks)."""
        return "primitive"

    @property
    def children(self) -> List["Node"]:
        """Always empty."""
        return []

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
        """Plain dict (JSON-friendly) with the type-specific fields."""
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

    def count(self) -> int:
        """Number of primitives in this subtree (1)."""
        return 1

    def walk(self) -> Iterator[Union["Node", "Primitive"]]:
        """Yields this node (pre-order traversal of a leaf)."""
        yield self

    def __str__(self) -> str:
        fields = ", ".join(f"{k}={v:.4g}" for k, v in self.to_dict().items() if k != "type")
        return f"{self.type}({fields})"


@dataclass
class Node:
    """An operator node: op is "union", "difference" (first child minus all others) or
    "intersection"; children are Node or Primitive objects."""

    op: str
    children: List[Union["Node", Primitive]] = field(default_factory=list)

    def to_dict(self) -> dict:
        """Plain nested dict: {"op": ..., "children": [...]}."""
        return {"op": self.op, "children": [c.to_dict() for c in self.children]}

    def count(self) -> int:
        """Number of primitives in this subtree."""
        return sum(c.count() for c in self.children)

    def walk(self) -> Iterator[Union["Node", Primitive]]:
        """Yields every node of the subtree in pre-order."""
        yield self
        for c in self.children:
            yield from c.walk()

    def __str__(self) -> str:
        return f"{self.op}({', '.join(str(c) for c in self.children)})"


@dataclass
class FitStats:
    """How good a tree is and what the search did.

    iou: intersection over union of the tree's raster and the target.
    primitives: leaves in the tree. excess / uncovered: pixels wrongly inside / outside.
    score: excess + uncovered + k * primitives (lower is better). k: the size weight used.
    evaluations: tree evaluations; trees: trees searched; seconds: wall time.
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


def _convert(d: dict, scale: float) -> Union[Node, Primitive]:
    if "op" in d:
        return Node(d["op"], [_convert(c, scale) for c in d["children"]])
    return Primitive(type=d["type"], cx=d["cx"] * scale, cy=d["cy"] * scale, w=d["w"] * scale,
                     h=d["h"] * scale, angle=d["angle"], apex=d["apex"])


class Alternative:
    """A structurally different runner-up tree: .tree, .stats, .raster(), .to_scad()."""

    def __init__(self, native, index: int):
        self._native = native
        self._index = index
        self.tree = _convert(native.tree(index), native.pixel_size)
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


class FitResult:
    """The outcome of fit_image (or load_json).

    tree: the best tree (Node / Primitive objects in model units).
    stats: FitStats of the best tree. alternatives: list of Alternative, best first.
    width, height: canvas in pixels; pixel_size, thickness: model frame; source: input name.
    """

    def __init__(self, native):
        self._native = native
        self.tree = _convert(native.tree(), native.pixel_size)
        self.stats = FitStats._from_dict(native.stats())
        self.alternatives = [Alternative(native, i) for i in range(native.alternative_count)]

    width = property(lambda self: self._native.width, doc="Canvas width in pixels.")
    height = property(lambda self: self._native.height, doc="Canvas height in pixels.")
    pixel_size = property(lambda self: self._native.pixel_size, doc="Model units per pixel.")
    source = property(lambda self: self._native.source, doc="Input file name ('' for arrays).")

    @property
    def thickness(self) -> float:
        """Extrusion height in model units (0 = 2D); affects to_scad / to_json."""
        return self._native.thickness

    @thickness.setter
    def thickness(self, value: float) -> None:
        self._native.thickness = float(value)

    def raster(self):
        """The solver's raster of the best tree: bool numpy array (height, width), row 0 on top."""
        return self._native.raster(-1)

    def target(self):
        """The bitmap that was fitted (bool array, True = shape), or None for loaded JSON."""
        return self._native.target()

    def to_json(self) -> str:
        """The result as JSON text (schema: docs/JSON_SCHEMA.md)."""
        return self._native.to_json()

    def to_scad(self, fn: int = 96) -> str:
        """The best tree as OpenSCAD 2021.01 source (model units; linear_extrude when
        thickness > 0). fn is the default $fn written as a variable."""
        return self._native.to_scad(-1, fn)

    def to_dict(self) -> dict:
        """Model-unit tree and stats as plain dicts (what the FreeCAD builder consumes)."""
        return {"tree": self.tree.to_dict(), "stats": vars(self.stats).copy(),
                "pixel_size": self.pixel_size, "thickness": self.thickness,
                "width": self.width, "height": self.height, "source": self.source}

    def __repr__(self) -> str:
        return (f"FitResult(primitives={self.stats.primitives}, iou={self.stats.iou:.4f}, "
                f"seconds={self.stats.seconds:.2f}, stop_reason={self.stats.stop_reason!r})")


def _primitive_list(primitives) -> str:
    if primitives is None:
        return "all"
    if isinstance(primitives, str):
        return primitives
    items = [str(p) for p in primitives]
    if not items:
        raise InputError("primitives: the list is empty")
    return ",".join(items)


def _mask_from_array(array, threshold: Optional[int], invert: bool):
    import numpy as np

    a = np.asarray(array)
    if a.ndim != 2:
        raise InputError(f"expected a 2D array (height x width), got {a.ndim} dimension"
                         f"{'' if a.ndim == 1 else 's'}")
    if a.size == 0:
        raise InputError(f"empty image ({a.shape[1]} x {a.shape[0]} pixels)")
    if a.dtype == np.bool_:
        return np.logical_not(a) if invert else a
    if a.dtype == np.uint8:
        return _csgfit.threshold_grey(np.ascontiguousarray(a),
                                      -1 if threshold is None else int(threshold), invert)
    raise InputError(f"unsupported array dtype {a.dtype}: pass a bool mask (True = shape) or "
                     "uint8 grey levels (dark = shape)")


def load_bitmap(path: Union[str, os.PathLike], *, threshold: Optional[int] = None,
                invert: bool = False, max_size: int = 0):
    """Reads an image file (PNG, JPEG, BMP, PGM/PBM, TGA) and thresholds it as the CLI does.

    Returns a bool numpy array (height, width), True = shape, row 0 at the top. threshold is a
    grey level (pixels <= it are shape; None = Otsu); max_size > 0 downsamples so that neither
    side exceeds it. Raises InputError (a ValueError) for missing or bad files.
    """
    return _csgfit.load_bitmap(os.fspath(path), -1 if threshold is None else int(threshold),
                               bool(invert), 0, int(max_size))


def fit_image(image, *, threshold: Optional[int] = None, invert: bool = False,
              pixel_size: float = 1.0, thickness: float = 0.0, time: float = 10.0,
              threads: int = 0, seed: int = 1, k: Optional[float] = None,
              primitives: Union[None, str, Sequence[str]] = None, alternatives: int = 0,
              quality: str = "default", max_size: int = 0,
              progress: Optional[Callable[[FitProgress], Optional[bool]]] = None,
              cancel: Optional[CancelToken] = None) -> FitResult:
    """Fits a compact CSG tree to a bitmap.

    image: a file path (PNG, JPEG, BMP, PGM/PBM, TGA), or a 2D numpy array: bool (True =
        shape) or uint8 grey levels (dark = shape, as in files). Row 0 is the top row.
    threshold: grey level for files and uint8 arrays (<= threshold is shape); None = Otsu.
    invert: the light pixels (or the False ones) are the shape.
    pixel_size: model units (mm) per pixel; the tree is returned in model units.
    thickness: > 0 makes to_scad() extrude the 2D result to this height.
    time: wall-time budget in seconds (the search stops earlier when it converges).
    threads: worker threads, 0 = all cores. seed: same seed and threads, same tree.
    k: size weight (penalty per primitive); None = 25 scaled to the image area.
    primitives: "all", or a list / comma-separated string of "rectangle", "circle",
        "ellipse", "triangle".
    alternatives: also return up to this many structurally different good trees.
    quality: "fast", "default", "best" or "paper" (the paper's search settings).
    max_size: for files, downsample so that neither side exceeds it (0 = never).
    progress: called with a FitProgress now and then (from a solver thread, GIL held);
        returning False cancels the fit. An exception raised in it cancels the fit and is
        re-raised by fit_image.
    cancel: a CancelToken; token.cancel() from any thread stops the fit promptly.

    The solver runs with the GIL released, so other Python threads (a GUI) keep running.
    A cancelled fit returns the best tree so far with stats.stop_reason == "cancelled".
    Raises InputError (a ValueError) for bad input: missing or unreadable file, wrong array
    shape or dtype, an image without shape pixels ("no shape found"), bad options.
    """
    if quality not in QUALITIES:
        raise InputError(f"unknown quality '{quality}' (expected {', '.join(QUALITIES)})")
    if cancel is not None and not isinstance(cancel, CancelToken):
        raise InputError("cancel must be a csgfit.CancelToken")
    if isinstance(image, (str, bytes, os.PathLike)):
        path = os.fsdecode(image)
        mask = load_bitmap(path, threshold=threshold, invert=invert, max_size=max_size)
        source = os.path.basename(path)
    else:
        mask = _mask_from_array(image, threshold, invert)
        source = ""
    if not mask.any():
        raise InputError("no shape found: the image has no shape pixels (try invert=True?)")
    native = _csgfit.fit(mask, k=-1.0 if k is None else float(k),
                         primitives=_primitive_list(primitives), time=float(time),
                         threads=int(threads), seed=int(seed), alternatives=int(alternatives),
                         quality=quality, progress=progress, cancel=cancel,
                         pixel_size=float(pixel_size), thickness=float(thickness), source=source)
    return FitResult(native)


def load_json(text_or_path: Union[str, os.PathLike]) -> FitResult:
    """Reads a result written by FitResult.to_json() or `csgfit image ... -o X.json`.

    Accepts the JSON text itself or a path to a .json file. Raises InputError when malformed.
    """
    text = os.fspath(text_or_path)
    if text.lstrip().startswith("{"):
        return FitResult(_csgfit.from_json(text))
    return FitResult(_csgfit.load_json_file(text))


# ---- 3D ------------------------------------------------------------------------------------


class FitResult3D:
    """The outcome of fit_mesh / fit_voxels.

    document: the dimension-3 JSON document as a dict (docs/JSON_SCHEMA.md, "3D documents"),
        exactly what `csgfit mesh IN -o OUT.json` writes: its "tree" holds operator nodes and
        primitives with "center", "rotation" (unit quaternion w, x, y, z, local -> model) and
        their sizes, in the mesh's own units.
    tree: document["tree"]. stats: FitStats (excess / uncovered in voxels).
    shape, origin, voxel_size: the voxel grid the fit was scored on.
    source: the input's file name ('' for arrays). warning: what is wrong with the input mesh
        (open, non-manifold, inverted...), '' when nothing.
    """

    def __init__(self, native):
        import json

        self._native = native
        self.document = json.loads(native.to_json())
        self.tree = self.document["tree"]
        self.stats = FitStats._from_dict(self.document.get("stats") or {})

    shape = property(lambda self: tuple(self._native.shape), doc="Grid size (nx, ny, nz).")
    origin = property(lambda self: tuple(self._native.origin),
                      doc="Model coordinates of the grid's low corner.")
    voxel_size = property(lambda self: self._native.voxel_size, doc="Voxel edge (model units).")
    source = property(lambda self: self._native.source, doc="Input file name ('' for arrays).")
    warning = property(lambda self: self._native.warning, doc="Mesh diagnosis ('' = fine).")

    def target(self):
        """The voxels that were fitted: bool array [i, j, k] = voxel (x, y, z); voxel (i, j, k)'s
        centre is origin + (i + 0.5, j + 0.5, k + 0.5) * voxel_size."""
        return self._native.target()

    def raster(self):
        """The solver's voxels of the tree on the same grid (bool array like target())."""
        return self._native.raster()

    def volume(self) -> float:
        """The tree's volume as the solver sees it: its voxels times the voxel volume."""
        return float(self.raster().sum()) * self.voxel_size ** 3

    def to_json(self) -> str:
        """The 3D JSON document as text."""
        return self._native.to_json()

    def to_dict(self) -> dict:
        """A copy of the 3D JSON document (what the FreeCAD builder consumes)."""
        import copy

        return copy.deepcopy(self.document)

    def to_scad(self, fn: int = 64) -> str:
        """The tree as OpenSCAD 2021.01 source (model units); fn is $fn for round primitives."""
        return self._native.to_scad(fn)

    def __repr__(self) -> str:
        return (f"FitResult3D(primitives={self.stats.primitives}, iou={self.stats.iou:.4f}, "
                f"seconds={self.stats.seconds:.2f}, stop_reason={self.stats.stop_reason!r})")


def _primitive_list_3d(primitives) -> str:
    if primitives is None:
        return ",".join(DEFAULT_PRIMITIVES_3D)
    return _primitive_list(primitives)


def _check_fit_args(cancel, progress):
    if cancel is not None and not isinstance(cancel, CancelToken):
        raise InputError("cancel must be a csgfit.CancelToken")
    if progress is not None and not callable(progress):
        raise InputError("progress must be callable or None")


def load_mesh(path: Union[str, os.PathLike]):
    """Reads an STL, OBJ, OFF or PLY mesh: (vertices float (n, 3), triangles int32 (m, 3)).
    Raises InputError for a missing, truncated, mislabelled or empty file."""
    return _csgfit.load_mesh(os.fspath(path))


def load_voxels(path: Union[str, os.PathLike]):
    """Reads a .npy or .binvox voxel grid: (bool array [i, j, k], origin (x, y, z), voxel_size)."""
    return _csgfit.load_voxels(os.fspath(path))


def voxelize(vertices, triangles, *, resolution: int = 0, voxel_size: float = 0.0):
    """Solid voxels of a mesh as `csgfit mesh` makes them: (bool array [i, j, k], origin,
    voxel_size, warning). resolution: voxels along the longest side; voxel_size: explicit edge;
    both 0 = automatic (about 11 voxels across the mean wall thickness, 96..256 along the
    longest side, at most 160^3 voxels)."""
    import numpy as np

    return _csgfit.voxelize(np.asarray(vertices, dtype=np.float64),
                            np.asarray(triangles, dtype=np.int64), int(resolution),
                            float(voxel_size))


def fit_mesh(mesh, *, resolution: int = 0, voxel_size: float = 0.0, time: float = 30.0,
             threads: int = 0, seed: int = 1, k: Optional[float] = None,
             primitives: Union[None, str, Sequence[str]] = None,
             progress: Optional[Callable[[FitProgress], Optional[bool]]] = None,
             cancel: Optional[CancelToken] = None) -> FitResult3D:
    """Fits a 3D CSG tree to a mesh or a voxel file, as `csgfit mesh` does.

    mesh: a path (STL, OBJ, OFF, PLY; or .npy / .binvox voxel grids, fitted as they are) or a
        (vertices (n, 3), triangles (m, 3)) pair of arrays, in the mesh's own units.
    resolution / voxel_size: the voxelisation (see voxelize; both 0 = automatic).
    time: wall-time budget in seconds (the search stops earlier when it converges).
    threads: 0 = all cores. seed: same seed and threads, same tree (when it converges).
    k: size weight per primitive in voxels; None = 200 per million grid voxels.
    primitives: list or comma-separated names of PRIMITIVE_TYPES_3D, or "all"; boxes are
        required. Default: all but the torus.
    progress / cancel: as for fit_image (cancel stops the fit within a fraction of a second and
        returns the best tree so far, stats.stop_reason == "cancelled").

    The GIL is released while voxelising and solving. Raises InputError (a ValueError) for bad
    input: unreadable files, wrong array shapes, NaN, indices out of range, no solid, options.
    """
    import numpy as np

    _check_fit_args(cancel, progress)
    kw = dict(k=-1.0 if k is None else float(k), primitives=_primitive_list_3d(primitives),
              time=float(time), threads=int(threads), seed=int(seed), progress=progress,
              cancel=cancel)
    if isinstance(mesh, (str, bytes, os.PathLike)):
        path = os.fsdecode(mesh)
        return FitResult3D(_csgfit.fit_file(path, resolution=int(resolution),
                                            voxel_size=float(voxel_size),
                                            source=os.path.basename(path), **kw))
    try:
        vertices, triangles = mesh
    except (TypeError, ValueError):
        raise InputError("mesh must be a path or a (vertices, triangles) pair") from None
    try:
        v = np.asarray(vertices, dtype=np.float64)
        t = np.asarray(triangles, dtype=np.int64)
    except (TypeError, ValueError) as e:
        raise InputError(f"mesh arrays: {e}") from None
    return FitResult3D(_csgfit.fit_mesh_arrays(v, t, resolution=int(resolution),
                                               voxel_size=float(voxel_size), **kw))


def fit_voxels(voxels, *, origin: Sequence[float] = (0.0, 0.0, 0.0), voxel_size: float = 1.0,
               time: float = 30.0, threads: int = 0, seed: int = 1, k: Optional[float] = None,
               primitives: Union[None, str, Sequence[str]] = None,
               progress: Optional[Callable[[FitProgress], Optional[bool]]] = None,
               cancel: Optional[CancelToken] = None, source: str = "") -> FitResult3D:
    """Fits a 3D CSG tree to a voxel array.

    voxels: 3D array, [i, j, k] = voxel (x, y, z), nonzero / True = solid (the .npy
        convention). Voxel (i, j, k) is the cube from origin + (i, j, k) * voxel_size to
        origin + (i + 1, j + 1, k + 1) * voxel_size. Other arguments as for fit_mesh.
    """
    import numpy as np

    _check_fit_args(cancel, progress)
    try:
        a = np.asarray(voxels)
    except (TypeError, ValueError) as e:
        raise InputError(f"voxels: {e}") from None
    if a.dtype.kind not in "biuf":
        raise InputError(f"unsupported voxel dtype {a.dtype} (bool or numbers, nonzero = solid)")
    if a.dtype.kind == "f" and a.size and not np.isfinite(a).all():
        raise InputError("voxels: NaN or infinite values")
    if a.ndim != 3:
        raise InputError(f"expected a 3D voxel array (nx x ny x nz), got {a.ndim} dimension"
                         f"{'' if a.ndim == 1 else 's'}")
    try:
        origin = [float(x) for x in origin]
    except (TypeError, ValueError):
        raise InputError("origin must be three numbers") from None
    return FitResult3D(_csgfit.fit_voxels(
        np.ascontiguousarray(a != 0).view(np.uint8), origin, float(voxel_size),
        k=-1.0 if k is None else float(k), primitives=_primitive_list_3d(primitives),
        time=float(time), threads=int(threads), seed=int(seed), progress=progress,
        cancel=cancel, source=str(source)))

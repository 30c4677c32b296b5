"""csgfit: turn bitmaps into compact, editable CSG trees.

    >>> import csgfit
    >>> result = csgfit.fit_image("part.png", pixel_size=0.5, time=2)
    >>> result.stats.iou, result.stats.primitives
    >>> print(result.tree)            # Node / Primitive objects in model units (mm)
    >>> open("part.scad", "w").write(result.to_scad())

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
    "FitStats",
    "InputError",
    "Node",
    "Primitive",
    "default_k",
    "fit_image",
    "load_bitmap",
    "load_json",
]

CancelToken = _csgfit.CancelToken
FitProgress = _csgfit.FitProgress
#: Raised for bad input or options; a subclass of ValueError with a one-line message.
InputError = _csgfit.InputError
default_k = _csgfit.default_k

PRIMITIVE_TYPES = ("rectangle", "circle", "ellipse", "triangle")
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
        return cls(**{k: v for k, v in d.items() if k in names})


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
    if not text.lstrip().startswith("{"):
        try:
            with open(text, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise InputError(f"cannot read {text}: {e.strerror}") from None
    return FitResult(_csgfit.from_json(text))

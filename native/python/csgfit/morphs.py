"""Two shapes in, a MorphResult out (seed 000's morphing): csgfit.morph."""

from __future__ import annotations

import json
import os
from typing import Callable, Optional, Sequence, Union

from . import _csgfit
from .bitmaps import _mask_from_array, load_bitmap
from .options import CancelToken, FitProgress, InputError, integer, number, search_arguments
from .ranges import _write_fcstd, _write_text
from .results import FitStats
from .tree import tree_from_json3d, tree_from_pixels

PRESETS = ("default", "paper")
ROTATIONS = ("shortest", "cw", "ccw")


class MorphResult:
    """Two trees of one structure: tree_a matches shape A, tree_b shape B, leaf for leaf.

    stats_a / stats_b: each tree against its own shape (FitStats; the search's counters in
    both). leaves: per leaf in pre-order, {"in_a": bool, "in_b": bool}: a leaf seen in one
    shape only has size 0 in the other, at a point of its partner, so the morph grows it there.
    frame(t): the solver's raster of the morph at t (2D bool array; 3D voxels on the shared
    grid). to_scad(): one model with a `morph` parameter (0 = A, 1 = B; -1 follows $t for
    OpenSCAD's animation). to_json(): A's document with a "morph" object (docs/JSON_SCHEMA.md).
    """

    def __init__(self, native, dimension: int):
        self._native = native
        self.dimension = dimension
        self.stats_a = FitStats._from_dict(native.stats_a())
        self.stats_b = FitStats._from_dict(native.stats_b())
        self.leaves = native.leaves()
        if dimension == 2:
            s = native.pixel_size
            self.tree_a = tree_from_pixels(native.tree_a(), s)
            self.tree_b = tree_from_pixels(native.tree_b(), s)
        else:
            doc = json.loads(native.to_json())
            self.tree_a = tree_from_json3d(doc["tree"])
            self.tree_b = tree_from_json3d(doc["morph"]["tree_b"])

    source = property(lambda self: self._native.source, doc="A's file name ('' for arrays).")

    @property
    def thickness(self) -> float:
        """2D: the extrusion height of to_scad() in mm (0 = flat); settable, as FreeCAD's Export
        OpenSCAD does with the group's thickness cell."""
        return self._native.thickness if self.dimension == 2 else 0.0

    @thickness.setter
    def thickness(self, value: float) -> None:
        if self.dimension != 2:
            raise InputError("a 3D morph has no thickness")
        self._native.thickness = number("thickness", value, "thickness")
    source_b = property(lambda self: self._native.source_b, doc="B's file name ('' for arrays).")

    def frame(self, t: float):
        """The morph at t in [0, 1] as the solver rasterises it (0 = A's tree, 1 = B's)."""
        t = number("t", t, "time") if not isinstance(t, (int, float)) else float(t)
        if self.dimension == 2:
            return self._native.raster(t)
        return self._native.voxels(t)

    def to_json(self) -> str:
        return self._native.to_json()

    def to_scad(self, fn: Optional[int] = None) -> str:
        default = 96 if self.dimension == 2 else 64
        return self._native.to_scad(fn=default if fn is None else integer("fn", fn, "fn"))

    def save(self, path) -> str:
        """Writes the morph by the file's extension: .scad, .json or .FCStd (one parametric
        FreeCAD tree driven by a spreadsheet cell `morph`)."""
        path = os.fsdecode(path)
        ext = os.path.splitext(path)[1].lower()
        if ext in (".scad", ".json"):
            _write_text(path, self.to_scad() if ext == ".scad" else self.to_json())
        elif ext == ".fcstd":
            _write_fcstd(self.to_json(), path)
        else:
            raise InputError(f"cannot write '{path}': a morph is written as .scad, .json or .FCStd")
        return path

    def __repr__(self) -> str:
        return (f"MorphResult(primitives={self.stats_a.primitives}, iou_a={self.stats_a.iou:.4f}, "
                f"iou_b={self.stats_b.iou:.4f}, seconds={self.stats_a.seconds:.2f})")


def _mask(image, threshold, invert, max_size):
    if isinstance(image, (str, bytes, os.PathLike)):
        path = os.fsdecode(image)
        return load_bitmap(path, threshold=threshold, invert=invert, max_size=max_size), \
            os.path.basename(path)
    return _mask_from_array(image, threshold, invert), ""


def morph(a, b, *, threshold: Optional[int] = None, invert: bool = False,
          pixel_size: float = 1.0, thickness: float = 0.0, time: float = 10.0, threads: int = 0,
          seed: int = 1, k: Optional[float] = None,
          primitives: Union[None, str, Sequence[str]] = None, preset: str = "default",
          rotate: str = "shortest", max_size: int = 0, resolution: int = 0,
          progress: Optional[Callable[[FitProgress], Optional[bool]]] = None,
          cancel: Optional[CancelToken] = None) -> MorphResult:
    """Finds two CSG trees of one structure, one for shape A and one for shape B, to morph
    between (seed 000: the pair search; REP, ADD and CUT act on both trees alike).

    a, b: two images (paths, or 2D arrays as fit_image takes them) of the same size, or two
        mesh / voxel files (.stl, .obj, .off, .ply, .npy, .binvox), put on one grid of
        `resolution` voxels along the longest side of both (0 = 64).
    preset: "default" (our first trees copied into both trees of a pair, beside random pairs)
        or "paper" (seed 000's Table 2 with a = 5, as its morphing runs).
    rotate: how 2D primitives turn from A to B: "shortest", "cw" or "ccw".
    The other arguments are fit_image's (fit_mesh's for 3D). Raises InputError for images of
    different sizes (both named), an image and a mesh together, an empty shape or bad options.
    """
    if preset not in PRESETS:
        raise InputError(f"unknown preset '{preset}' (expected {', '.join(PRESETS)})")
    if rotate not in ROTATIONS:
        raise InputError(f"unknown rotation '{rotate}' (expected {', '.join(ROTATIONS)})")
    solid = _three_dimensional(a, b)
    search = search_arguments(k=k, primitives=primitives, time=time, threads=threads, seed=seed,
                              progress=progress, cancel=cancel,
                              default_primitives="" if solid else "all")
    if solid:
        return MorphResult(_csgfit.morph_files3d(
            os.fsdecode(a), os.fsdecode(b), resolution=integer("resolution", resolution, "resolution"),
            source_a=os.path.basename(os.fsdecode(a)), source_b=os.path.basename(os.fsdecode(b)),
            **search), 3)
    pixel_size = number("pixel_size", pixel_size, "scale")
    thickness = number("thickness", thickness, "thickness")
    mask_a, source_a = _mask(a, threshold, invert, max_size)
    mask_b, source_b = _mask(b, threshold, invert, max_size)
    if mask_a.shape != mask_b.shape:
        raise InputError(f"the images differ in size: A is {mask_a.shape[1]} x {mask_a.shape[0]} "
                         f"pixels, B {mask_b.shape[1]} x {mask_b.shape[0]}")
    for name, m in (("A", mask_a), ("B", mask_b)):
        if not m.any():
            raise InputError(f"no shape found in {name}: it has no shape pixels (try invert=True?)")
    return MorphResult(_csgfit.morph(mask_a, mask_b, preset=preset, rotate=rotate,
                                     pixel_size=pixel_size, thickness=thickness,
                                     source_a=source_a, source_b=source_b, **search), 2)


def _three_dimensional(a, b) -> bool:
    """Two mesh / voxel files (by extension, as the readers pick them); images or arrays
    otherwise. A mix of an image and a 3D file is refused."""
    def solid(x):
        return isinstance(x, (str, bytes, os.PathLike)) and _csgfit.is_3d_input(os.fsdecode(x))
    if solid(a) != solid(b):
        raise InputError("give two images or two meshes / voxel files, not one of each")
    return solid(a)

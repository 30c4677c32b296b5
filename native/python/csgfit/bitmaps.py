"""Bitmaps in, FitResult out: fit_image, load_bitmap and load_json."""

from __future__ import annotations

import os
from typing import Callable, Optional, Sequence, Union

from . import _csgfit
from .options import (QUALITIES, CancelToken, FitProgress, InputError, check_array_size, integer,
                      number, search_arguments)
from .results import FitResult


def _mask_from_array(array, threshold: Optional[int], invert: bool):
    import numpy as np

    try:
        a = np.asarray(array)
    except (TypeError, ValueError) as e:
        raise InputError(f"image: {str(e).splitlines()[0]}") from None
    if a.ndim != 2:
        raise InputError(f"expected a 2D array (height x width), got {a.ndim} dimension"
                         f"{'' if a.ndim == 1 else 's'}")
    if a.size == 0:
        raise InputError(f"empty image ({a.shape[1]} x {a.shape[0]} pixels)")
    why = _csgfit.rule_violation("pixel_count", float(a.size))
    if why:
        raise InputError(f"a {a.shape[1]} x {a.shape[0]} image: its pixel count {why}")
    check_array_size(a, f"a {a.shape[1]} x {a.shape[0]} image")
    if a.dtype == np.bool_:
        return np.ascontiguousarray(np.logical_not(a) if invert else a)
    if a.dtype == np.uint8:
        return _csgfit.threshold_grey(np.ascontiguousarray(a), _threshold(threshold), invert)
    raise InputError(f"unsupported array dtype {a.dtype}: pass a bool mask (True = shape) or "
                     "uint8 grey levels (dark = shape)")


def _threshold(threshold) -> int:
    return -1 if threshold is None else integer("threshold", threshold, "threshold")


def _max_size(max_size) -> int:
    return 0 if max_size == 0 else integer("max_size", max_size, "image_side")


def load_bitmap(path: Union[str, os.PathLike], *, threshold: Optional[int] = None,
                invert: bool = False, max_size: int = 0):
    """Reads an image file (PNG, JPEG, BMP, PGM/PBM, TGA) and thresholds it as the CLI does.

    Returns a bool numpy array (height, width), True = shape, row 0 at the top. threshold is a
    grey level (pixels <= it are shape; None = Otsu); max_size > 0 downsamples so that neither
    side exceeds it. Raises InputError (a ValueError) for missing or bad files.
    """
    return _csgfit.load_bitmap(os.fspath(path), _threshold(threshold), bool(invert), 0,
                               _max_size(max_size))


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
    search = search_arguments(k=k, primitives=primitives, time=time, threads=threads, seed=seed,
                              progress=progress, cancel=cancel, default_primitives="all")
    # Checked whether or not this input uses them, as the CLI checks its options.
    _threshold(threshold)
    _max_size(max_size)
    alternatives = integer("alternatives", alternatives, "alternatives")
    pixel_size = number("pixel_size", pixel_size, "scale")
    thickness = number("thickness", thickness, "thickness")
    if isinstance(image, (str, bytes, os.PathLike)):
        path = os.fsdecode(image)
        mask = load_bitmap(path, threshold=threshold, invert=invert, max_size=max_size)
        source = os.path.basename(path)
    else:
        mask = _mask_from_array(image, threshold, invert)
        source = ""
    if not mask.any():
        raise InputError("no shape found: the image has no shape pixels (try invert=True?)")
    return FitResult(_csgfit.fit(mask, alternatives=alternatives, quality=quality,
                                 pixel_size=pixel_size, thickness=thickness,
                                 source=source, **search))


def load_json(text_or_path: Union[str, os.PathLike]):
    """Reads a result written by FitResult.to_json() or `csgfit image ... -o X.json`; a 2D morph
    document (`csgfit morph ... -o X.json`) comes back as a csgfit.MorphResult.

    Accepts the JSON text itself or a path to a .json file. Raises InputError when malformed.
    """
    try:
        text = os.fspath(text_or_path)
    except TypeError:
        raise InputError("load_json takes JSON text or a path") from None
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    # Text, not a path: JSON starts with "{" (or "[" for a malformed one), and no path has a
    # line break or is longer than the system's path limit.
    if not (text.lstrip()[:1] in ("{", "[") or "\n" in text or len(text) > 4096):
        text = _csgfit.read_json_file(text)
    if _csgfit.is_json_morph(text):
        from .morphs import MorphResult
        return MorphResult(_csgfit.morph_from_json(text), 2)
    return FitResult(_csgfit.from_json(text))

"""The keyword arguments every fit shares, checked and put in the native module's form."""

from __future__ import annotations

from typing import Optional, Sequence, Union

from . import _csgfit

#: Raised for bad input or options; a subclass of ValueError with a one-line message.
InputError = _csgfit.InputError
CancelToken = _csgfit.CancelToken
FitProgress = _csgfit.FitProgress

PRIMITIVE_TYPES = ("rectangle", "circle", "ellipse", "triangle")
#: 3D primitive names (JSON "type"); "prism" is the triangular prism.
PRIMITIVE_TYPES_3D = ("box", "sphere", "cylinder", "cone", "ellipsoid", "torus", "prism")
#: What fit_mesh / fit_voxels use by default (the CLI's default: no torus).
DEFAULT_PRIMITIVES_3D = ("box", "sphere", "cylinder", "cone", "ellipsoid", "prism")
QUALITIES = ("fast", "default", "best", "paper")


def primitive_list(primitives: Union[None, str, Sequence[str]], default: str) -> str:
    """The comma-separated names the native fits parse (and refuse with one line)."""
    if primitives is None:
        return default
    if isinstance(primitives, str):
        return primitives
    items = [str(p) for p in primitives]
    if not items:
        raise InputError("primitives: the list is empty")
    return ",".join(items)


def search_arguments(*, k: Optional[float], primitives, time: float, threads: int, seed: int,
                     progress, cancel, default_primitives: str) -> dict:
    """The search keyword arguments of _csgfit.fit, fit_mesh_arrays, fit_voxels and fit_file."""
    if cancel is not None and not isinstance(cancel, CancelToken):
        raise InputError("cancel must be a csgfit.CancelToken")
    if progress is not None and not callable(progress):
        raise InputError("progress must be callable or None")
    return dict(k=-1.0 if k is None else float(k),
                primitives=primitive_list(primitives, default_primitives), time=float(time),
                threads=int(threads), seed=int(seed), progress=progress, cancel=cancel)

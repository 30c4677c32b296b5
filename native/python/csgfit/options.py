"""The keyword arguments every fit shares, checked and put in the native module's form."""

from __future__ import annotations

import numbers
import operator
from typing import Optional, Sequence, Union

from . import _csgfit

#: Raised for bad input or options; a subclass of ValueError with a one-line message.
InputError = _csgfit.InputError
CancelToken = _csgfit.CancelToken
FitProgress = _csgfit.FitProgress

PRIMITIVE_TYPES = ("rectangle", "circle", "ellipse", "triangle")
#: 3D primitive names (JSON "type"); "prism" is the triangular prism.
PRIMITIVE_TYPES_3D = ("box", "sphere", "cylinder", "cone", "ellipsoid", "torus", "prism",
                      "rounded_box")
#: What fit_mesh / fit_voxels use by default: the CLI's default, from the same place.
DEFAULT_PRIMITIVES_3D = tuple(_csgfit.DEFAULT_MESH_PRIMITIVES.split(","))
QUALITIES = ("fast", "default", "best", "paper")


def number(name: str, value, rule: str, *, optional: bool = False) -> Optional[float]:
    """value as a float within the native option rule `rule` (the CLI's table, README
    "Limits"), or one InputError line naming the argument. None passes when optional."""
    if value is None and optional:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a number, got {_shown(value)}")
    try:
        v = float(value)
    except OverflowError:  # an int beyond a double
        v = float("inf") if value > 0 else float("-inf")
    return _obeying(name, v, rule)


def integer(name: str, value, rule: str) -> int:
    """value as an int within the native option rule `rule`, or one InputError line."""
    v = _index(name, value)
    _obeying(name, float(v) if abs(v) < 2 ** 1000 else float("inf"), rule)
    return v


def _index(name: str, value) -> int:
    if not isinstance(value, bool):
        try:
            return operator.index(value)
        except TypeError:
            pass
    raise InputError(f"{name} must be an integer, got {_shown(value)}")


def _obeying(name: str, value: float, rule: str) -> float:
    why = _csgfit.rule_violation(rule, value)
    if why:
        raise InputError(f"{name} {why}")
    return value


def seed_value(seed) -> int:
    """A seed: an int in 0 .. 2^64 - 1, as the CLI's --seed."""
    v = _index("seed", seed)
    if not 0 <= v < 2 ** 64:
        raise InputError(f"seed must be an integer in 0 .. {2 ** 64 - 1}, not {_shown(v)}")
    return v


def _shown(value) -> str:
    """A value in a message: its repr, cut short (a 2 MB string must not become the message)."""
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def check_array_size(array, what: str) -> None:
    """Refuses an array whose contiguous copy would exceed the memory budget (a zero-stride
    broadcast can claim 10^15 elements without owning them)."""
    _csgfit.check_allocation(float(array.size) * array.itemsize, what)


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
    return dict(k=-1.0 if k is None else number("k", k, "k"),
                primitives=primitive_list(primitives, default_primitives),
                time=number("time", time, "time"), threads=integer("threads", threads, "threads"),
                seed=seed_value(seed), progress=progress, cancel=cancel)


def set_max_memory(size: Union[int, str, None]) -> None:
    """Sets the memory budget that every large allocation checks first (the CLI's
    --max-memory): bytes as an int, or a string such as "4G" or "512M"; None restores the
    default, half of the machine's memory. Over-budget inputs raise InputError."""
    if size is None:
        _csgfit.reset_max_memory()
        return
    if isinstance(size, bool) or not isinstance(size, (numbers.Integral, str)):
        raise InputError(f"max_memory must be bytes or a size such as '4G', got {_shown(size)}")
    _csgfit.set_max_memory(str(size))

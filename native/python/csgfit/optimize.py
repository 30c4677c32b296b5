"""Seed 001's CSG-tree optimiser: the same solid from a smaller tree (``csgfit optimize``)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import List, Tuple, Union

from . import _csgfit
from .options import number, seed_value

METHODS = ("auto", "espresso", "qmc", "setcover", "ga")


@dataclass
class OptimizeResult:
    """The optimised program as OpenSCAD text (``scad`` readable, ``csg`` flattened), with
    what the optimiser did: sizes (literals plus operations, seed 001's measure), primitives,
    the proximity of Sec. 4 before and after, and the GA's Pareto front of (size, proximity)
    when method="ga"."""

    scad: str
    csg: str
    size_before: int
    size_after: int
    primitives_before: int
    primitives_after: int
    proximity_before: float
    proximity_after: float
    opaque: int
    seconds: float
    pareto: List[Tuple[int, float]] = field(default_factory=list)
    stages: List[Tuple[str, int]] = field(default_factory=list)

    def save(self, path: Union[str, os.PathLike]) -> str:
        """Writes .scad (readable) or .csg (flattened); returns the path."""
        path = os.fspath(path)
        ext = os.path.splitext(path)[1].lower()
        if ext not in (".scad", ".csg"):
            raise _csgfit.InputError("OptimizeResult.save writes .scad or .csg, not '%s'" % path)
        with open(path, "w") as f:
            f.write(self.scad if ext == ".scad" else self.csg)
        return path


def optimize(source: Union[str, os.PathLike], *, method: str = "auto", proximity_weight: float = 2.0,
             time: float = 10.0, seed: int = 1) -> OptimizeResult:
    """Optimises an OpenSCAD program: ``source`` is a .scad path (run through OpenSCAD), a .csg
    path, or .csg text (what FreeCAD's OpenSCAD exporter writes). Opaque calls (hull,
    minkowski, ...) are kept as they are."""
    if method not in METHODS:
        raise _csgfit.InputError("unknown method '%s' (%s)" % (method, ", ".join(METHODS)))
    weight = number("proximity_weight", proximity_weight, "weight")
    seconds = number("time", time, "time")
    text = os.fspath(source)
    is_path = isinstance(source, os.PathLike) or (
        "\n" not in text and os.path.splitext(text)[1].lower() in (".scad", ".csg"))
    d = _csgfit.optimize_program(text, is_path, method, weight, seconds, seed_value(seed))
    r = d["report"]
    return OptimizeResult(scad=d["scad"], csg=d["csg"], size_before=r["size_before"], size_after=r["size_after"],
                          primitives_before=d["primitives_before"], primitives_after=d["primitives_after"],
                          proximity_before=r["proximity_before"], proximity_after=r["proximity_after"],
                          opaque=r["opaque"], seconds=r["seconds"], pareto=list(r["pareto"]),
                          stages=list(r["stages"]))

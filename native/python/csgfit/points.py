"""Scanned point clouds in, PointsFitResult out (seed 004): fit_points, as `csgfit points`.

Seed 004's GP/ES on islands evolves a CSG tree whose terminals are the analytic primitives and
NURBS terminals (a bicubic B-spline patch and the solid under it), scored per point by distance,
normals and curvature type against the number of nodes; where the cloud is a height field the
patch's control net is fitted by least squares first.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from typing import Optional, Sequence, Union

from . import _csgfit
from .options import CancelToken, InputError, integer, number, search_arguments
from .ranges import CloudResult, Progress, fit_range_points, point_arrays, point_file
from .results import FitStats
from .tree import tree_from_json3d

#: What fit_points uses by default (the CLI's default).
DEFAULT_PRIMITIVES_POINTS = ("box", "sphere", "cylinder", "nurbs")
SCANS = ("auto", "top", "all")
SEARCHES = ("gp", "hill", "range")


@dataclass
class PointFitness:
    """Seed 004's fitness of the result on every point: fitness = distance_term + normals_term
    + curvature_term - nodes / c (each term a mean over the points), the floor samples' term,
    and the mean distance of the points to the tree (model units)."""

    fitness: float
    distance_term: float
    normals_term: float
    curvature_term: float
    floor_term: float
    mean_distance: float
    nodes: int


class PointsFitResult(CloudResult):
    """The outcome of fit_points (search "gp" or "hill").

    tree: Node / Primitive3D objects in model units (a NURBS terminal is a Primitive3D of type
        "nurbs" with its degree, knots and control net). stats: FitStats (score = fitness).
    document: the JSON document as `csgfit points -o x.json` writes it (a dict).
    fitness: PointFitness. scan: "top" or "all". search: "gp" or "hill". islands, generations:
    of the GP/ES (0 for the hill climbing). first_tree: where the search started ("levels and
    detected", "levels", "detected", "random" or "voxels").
    patch_rms: the NURBS patch's least-squares residual, None without a patch.
    """

    def __init__(self, native):
        document = json.loads(native.to_json())
        super().__init__(native, tree_from_json3d(document["tree"]),
                         FitStats._from_dict(document.get("stats") or {}))
        self.document = document
        p = document["points"]
        self.fitness = PointFitness(
            float(p["fitness"]), float(p["distance_term"]), float(p["normals_term"]),
            float(p["curvature_term"]), float(p["floor_term"]), float(p["mean_distance"]),
            int(p["nodes"]))
        self.scan, self.search = p["scan"], p["search"]
        self.islands, self.generations = int(p["islands"]), int(p["generations"])
        self.first_tree = p["first_tree"]
        self.patch_rms = None if p["patch_rms"] < 0 else float(p["patch_rms"])

    def report(self) -> str:
        """Seed 004's terms of the result, as `csgfit points --report` prints them."""
        return self._native.report()

    def __repr__(self) -> str:
        return (f"PointsFitResult(primitives={self.stats.primitives}, scan={self.scan!r}, "
                f"search={self.search!r}, fitness={self.fitness.fitness:.4f}, "
                f"mean_distance={self.fitness.mean_distance:.4g}, "
                f"seconds={self.stats.seconds:.2f})")


def _choice(name: str, value, choices) -> str:
    if value not in choices:
        raise InputError(f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def fit_points(points, normals=None, *, search: str = "gp", scan: str = "auto",
               floor: float = 0.0, islands: int = 4, time: float = 30.0, seed: int = 1,
               threads: int = 0, primitives: Union[None, str, Sequence[str]] = None,
               progress: Progress = None, cancel: Optional[CancelToken] = None):
    """Fits a CSG tree with NURBS terminals to a scanned point cloud, as `csgfit points` does.

    points: an (n, 3) array in model units, or a path to a .xyz / .ply file (normals from
        the file where it has them).
    normals: (n, 3) outward normals, or None to estimate them (nearest neighbours, oriented
        consistently and outwards).
    search: "gp" (seed 004's GP/ES on `islands` populations), "hill" (the voxel hill climbing,
        to compare) or "range" (seed 002's surface detector and precedence graph: returns a
        RangeFitResult; scan, floor and islands do not apply).
    scan: "top" (seen from above: the solid is everything between `floor` and the surface),
        "all" (all around) or "auto" (from the normals: no point facing down = top).
    time: wall-time budget in seconds. seed: same seed, same tree when the search ends by
        generations. threads: 0 = all cores. primitives: list or comma-separated names
        (default DEFAULT_PRIMITIVES_POINTS; "nurbs" allows the NURBS terminal).
    progress / cancel: as for fit_mesh.

    The GIL is released while fitting. Raises InputError (one line) for bad input: fewer than
    20 points, NaN or inf, normals of zero length, points on a line, or on a plane for a scan
    all around, a file claiming more points than it holds, a bad argument.
    """
    _choice("search", search, SEARCHES)
    if search == "range":
        if (scan, floor, islands) != ("auto", 0.0, 4):
            raise InputError("scan, floor and islands apply to search 'gp' and 'hill', not 'range'")
        return fit_range_points(points, normals, time=time, seed=seed, threads=threads,
                                primitives=primitives, progress=progress, cancel=cancel)
    args = search_arguments(k=None, primitives=primitives, time=time, threads=threads, seed=seed,
                            progress=progress, cancel=cancel,
                            default_primitives=",".join(DEFAULT_PRIMITIVES_POINTS))
    del args["k"]
    args.update(scan=_choice("scan", scan, SCANS), floor=number("floor", floor, "height"),
                search=search, islands=integer("islands", islands, "islands"))
    if isinstance(points, (str, bytes, os.PathLike)):
        return PointsFitResult(_csgfit.fit_points_files([point_file(points, normals)], **args))
    cloud, given_normals = point_arrays(points, normals)
    return PointsFitResult(_csgfit.fit_points_cloud(cloud, given_normals, **args))

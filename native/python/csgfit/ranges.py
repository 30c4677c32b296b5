"""Range images and point clouds in, RangeFitResult out (seed 002): fit_range, fit_range_points.

A range fit reads surface patches off the points, recognises a signed primitive per patch
group, orders them in a precedence graph (subobjects, orders: odd = added, even = subtracted)
and refines the tree against the points and the viewing rays, as `csgfit range` does.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from typing import Callable, List, Optional, Sequence, Tuple, Union

from . import _csgfit
from .options import CancelToken, FitProgress, InputError, number, search_arguments
from .results import FitStats, Result
from .tree import Primitive3D, tree_from_json3d

#: What fit_range / fit_points use by default (the CLI's default).
DEFAULT_PRIMITIVES_RANGE = ("box", "sphere", "cylinder", "cone", "torus")
#: Unorganised point files fit_points reads (fit_range reads them too, and range images).
POINT_FILE_TYPES = (".xyz", ".ply")

PathLike = Union[str, bytes, os.PathLike]


@dataclass
class GraphNode:
    """A primitive of the precedence graph: kind ("box", "cylinder"...), sign ("positive" or
    "negative"), order (1-based rank in its subobject; odd = positive), subobject (0-based),
    the primitive in model units, its dims (box lengths; cylinder r, r, altitude), the
    indices of the surface patches it explains, and whether it is a conjectured cut (a
    halfspace through a seen face that the search added, not a surface seen as concave)."""

    kind: str
    sign: str
    order: int
    subobject: int
    primitive: Primitive3D
    dims: Tuple[float, ...]
    patches: Tuple[int, ...]
    conjectured: bool = False

    @property
    def positive(self) -> bool:
        return self.sign == "positive"


@dataclass
class GraphArc:
    """`from_` comes before `to` (node indices); kind "subtracting" (the negative `to` is cut
    from the positive `from_`) or "appending" (the positive `to` is added after `from_`)."""

    from_: int
    to: int
    kind: str


@dataclass
class PrecedenceGraph:
    """Seed 002's precedence graph: nodes, arcs, and the number of subobjects."""

    nodes: List[GraphNode]
    arcs: List[GraphArc]
    subobjects: int

    def subobject_nodes(self, subobject: int) -> List[int]:
        """The node indices of one subobject, in order (the order the tree applies them)."""
        members = [i for i, n in enumerate(self.nodes) if n.subobject == subobject]
        return sorted(members, key=lambda i: self.nodes[i].order)

    @classmethod
    def _from_dict(cls, d: dict) -> "PrecedenceGraph":
        nodes = [GraphNode(kind=n["kind"], sign=n["sign"], order=int(n["order"]),
                           subobject=int(n["subobject"]),
                           primitive=Primitive3D.from_dict(n["primitive"]),
                           dims=tuple(n.get("dims") or ()), patches=tuple(n.get("patches") or ()),
                           conjectured=bool(n.get("conjectured", False)))
                 for n in d.get("nodes") or []]
        arcs = [GraphArc(from_=int(a["from"]), to=int(a["to"]), kind=a["kind"])
                for a in d.get("arcs") or []]
        return cls(nodes, arcs, int(d.get("subobjects") or 0))


@dataclass
class ViewAgreement:
    """How the tree agrees with one view, re-seen through that view's camera: silhouette IoU,
    and the mean |depth - tree depth| over pixels both see (model units)."""

    source: str
    silhouette_iou: float
    depth_error: float


@dataclass
class SurfacePatch:
    """A detected surface: kind ("plane", "cylinder"...), its point count, whether it bulges
    towards the sensor (convex), and the rms distance of its points to the surface."""

    kind: str
    points: int
    convex: bool
    rms: float


class CloudResult(Result):
    """What the fits to points share (RangeFitResult, PointsFitResult): the input files, the
    points' bounding-box diagonal, and save() by the file's extension."""

    SCAD_FN = 96

    sources = property(lambda self: list(self._native.sources), doc="The input files.")
    diagonal = property(lambda self: self._native.diagonal, doc="Points' bounding-box diagonal.")

    def save(self, path: PathLike) -> str:
        """Writes the result by the file's extension: .scad, .json, .step / .stp, or .FCStd
        (the parametric FreeCAD tree, built by freecadcmd as the CLI does)."""
        path = os.fsdecode(path)
        ext = os.path.splitext(path)[1].lower()
        if ext in (".scad", ".json"):
            _write_text(path, self.to_scad() if ext == ".scad" else self.to_json())
        elif ext in (".step", ".stp"):
            self._native.save_step(path)
        elif ext == ".fcstd":
            _write_fcstd(self.to_json(), path)
        else:
            raise InputError(f"cannot write '{path}': expected .scad, .json, .step or .FCStd")
        return path


class RangeFitResult(CloudResult):
    """The outcome of fit_range (and fit_points with search="range").

    tree: Node / Primitive3D objects in model units. stats: FitStats (iou = mean silhouette IoU
        of the views with a camera; excess / uncovered unused). document: the JSON document as
        `csgfit range -o x.json` writes it (a dict). precedence_graph: PrecedenceGraph.
    views: ViewAgreement per view with a camera. patches: SurfacePatch list (the segmentation).
    patch_of_point: int array, per merged point (views in order), its patch index or -1.
    sources: the input files. diagonal: of the points' bounding box.
    """

    def __init__(self, native):
        document = json.loads(native.to_json())
        super().__init__(native, tree_from_json3d(document["tree"]),
                         FitStats._from_dict(document.get("stats") or {}))
        self.document = document
        self.precedence_graph = PrecedenceGraph._from_dict(document.get("precedence_graph") or {})
        self.views = [ViewAgreement(v["source"], float(v["silhouette_iou"] or 0.0),
                                    float(v["depth_error"] or 0.0))
                      for v in document.get("views") or []]
        self.patches = [SurfacePatch(p["kind"], int(p["points"]), bool(p["convex"]),
                                     float(p["rms"] or 0.0))
                        for p in document.get("patches") or []]

    patch_of_point = property(lambda self: self._native.patch_of_point,
                              doc="Patch index per merged point (-1 = none).")
    has_preview = property(lambda self: self._native.has_preview,
                           doc="Whether save_preview can draw (the first input has a camera).")

    def report(self) -> str:
        """Seed 002's Fig. 10 listing: subobjects, orders, each primitive with its axes,
        sizes and sign (what `csgfit range --report` prints)."""
        return self._native.report()

    def save_preview(self, path: PathLike) -> str:
        """Writes the first view segmented by patch beside the tree's depth error (PNG, as
        `csgfit range --preview` does); InputError when the first input has no camera."""
        path = os.fsdecode(path)
        self._native.save_preview(path)
        return path

    def __repr__(self) -> str:
        return (f"RangeFitResult(primitives={self.stats.primitives}, "
                f"subobjects={self.precedence_graph.subobjects}, patches={len(self.patches)}, "
                f"iou={self.stats.iou:.4f}, seconds={self.stats.seconds:.2f})")


def _write_text(path: str, text: str) -> None:
    tmp = path + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        raise InputError(f"cannot write '{path}': {e.strerror}") from None


def _write_fcstd(json_text: str, path: str) -> None:
    """Runs the CLI's FreeCAD writer on the JSON (freecadcmd takes its arguments from the
    environment); its one-line reason becomes the InputError's."""
    exe = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    if exe is None:
        raise InputError(f"cannot write '{path}': freecadcmd is not installed")
    writer = os.environ.get("CSGFIT_FCSTD_WRITER") or _csgfit.FCSTD_WRITER
    with tempfile.TemporaryDirectory(prefix="csgfit-") as tmp:
        json_path = os.path.join(tmp, "result.json")
        with open(json_path, "w", encoding="utf-8") as f:
            f.write(json_text)
        env = dict(os.environ, CSGFIT_JSON=json_path, CSGFIT_FCSTD=os.path.abspath(path))
        run = subprocess.run([exe, writer], env=env, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True)
    reasons = [ln[len("csgfit: error:"):].strip() for ln in run.stderr.splitlines()
               if ln.startswith("csgfit: error:")]
    if run.returncode != 0 or not os.path.isfile(path):
        raise InputError(f"cannot write '{path}': " + (reasons[-1] if reasons else "FreeCAD failed"))


def _search(primitives, time, threads, seed, progress, cancel) -> dict:
    args = search_arguments(k=None, primitives=primitives, time=time, threads=threads, seed=seed,
                            progress=progress,
                            cancel=cancel, default_primitives=",".join(DEFAULT_PRIMITIVES_RANGE))
    del args["k"]  # the range fit weighs primitives by the evidence, not by a k
    return args


def _paths(inputs) -> List[str]:
    if isinstance(inputs, (str, bytes, os.PathLike)):
        inputs = [inputs]
    try:
        paths = [os.fsdecode(p) for p in inputs]
    except TypeError:
        raise InputError("inputs must be a path or a list of paths") from None
    if not paths:
        raise InputError("no input given")
    return paths


Progress = Optional[Callable[[FitProgress], Optional[bool]]]


def fit_range(inputs: Union[PathLike, Sequence[PathLike]], *, time: float = 20.0,
              seed: int = 1, threads: int = 0,
              primitives: Union[None, str, Sequence[str]] = None,
              fx: Optional[float] = None, fy: Optional[float] = None,
              cx: Optional[float] = None, cy: Optional[float] = None,
              pixel_size: Optional[float] = None, depth_unit: Optional[float] = None,
              progress: Progress = None, cancel: Optional[CancelToken] = None) -> RangeFitResult:
    """Fits a CSG tree to range images or point clouds of one part, as `csgfit range` does.

    inputs: a path, or a list of paths (several views of one part, put in one frame by their
        sidecars and merged): 16-bit PNG or float .npy depth with a .json sidecar of the same
        name, organised clouds (.npy H x W x 3, PLY with width/height), points (.xyz, .ply).
    fx, fy, cx, cy, pixel_size, depth_unit: intrinsics that replace the sidecar's fields, or
        stand in for a missing sidecar (pixel_size: orthographic; fx and fy: pinhole; cx, cy
        default to the image centre, depth_unit to 1).
    time: wall-time budget in seconds. seed: RANSAC and refinement draws (same seed, same
        tree). threads: 0 = all cores. primitives: list or comma-separated names (default
        DEFAULT_PRIMITIVES_RANGE). progress / cancel: as for fit_mesh.

    The GIL is released while reading and fitting. Raises InputError (one line) for bad
    input: a missing file, a PNG without sidecar or intrinsics, bad intrinsics, no returns,
    too few points, views that do not overlap.
    """
    paths = _paths(inputs)
    intrinsics = {name: number(name, v, rule, optional=True) for name, v, rule in
                  (("fx", fx, "focal_length"), ("fy", fy, "focal_length"),
                   ("cx", cx, "principal_point"), ("cy", cy, "principal_point"),
                   ("pixel_size", pixel_size, "scale"), ("depth_unit", depth_unit, "scale"))}
    search = _search(primitives, time, threads, seed, progress, cancel)
    return RangeFitResult(_csgfit.fit_range_files(paths, **intrinsics, **search))


def fit_range_points(points, normals=None, *, time: float = 20.0, seed: int = 1,
                     threads: int = 0, primitives: Union[None, str, Sequence[str]] = None,
                     progress: Progress = None,
                     cancel: Optional[CancelToken] = None) -> RangeFitResult:
    """Seed 002's fit of unorganised points of one part (the range pipeline without a camera):
    what fit_points(search="range") runs.

    points: an (n, 3) array in model units, or a path to a .xyz / .ply file.
    normals: (n, 3) outward normals, or None to estimate them (principal components of the
        nearest neighbours, oriented consistently and outwards); points whose normal cannot be
        had are dropped. Other arguments as for fit_range.
    """
    search = _search(primitives, time, threads, seed, progress, cancel)
    if isinstance(points, (str, bytes, os.PathLike)):
        return RangeFitResult(_csgfit.fit_range_files([point_file(points, normals)], **search))
    return RangeFitResult(_csgfit.fit_point_arrays(*point_arrays(points, normals), **search))


def point_file(points: PathLike, normals) -> str:
    """The path of a point file given as `points`, or one InputError line."""
    path = os.fsdecode(points)
    if os.path.splitext(path)[1].lower() not in POINT_FILE_TYPES:
        raise InputError(f"'{path}': fit_points reads .xyz or .ply (range images: fit_range)")
    if normals is not None:
        raise InputError("normals come from the file when points is a path")
    return path


def point_arrays(points, normals) -> Tuple:
    """points and normals (or None) as contiguous float64 arrays, within the memory budget."""
    import numpy as np

    arrays = []
    for name, a in (("points", points), ("normals", normals)):
        if a is None:
            arrays.append(None)
            continue
        try:
            a = np.asarray(a)
        except (TypeError, ValueError) as e:
            raise InputError(f"{name}: {str(e).splitlines()[0]}") from None
        _csgfit.check_allocation(float(a.size) * 8, f"{name} ({a.size} values)")
        try:
            arrays.append(np.ascontiguousarray(a, dtype=np.float64))
        except (TypeError, ValueError) as e:
            raise InputError(f"{name}: {str(e).splitlines()[0]}") from None
    return tuple(arrays)

"""Meshes and voxel grids in, FitResult3D out: fit_mesh, fit_voxels and their readers."""

from __future__ import annotations

import os
from typing import Callable, Optional, Sequence, Union

from . import _csgfit
from .options import (DEFAULT_PRIMITIVES_3D, CancelToken, FitProgress, InputError,
                      check_array_size, integer, number, search_arguments)
from .results import FitResult3D


def load_mesh(path: Union[str, os.PathLike]):
    """Reads an STL, OBJ, OFF or PLY mesh: (vertices float (n, 3), triangles int32 (m, 3)).
    Raises InputError for a missing, truncated, mislabelled or empty file."""
    return _csgfit.load_mesh(os.fspath(path))


def load_voxels(path: Union[str, os.PathLike]):
    """Reads a .npy or .binvox voxel grid: (bool array [i, j, k], origin (x, y, z), voxel_size)."""
    return _csgfit.load_voxels(os.fspath(path))


def voxelize(vertices, triangles, *, resolution: int = 0, voxel_size: float = 0.0):
    """Solid voxels of a mesh: (bool array [i, j, k], origin, voxel_size, warning).
    resolution: voxels along the longest side; voxel_size: explicit edge; both 0 = automatic
    (about 11 voxels across the mean wall thickness, 96..256 along the longest side, at most
    160^3 voxels)."""
    v, t = _mesh_arrays(vertices, triangles)
    grid = _grid(resolution, voxel_size)
    return _csgfit.voxelize(v, t, grid["resolution"], grid["voxel_size"])


def _grid(resolution, voxel_size) -> dict:
    return dict(resolution=integer("resolution", resolution, "resolution"),
                voxel_size=0.0 if voxel_size == 0 else number("voxel_size", voxel_size, "scale"))


def _mesh_arrays(vertices, triangles):
    """Float vertices and int64 triangles, contiguous; float indices must be whole numbers
    (a cast would truncate 2.7 to vertex 2 without a word)."""
    import numpy as np

    try:
        v = np.asarray(vertices)
        t = np.asarray(triangles)
    except (TypeError, ValueError) as e:
        raise InputError(f"mesh arrays: {str(e).splitlines()[0]}") from None
    check_array_size(v, f"vertices ({v.size} values)")
    check_array_size(t, f"triangles ({t.size} values)")
    if t.dtype.kind == "f":
        if t.size and not (np.isfinite(t).all() and (t == np.floor(t)).all()):
            raise InputError("triangles must be integer vertex indices (got fractional or "
                             "non-finite values)")
    elif t.dtype.kind not in "iu" and t.size:
        raise InputError(f"triangles must be integer vertex indices, not {t.dtype}")
    try:
        return (np.ascontiguousarray(v, dtype=np.float64),
                np.ascontiguousarray(t, dtype=np.int64))
    except (TypeError, ValueError) as e:
        raise InputError(f"mesh arrays: {str(e).splitlines()[0]}") from None


def _search(k, primitives, time, threads, seed, progress, cancel) -> dict:
    return search_arguments(k=k, primitives=primitives, time=time, threads=threads, seed=seed,
                            progress=progress, cancel=cancel,
                            default_primitives=",".join(DEFAULT_PRIMITIVES_3D))


def fit_mesh(mesh, *, resolution: int = 0, voxel_size: float = 0.0, time: float = 30.0,
             threads: int = 0, seed: int = 1, k: Optional[float] = None,
             primitives: Union[None, str, Sequence[str]] = None,
             progress: Optional[Callable[[FitProgress], Optional[bool]]] = None,
             cancel: Optional[CancelToken] = None, construct: bool = True) -> FitResult3D:
    """Fits a 3D CSG tree to a mesh or a voxel file, as `csgfit mesh` does.

    mesh: a path (STL, OBJ, OFF, PLY; or .npy / .binvox voxel grids, fitted as they are) or a
        (vertices (n, 3), triangles (m, 3)) pair of arrays, in the mesh's own units.
    resolution: voxels along the longest side of the search grid; voxel_size: that grid's
        voxel edge instead; both 0 = automatic. Either way the part is fitted in its dominant
        frame (the directions of its largest planar faces) and polished against its surface.
    time: wall-time budget in seconds (the search stops earlier when it converges).
    threads: 0 = all cores. seed: same seed and threads, same tree (when it converges).
    k: size weight per primitive in voxels; None = 140 per million grid voxels.
    primitives: list or comma-separated names of PRIMITIVE_TYPES_3D, or "all"; boxes are
        required. Default: DEFAULT_PRIMITIVES_3D (every kind, the rounded box too).
    progress / cancel: as for fit_image (cancel stops the fit within a fraction of a second and
        returns the best tree so far, stats.stop_reason == "cancelled").
    construct: build the tree from the mesh's faces first (stats.stop_reason ==
        "constructed" when they explain the mesh); False searches from the voxels only, as
        `csgfit mesh --no-construct`.

    The GIL is released while reading, voxelising and solving. Raises InputError (a
    ValueError) for bad input: unreadable files, wrong array shapes, NaN, indices out of
    range, no solid, options.
    """
    import numpy as np

    search = _search(k, primitives, time, threads, seed, progress, cancel)
    grid = dict(_grid(resolution, voxel_size), construct=bool(construct))
    if isinstance(mesh, (str, bytes, os.PathLike)):
        path = os.fsdecode(mesh)
        return FitResult3D(_csgfit.fit_file(path, source=os.path.basename(path), **grid,
                                            **search))
    try:
        vertices, triangles = mesh
    except (TypeError, ValueError):
        raise InputError("mesh must be a path or a (vertices, triangles) pair") from None
    v, t = _mesh_arrays(vertices, triangles)
    return FitResult3D(_csgfit.fit_mesh_arrays(v, t, **grid, **search))


def fit_voxels(voxels, *, origin: Sequence[float] = (0.0, 0.0, 0.0), voxel_size: float = 1.0,
               time: float = 30.0, threads: int = 0, seed: int = 1, k: Optional[float] = None,
               primitives: Union[None, str, Sequence[str]] = None,
               progress: Optional[Callable[[FitProgress], Optional[bool]]] = None,
               cancel: Optional[CancelToken] = None, source: str = "") -> FitResult3D:
    """Fits a 3D CSG tree to a voxel array, on its own grid and axes.

    voxels: 3D array, [i, j, k] = voxel (x, y, z), nonzero / True = solid (the .npy
        convention). Voxel (i, j, k) is the cube from origin + (i, j, k) * voxel_size to
        origin + (i + 1, j + 1, k + 1) * voxel_size. Other arguments as for fit_mesh.
    """
    import numpy as np

    search = _search(k, primitives, time, threads, seed, progress, cancel)
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
    # The solid mask below is a byte per voxel, whatever the array's own strides.
    _csgfit.check_allocation(float(a.size), "a {} x {} x {} voxel array".format(*a.shape))
    try:
        origin = [float(x) for x in origin]
    except (TypeError, ValueError):
        raise InputError("origin must be three numbers") from None
    return FitResult3D(_csgfit.fit_voxels(np.ascontiguousarray(a != 0).view(np.uint8), origin,
                                          number("voxel_size", voxel_size, "scale"),
                                          source=str(source), **search))

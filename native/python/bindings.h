// The areas of the `_csgfit` module, one bind_ function each, as Open3D and OpenVDB split
// theirs: module.cpp only calls them, so an area can change without touching the others.
#pragma once

#include <pybind11/pybind11.h>

namespace csgfit_python {

/// csgfit.InputError and the translation of the solver's InputError into it.
void bind_errors(pybind11::module_& m);
/// CancelToken and FitProgress, shared by every fit.
void bind_progress(pybind11::module_& m);
/// The bitmap fit, its result and the 2D JSON reader.
void bind_2d(pybind11::module_& m);
/// The mesh and voxel fit (one entry: fit_input3d) and its result.
void bind_3d(pybind11::module_& m);
/// The range fit (range images, point files and arrays) and its result.
void bind_range(pybind11::module_& m);
/// The point-cloud fit (seed 004: point files and arrays) and its result.
void bind_points(pybind11::module_& m);
/// Seed 001's optimiser on OpenSCAD programs.
void bind_optimize(pybind11::module_& m);
/// Seed 000's morphing of two bitmaps (or two meshes / voxel files).
void bind_morph(pybind11::module_& m);
/// Readers of images, meshes and voxel grids, thresholding and voxelising.
void bind_io(pybind11::module_& m);

}  // namespace csgfit_python

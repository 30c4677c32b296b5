// Triangle mesh -> 3D CSG tree: the steps between a mesh file and fit_voxels that every front
// end (CLI, Python, FreeCAD) shares: the fitting frame, the voxel sizes, the coarse search and
// the fine polish, and the tree back in the mesh's own coordinates.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "csgfit/model/mesh.h"
#include "csgfit/model/quaternion.h"
#include "csgfit/pipeline/fit_voxels.h"

namespace csgfit {

/// How a mesh is turned into voxels for the fit.
struct MeshFitOptions {
  /// Voxels along the longest side of the search grid; 0 = auto (about half a million voxels
  /// over the part's box, never coarser than 64 along its longest side).
  int resolution = 0;
  /// Fit in the mesh's dominant frame (see dominant_frame) rather than its own axes.
  bool align = true;
  /// Re-optimise the searched tree's parameters on the finer grid of auto_voxel_size (about
  /// 11 voxels across the part's mean wall thickness) and refine them against surface samples
  /// in this share of the time budget (half of it when the grids are alike); 0 = neither.
  double polish_share = 0.25;
};

/// A mesh fit: the tree in the mesh's coordinates and how it was obtained.
struct MeshFitResult {
  FitResult3D fit;     ///< tree in mesh coordinates; stats measured on `grid`
  VoxelGrid grid;      ///< the finest grid the tree was scored on, in the fitting frame
  Quaternion frame;    ///< fitting frame -> mesh coordinates (identity when not aligned)
  MeshReport report;   ///< diagnostics of the input mesh
  double search_voxel_size = 0;
};

/// Fits a CSG tree to a closed (or nearly closed) mesh. Throws InputError when the mesh holds
/// no solid, std::invalid_argument for bad options; honours progress and cancel as fit_voxels.
MeshFitResult fit_mesh(const TriangleMesh& mesh, const FitOptions3D& options,
                       const MeshFitOptions& mesh_options = {},
                       const ProgressCallback& progress = nullptr,
                       const std::atomic<bool>* cancel = nullptr);
/// The same with the mesh's analyze_mesh() report already made (it walks every edge: a caller
/// that shows its warnings before the fit need not pay for it twice).
MeshFitResult fit_mesh(const TriangleMesh& mesh, const MeshReport& report,
                       const FitOptions3D& options, const MeshFitOptions& mesh_options = {},
                       const ProgressCallback& progress = nullptr,
                       const std::atomic<bool>* cancel = nullptr);

}  // namespace csgfit

// Triangle mesh -> 3D CSG tree: the steps between a mesh file and fit_voxels that every front
// end (CLI, Python, FreeCAD) shares: the fitting frame, the voxel sizes, the coarse search and
// the fine polish, and the tree back in the mesh's own coordinates.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "csgfit/fit3d.h"
#include "csgfit/local_opt3d.h"
#include "csgfit/mesh_io.h"

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

/// The rotation that takes the axes of the mesh's dominant orthogonal frame onto the model
/// axes' nearest signed permutation, i.e. frame -> mesh: the directions with the most planar
/// face area (area-weighted normals within 2 degrees of one another), the second orthogonal
/// to the first, the third their cross product. The identity when the mesh's own axes hold at
/// least 90 % as much aligned face area (an axis-aligned part stays as drawn) or when there is
/// no planar face to go by (spheres, tori).
Quaternion dominant_frame(const TriangleMesh& mesh);

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

/// `count` points spread over the mesh's surface in proportion to area (the same for the same
/// seed): the samples the final least-squares refinement fits to.
std::vector<Vec3> surface_samples(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed);

/// The mesh's planar faces perpendicular to a model axis (normals within half a degree of it):
/// faces whose offsets lie within `merge` of one another are one plane (at their area-weighted
/// mean), kept when it carries at least `min_area`. What snap_to_planes snaps faces to.
std::vector<AxisPlane> axis_planes(const TriangleMesh& mesh, double merge, double min_area);

/// Rotates every primitive of the tree by q about the origin (centres and orientations).
void rotate_tree(Node3D& tree, const Quaternion& q);

}  // namespace csgfit

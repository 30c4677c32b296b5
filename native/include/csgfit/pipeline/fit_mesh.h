// Mesh or voxel grid -> 3D CSG tree: the one place where the 3D stages are ordered, for every
// front end (CLI, Python, FreeCAD): the fitting frame, the voxel sizes, the coarse search, the
// polish against the surface, and the tree back in the mesh's own coordinates.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "csgfit/model/mesh.h"
#include "csgfit/model/quaternion.h"
#include "csgfit/pipeline/fit_voxels.h"

namespace csgfit {

/// The kinds a mesh or voxel fit uses unless told otherwise, for every front end: every
/// analytic kind, the rounded box too, since it is the outline designers draw most (a plate's
/// rounded rectangle, a slot).
inline constexpr const char* kDefaultMeshPrimitives = "box,sphere,cylinder,cone,ellipsoid,torus,prism,rounded_box";

/// How a mesh is turned into voxels for the fit.
struct MeshFitOptions {
  /// Voxels along the longest side of the search grid; 0 = auto (about half a million voxels
  /// over the part's box, never coarser than 64 along its longest side).
  int resolution = 0;
  /// > 0: the search grid's voxel edge in model units (instead of the resolution). With either
  /// the search grid is the only grid: the refinement against the surface runs on it.
  double voxel_size = 0;
  /// Fit in the mesh's dominant frame (see dominant_frame) rather than its own axes.
  bool align = true;
  /// Re-optimise the searched tree's parameters on the finer grid of auto_voxel_size (about
  /// 11 voxels across the part's mean wall thickness) and refine them against surface samples
  /// in this share of the time budget (half of it when the grids are alike); 0 = neither.
  double polish_share = 0.25;
  /// Read the mesh's surface as primitives (planes, spheres, cylinders, cones, tori; seed 002's
  /// recognition) and give them to the search as a first tree and proposals (issue 11).
  bool surface_seeds = true;
  /// Build the tree from the mesh's own faces first (issue 42, construct/boundary_csg.h): when
  /// it explains the mesh there is no search; otherwise it is the search's first tree.
  bool construct = true;
};

/// A 3D fit: the tree in the input's coordinates and how it was obtained.
struct MeshFitResult {
  FitResult3D fit;     ///< tree in mesh coordinates; stats measured on `grid`
  VoxelGrid grid;      ///< the finest grid the tree was scored on, in the fitting frame
  Quaternion frame;    ///< fitting frame -> mesh coordinates (identity when not aligned)
  MeshReport report;   ///< diagnostics of the input mesh (empty for a voxel grid)
  double search_voxel_size = 0;
};

/// What the 3D commands take: a triangle mesh (with its diagnosis) or a voxel grid.
struct Input3D {
  /// A mesh, analysed once (analyze_mesh walks every edge).
  static Input3D from_mesh(TriangleMesh mesh);
  static Input3D from_voxels(VoxelGrid voxels);

  bool is_mesh() const { return mesh_input; }
  /// One sentence for the user when the mesh is far from a closed solid; empty otherwise.
  std::string warning() const;

  bool mesh_input = true;
  TriangleMesh mesh;
  MeshReport report;
  VoxelGrid voxels;
};

/// Fits a CSG tree to a mesh as fit_mesh does, or to a voxel grid as it is (fit_voxels on its
/// own grid and axes: there is no surface to align to or refine against). Throws InputError
/// when the input holds no solid, std::invalid_argument for bad options.
MeshFitResult fit_input3d(const Input3D& input, const FitOptions3D& options,
                          const MeshFitOptions& mesh_options = {},
                          const ProgressCallback& progress = nullptr,
                          const std::atomic<bool>* cancel = nullptr);

/// The input as voxels in its own axes on the grid size the fit ended on: what a front end
/// shows beside the tree (the fit's own grid when it was not turned, the voxel input itself).
VoxelGrid input_voxels(const Input3D& input, const MeshFitResult& fit);

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

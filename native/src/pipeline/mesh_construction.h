// Internal to pipeline/: the mesh fit's first stage (issue 42): the tree built from the mesh's
// own surfaces, measured on the grid the fit reports on. When it explains the mesh the fit is
// done; when it does not, it is the search's first tree.
#pragma once

#include <chrono>

#include "csgfit/construct/boundary_csg.h"
#include "csgfit/pipeline/fit_voxels.h"

namespace csgfit {

/// Where the polish's second lattice of voxel centres lies, in voxels along every axis: the
/// reasons are at fit_mesh.cpp's polish_grids; the construction is measured on the same two.
constexpr double kStaggeredShift = 0.6;

struct ConstructedFit {
  bool built = false;     ///< whether the construction gave a tree (else `fit` is to be ignored)
  FitResult3D fit;        ///< the tree (in the fitting frame) and its statistics on `grid`
  VoxelGrid grid;         ///< the part's voxels on a box holding the mesh and the tree
  bool explains = false;  ///< within kExplainedShare of the mesh: no search needed
  Construction construction;
};

/// Builds the tree of `local` (the mesh in the fitting frame) and measures it on the part's
/// voxels of `voxel_size` (with `margin` voxels about a box that holds the mesh and the tree) and
/// on their staggered lattice, with the search's k for that grid doubled, as the polish counts.
ConstructedFit construct_mesh_fit(const TriangleMesh& local, double voxel_size, int margin,
                                  const FitOptions3D& options, std::chrono::steady_clock::time_point deadline);

}  // namespace csgfit

// Internal to pipeline/: the mesh fit's first stage (issue 42): the tree built from the mesh's
// own surfaces, measured on the grid the fit reports on. When it explains the mesh the fit is
// done; when it does not, it is the search's first tree.
#pragma once

#include <chrono>

#include "csgfit/construct/boundary_csg.h"
#include "csgfit/pipeline/fit_voxels.h"

namespace csgfit {

struct ConstructedFit {
  bool built = false;     ///< whether the construction gave a tree (else `fit` is to be ignored)
  FitResult3D fit;        ///< the tree (in the fitting frame) and its statistics on `grid`
  bool explains = false;  ///< within kExplainedShare of the mesh: no search needed
  Construction construction;
};

/// Builds the tree of `local` (the mesh in the fitting frame) and measures it on `grid` and
/// `staggered` (the polish's two lattices) with the search's k for `grid` doubled, as the polish
/// counts.
ConstructedFit construct_mesh_fit(const TriangleMesh& local, const VoxelGrid& grid, const VoxelGrid& staggered,
                                  const FitOptions3D& options, std::chrono::steady_clock::time_point deadline);

}  // namespace csgfit

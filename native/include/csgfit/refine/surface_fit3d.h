// Least-squares refinement of a 3D tree's primitives against points of the input's surface.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/refine/boundary_fit.h"

namespace csgfit {

/// Settings of refine_to_surface.
struct SurfaceFitOptions3D : BoundaryFitOptions {
  /// Refined primitives are kept while the voxel mismatch stays within this many voxels of
  /// what it was before the refinement (one allowance for all of them).
  double voxel_slack = 0;
};

/// Least-squares fit of every leaf to the input's surface samples (points on the mesh, in the
/// evaluator's grid coordinates), so that accuracy is not limited by the voxel size: each
/// sample within `inlier` voxels of the tree's surface goes to the primitive that makes the
/// surface there (TreeEvaluator3D::surface_leaf), and each primitive's parameters (centre,
/// free dimensions, turns, apex) take Levenberg-Marquardt steps on the sum of its samples'
/// squared signed distances. A refined primitive replaces the old one only if the voxel
/// mismatch stays within `voxel_slack` of the best seen. Returns the number of primitives
/// changed.
std::size_t refine_to_surface(TreeEvaluator3D& evaluator, const std::vector<Vec3>& samples,
                              const SurfaceFitOptions3D& options = {});

}  // namespace csgfit

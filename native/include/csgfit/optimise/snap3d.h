// Design values for 3D trees: axis-aligned placements, equal radii, shared axes, and faces on
// the input's own planes, where they cost (almost) no voxels.
#pragma once

#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator3d.h"
#include "csgfit/features/mesh_features.h"

namespace csgfit {

/// Snaps to what designers use where it costs at most `voxel_slack` mismatched voxels in all: a
/// primitive within 4 degrees of the grid's axes becomes axis-aligned (for cylinders, cones and
/// tori only their axis counts), radii of cylinders and spheres within 2 % of one another
/// become equal, and a cylinder, cone or torus whose axis is parallel to an earlier one's and
/// within half a voxel of it becomes coaxial with it. Returns the number of snaps kept.
std::size_t snap_to_design_values(TreeEvaluator3D& evaluator, double voxel_slack);

/// Moves every axis-aligned planar face of a leaf (the six faces of a box, the end faces of a
/// cylinder, cone or prism; aligned within half a degree) onto the nearest of `planes` on its axis when that is within
/// `tolerance` (model units), while the voxel mismatch stays within `voxel_slack` of where it
/// started (one allowance for all). The voxels only know a face to within half a voxel and the
/// surface fit leaves faces a hair apart where several primitives share one; on the input's
/// own plane a face is exact and neighbouring faces become coplanar. Returns faces moved.
std::size_t snap_to_planes(TreeEvaluator3D& evaluator, const std::vector<AxisPlane>& planes,
                           double tolerance, double voxel_slack);

}  // namespace csgfit

// The seed-000 local optimiser and pruning for 3D trees (the 3D twin of local_opt.h).
#pragma once

#include <atomic>
#include <chrono>

#include <cstddef>
#include <vector>

#include "csgfit/evaluator3d.h"

namespace csgfit {

struct LocalOptOptions3D {
  int max_sweeps = 60;         ///< passes over the primitives
  double initial_step = 2.0;   ///< first step in voxels (rotations: the step that moves the
                               ///< primitive's far end this far)
  double min_step = 0.125;     ///< a primitive is settled when its step falls below this
  bool move_rotation = true;   ///< false: orientation (and a prism's apex) stay as they are
  bool move_sizes = true;      ///< false: only positions move
  /// The optimiser stops at the next primitive once this time has passed (budgeted searches).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  /// Checked with the deadline: when set and true the optimiser stops the same way (a
  /// cancelled fit must not wait for a long polish).
  const std::atomic<bool>* cancel = nullptr;
};

/// Pattern search on the parameters of the given leaves (all leaves when `leaf_indices` is
/// empty): the centre along x, y, z, each free dimension, small turns about the primitive's
/// own axes (two for axially symmetric kinds, none for spheres) and a prism's apex. A move of
/// +-step is kept only if the exact voxel mismatch drops (and is then repeated with a doubled
/// step); a primitive whose sweep found nothing halves its step. Returns accepted moves.
std::size_t optimize_leaves(TreeEvaluator3D& evaluator, const LocalOptOptions3D& options,
                            std::vector<std::size_t> leaf_indices = {});

/// Settings of refine_to_surface.
struct SurfaceFitOptions3D {
  int rounds = 3;              ///< sample re-assignments
  int iterations = 8;          ///< Levenberg-Marquardt steps per primitive and round
  double inlier = 1.5;         ///< samples further than this (voxels) from every primitive are ignored
  /// Refined primitives are kept while the voxel mismatch stays within this many voxels of
  /// what it was before the refinement (one allowance for all of them).
  double voxel_slack = 0;
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

/// Least-squares fit of every leaf to the input's surface samples (points on the mesh, in the
/// evaluator's grid coordinates), so that accuracy is not limited by the voxel size: each
/// sample goes to the primitive whose surface is nearest (within `inlier` voxels), and each
/// primitive's parameters (centre, free dimensions, turns, apex) take Levenberg-Marquardt steps
/// on the sum of its samples' squared signed distances. A refined primitive replaces the old
/// one only if the voxel mismatch stays within `voxel_slack` of what it was at the start. Returns the
/// number of primitives changed.
std::size_t refine_to_surface(TreeEvaluator3D& evaluator, const std::vector<Vec3>& samples,
                              const SurfaceFitOptions3D& options = {});

/// Snaps to what designers use where it costs at most `voxel_slack` mismatched voxels in all: a
/// primitive within 4 degrees of the grid's axes becomes axis-aligned (for cylinders, cones and
/// tori only their axis counts), radii of cylinders and spheres within 2 % of one another
/// become equal, and a cylinder, cone or torus whose axis is parallel to an earlier one's and
/// within half a voxel of it becomes coaxial with it. Returns the number of snaps kept.
std::size_t snap_to_design_values(TreeEvaluator3D& evaluator, double voxel_slack);

/// A planar face of the input perpendicular to a grid axis: the plane axis = offset, and the
/// area of the input's surface on it.
struct AxisPlane {
  int axis = 0;
  double offset = 0;
  double area = 0;
};

/// Moves every axis-aligned planar face of a leaf (the six faces of a box, the end faces of a
/// cylinder, cone or prism) onto the nearest of `planes` on its axis when that is within
/// `tolerance` (model units), while the voxel mismatch stays within `voxel_slack` of where it
/// started (one allowance for all). The voxels only know a face to within half a voxel and the
/// surface fit leaves faces a hair apart where several primitives share one; on the input's
/// own plane a face is exact and neighbouring faces become coplanar. Returns faces moved.
std::size_t snap_to_planes(TreeEvaluator3D& evaluator, const std::vector<AxisPlane>& planes,
                           double tolerance, double voxel_slack);

/// Removes primitives whose removal costs fewer than k mismatched voxels, one at a time, best
/// first, then simplifies the tree. Returns the number removed.
std::size_t prune(Node3D& tree, const VoxelGrid& target, double k);

}  // namespace csgfit

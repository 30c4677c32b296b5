// The seed-000 local optimiser and pruning for 3D trees (the 3D twin of local_opt.h).
#pragma once

#include <atomic>
#include <chrono>

#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator3d.h"

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

}  // namespace csgfit

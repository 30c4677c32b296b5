// The local optimiser of seed 000 (Figures 3 and 4), for 2D and 3D trees: adjusts each
// primitive's position, each of its dimensions and its orientation while the mismatch with the
// target improves.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/eval/evaluator3d.h"

namespace csgfit {

/// Settings of optimize_leaves. Steps are in pixels (2D) or voxels (3D); a turn's step is the
/// distance it moves the primitive's far end.
struct LocalOptOptions {
  int max_sweeps = 80;          ///< M of Table 2: passes over the primitives
  double initial_step = 2.0;    ///< first step
  double min_step = 0.125;      ///< a primitive is settled when its step falls below this
  bool move_orientation = true; ///< false: orientation (and a triangle's apex) stay as they are
  bool move_sizes = true;       ///< false: only positions move
  /// The optimiser stops at the next primitive once this time has passed (budgeted searches).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  /// Checked with the deadline: when set and true the optimiser stops the same way (a
  /// cancelled fit must not wait for a long polish).
  const std::atomic<bool>* cancel = nullptr;

  /// At most `sweeps` passes, from steps of `initial` down to `min`; the rest as defaulted.
  static LocalOptOptions pattern(int sweeps, double initial, double min) {
    LocalOptOptions o;
    o.max_sweeps = sweeps;
    o.initial_step = initial;
    o.min_step = min;
    return o;
  }
};

/// Pattern search on the parameters of the given leaves (all leaves when `leaf_indices` is
/// empty): each parameter is moved by +-step, a move is kept only if the exact mismatch drops
/// (and is then repeated with a doubled step), and a primitive whose sweep found nothing halves
/// its step. 2D moves the centre, width, height, angle and a triangle's apex; 3D the centre
/// along x, y, z, each free dimension, small turns about the primitive's own axes (two for
/// axially symmetric primitives, three for a polygonal cylinder or cone, none for spheres) and
/// a prism's apex. Returns accepted moves.
std::size_t optimize_leaves(TreeEvaluator& evaluator, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices = {});
std::size_t optimize_leaves(TreeEvaluator3D& evaluator, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices = {});

}  // namespace csgfit

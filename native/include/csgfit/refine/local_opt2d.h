// The local optimiser of seed 000 (Figures 3 and 4): adjusts each primitive's position, each of
// its dimensions and its orientation while the mismatch with the target improves.
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "csgfit/eval/evaluator2d.h"

namespace csgfit {

struct LocalOptOptions {
  int max_sweeps = 80;        ///< M of Table 2: passes over the primitives
  double initial_step = 2.0;  ///< first step, pixels (angles: the step that moves a tip this far)
  double min_step = 0.125;    ///< a primitive is settled when its step falls below this
  bool move_angles = true;    ///< false: orientation and triangle apex stay as they are
  bool move_sizes = true;     ///< false: only positions move
  /// The optimiser stops at the next primitive once this time has passed (budgeted searches).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

/// Pattern search on the parameters of the given leaves (all leaves when `leaf_indices` is
/// empty): each parameter is moved by +-step, a move is kept only if the exact mismatch drops
/// (and is then repeated with a doubled step), and a primitive whose sweep found nothing halves
/// its step. Returns the number of accepted moves.
std::size_t optimize_leaves(TreeEvaluator& evaluator, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices = {});

}  // namespace csgfit

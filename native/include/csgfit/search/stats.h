// What a search reports: progress while it runs, statistics of a result.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "csgfit/eval/mismatch.h"

namespace csgfit {

/// Progress reported during a fit; the callback returns false to cancel.
struct FitProgress {
  double fraction = 0;          ///< 0..1 of the time budget or convergence, whichever is ahead
  double best_score = 0;
  std::size_t best_primitives = 0;
  std::size_t evaluations = 0;
  double seconds = 0;
};
using ProgressCallback = std::function<bool(const FitProgress&)>;

/// How good a tree is and what the search did to find it.
struct FitStats {
  double k = 0;
  double score = 0;
  std::size_t excess = 0, uncovered = 0;
  std::size_t primitives = 0;
  double iou = 0;
  std::size_t evaluations = 0;   ///< tree evaluations (full or incremental)
  std::size_t trees = 0;         ///< trees searched (perturbations evaluated)
  double seconds = 0;
  std::string stop_reason;       ///< "converged", "time", "max-trees", "cancelled"
};

/// Fills the mismatch fields of `stats` (excess including the tree beyond the grid, uncovered,
/// primitives, k, score, IoU over a target of `target_voxels`) from one measurement.
void set_mismatch_stats(FitStats& stats, const Mismatch& mismatch, std::size_t target_voxels,
                        std::size_t primitives, double k);

}  // namespace csgfit

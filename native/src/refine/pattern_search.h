// Internal to refine/: seed 000's pattern search, written once over any evaluator of leaf
// changes (the pixel and voxel evaluators, the range evidence) and any Moves policy (moves2d.h,
// moves3d.h). An Evaluator has leaf_count(), leaf(i), try_leaf(i, trial) -> Mismatch,
// mismatch() and update_leaf(i).
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/refine/local_opt.h"

namespace csgfit {

template <typename Evaluator, typename Moves>
std::size_t pattern_search(Evaluator& ev, const LocalOptOptions& options,
                           std::vector<std::size_t> leaf_indices, const Moves& moves) {
  if (leaf_indices.empty())
    for (std::size_t i = 0; i < ev.leaf_count(); ++i) leaf_indices.push_back(i);
  std::vector<double> steps(leaf_indices.size(), options.initial_step * moves.unit);
  const double min_step = options.min_step * moves.unit;
  std::size_t accepted = 0;
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    bool active = false;
    for (std::size_t li = 0; li < leaf_indices.size(); ++li) {
      double& step = steps[li];
      if (step < min_step) continue;
      if (std::chrono::steady_clock::now() >= options.deadline ||
          (options.cancel && options.cancel->load(std::memory_order_relaxed)))
        return accepted;
      active = true;
      const std::size_t leaf = leaf_indices[li];
      typename Moves::Param params[Moves::kMaxParams];
      const int np = moves.params_of(ev.leaf(leaf), options, params);
      bool improved = false;
      for (int pi = 0; pi < np; ++pi) {
        for (double dir : {1.0, -1.0}) {
          double delta = dir * step;
          bool moved = false;
          // Keep going while it pays, doubling the stride (Figure 4's "small steps towards").
          for (int rep = 0; rep < 6; ++rep) {
            auto trial = ev.leaf(leaf);
            moves.move(trial, params[pi], delta);
            const Mismatch m = ev.try_leaf(leaf, trial);
            if (m.total() >= ev.mismatch().total()) break;
            ev.leaf(leaf) = trial;
            ev.update_leaf(leaf);
            ++accepted;
            moved = improved = true;
            delta *= 2;
          }
          if (moved) break;  // no need to try the opposite direction
        }
      }
      if (!improved) step *= 0.5;
    }
    if (!active) break;
  }
  return accepted;
}

}  // namespace csgfit

// Seed 000's pattern search, written once; the primitives' parameters and moves are per
// dimension (moves2d.h, moves3d.h).
#include "csgfit/refine/local_opt.h"

#include <chrono>

#include "refine/moves2d.h"
#include "refine/moves3d.h"

namespace csgfit {

namespace {

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
      const int np = Moves::params_of(ev.leaf(leaf).kind, options, params);
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

}  // namespace

std::size_t optimize_leaves(TreeEvaluator& ev, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices) {
  return pattern_search(ev, options, std::move(leaf_indices), Moves2D{});
}

std::size_t optimize_leaves(TreeEvaluator3D& ev, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices) {
  return pattern_search(ev, options, std::move(leaf_indices), Moves3D{ev.target().voxel_size()});
}

}  // namespace csgfit

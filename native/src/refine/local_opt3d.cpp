#include "csgfit/refine/local_opt3d.h"

#include <algorithm>
#include <cmath>

#include "refine/moves3d.h"

namespace csgfit {

using moves3d::move;
using moves3d::Param;
using moves3d::params_of;

std::size_t optimize_leaves(TreeEvaluator3D& ev, const LocalOptOptions3D& options,
                            std::vector<std::size_t> leaf_indices) {
  if (leaf_indices.empty())
    for (std::size_t i = 0; i < ev.leaf_count(); ++i) leaf_indices.push_back(i);
  const double voxel = ev.target().voxel_size();
  std::vector<double> steps(leaf_indices.size(), options.initial_step * voxel);
  const double min_step = options.min_step * voxel;
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
      Param params[10];
      const int np = params_of(ev.leaf(leaf).kind, options, params);
      bool improved = false;
      for (int pi = 0; pi < np; ++pi) {
        for (double dir : {1.0, -1.0}) {
          double delta = dir * step;
          bool moved = false;
          // Keep going while it pays, doubling the stride (seed 000's "small steps towards").
          for (int rep = 0; rep < 6; ++rep) {
            Primitive3D trial = ev.leaf(leaf);
            move(trial, params[pi], delta, voxel);
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

// Seed 000's local optimiser over the voxel and pixel evaluators.
#include "csgfit/refine/local_opt.h"

#include "refine/moves2d.h"
#include "refine/moves3d.h"
#include "refine/pattern_search.h"

namespace csgfit {

std::size_t optimize_leaves(TreeEvaluator& ev, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices) {
  return pattern_search(ev, options, std::move(leaf_indices), Moves2D{});
}

std::size_t optimize_leaves(TreeEvaluator3D& ev, const LocalOptOptions& options,
                            std::vector<std::size_t> leaf_indices) {
  return pattern_search(ev, options, std::move(leaf_indices), Moves3D{ev.target().voxel_size()});
}

}  // namespace csgfit

// Internal: seed 001's optimiser as the last stage of a fit. The fits' own pruning already
// leaves little; this removes what the search's structure still repeats (an operand that an
// operation does not need, a cut that misses), and only when the result is smaller and draws
// exactly the same raster on the fit's own grid, so that the fit's statistics stay true.
#pragma once

#include "csgfit/error.h"
#include "csgfit/optimise/tree_expression.h"
#include "csgfit/search/stats.h"

namespace csgfit {

template <typename P, typename SameRaster>
void optimize_last(CsgNode<P>& tree, FitStats& stats, std::uint64_t seed, const SameRaster& same_raster) {
  opt::OptimizeOptions options;
  options.seed = seed;
  CsgNode<P> better;
  try {
    better = opt::optimize_csg_tree(tree, options);
  } catch (const InputError&) {  // a tree the optimiser cannot take (too many primitives)
    return;
  }
  if (better.primitive_count() >= tree.primitive_count() && better.node_count() >= tree.node_count()) return;
  if (!same_raster(tree, better)) return;
  tree = std::move(better);
  stats.primitives = tree.primitive_count();
}

}  // namespace csgfit

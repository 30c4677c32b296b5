// Seed 001's redundancy removal (Sec. 5.1) with the geometry: operands that are empty, that
// another operand already holds (identical-set, generalised to subsets), subtrahends that cut
// nothing; each decided by the sample set. Alternates with the structural rules until neither
// changes the tree.
#pragma once

#include "csgfit/optimise/expression.h"
#include "csgfit/optimise/sample_set.h"

namespace csgfit::opt {

struct RedundancyReport {
  std::size_t structural = 0;  ///< rewrites by the rules that need no geometry
  std::size_t sampled = 0;     ///< operands removed by an empty-set decision
};

/// Rewrites `e` in place; subtrees holding opaque leaves get the structural rules only, and an
/// opaque operand is never removed.
template <std::size_t D>
RedundancyReport remove_redundancy(Expr& e, const SampleSet<D>& samples);

/// The seed's proximity (Sec. 4): of all operand pairs of the tree's operations (an n-ary
/// operation folds left: ((a op b) op c) has two), the fraction whose point sets overlap.
/// 1 for a single halfspace; pairs with an opaque operand are not counted.
template <std::size_t D>
double proximity(const Expr& e, const SampleSet<D>& samples);

}  // namespace csgfit::opt

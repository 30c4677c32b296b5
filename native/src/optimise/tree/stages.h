// Internal: the stages of optimize_tree, each on an expression without opaque leaves.
#pragma once

#include <functional>

#include "csgfit/optimise/optimize_tree.h"
#include "csgfit/optimise/sample_set.h"

namespace csgfit::opt {

/// What the remaining-solid stage does to a solid no halfspace dominates.
template <std::size_t D>
using RemainingSolver = std::function<Expr(const Expr&, const SampleSet<D>&)>;

/// Sec. 5.2: the chain of dominant halfspaces, recursively, with the seed's proximity order;
/// the innermost remaining solid goes to `remaining`.
template <std::size_t D>
Expr decompose_dominant(Expr e, const SampleSet<D>& s, const RemainingSolver<D>& remaining,
                        OptimizeReport& report);

/// Sec. 5.3.1: the solid's samples as a truth table over its halfspaces, minimised two-level,
/// back as a union of products (factored by the structural rules). Returns the input when the
/// minimised form is not smaller.
template <std::size_t D>
Expr minimise_two_level(const Expr& solid, const SampleSet<D>& s, RemainingMethod method,
                        std::uint64_t seed);

/// Sec. 5.3.2: the GA over trees of the solid's halfspaces; returns the chosen tree and fills
/// the Pareto front of size against proximity.
template <std::size_t D>
Expr genetic_remaining(const Expr& solid, const SampleSet<D>& s, const OptimizeOptions& options,
                       std::vector<ParetoPoint>& front);

/// Whether the two expressions are the same solid: both differences empty (samples and the
/// dense check of SampleSet::is_empty).
template <std::size_t D>
bool same_solid(const Expr& a, const Expr& b, const SampleSet<D>& s) {
  return s.is_empty(Expr::make(ExprOp::Difference, {a, b})) && s.is_empty(Expr::make(ExprOp::Difference, {b, a}));
}

/// Orders operands so that each overlaps the ones before it where it can (the seed's spatial
/// sorting): the first stays, the others follow greedily.
template <std::size_t D>
void order_by_proximity(std::vector<Expr>& operands, const SampleSet<D>& s);

}  // namespace csgfit::opt

// Internal to search/: what the perturbations of both dimensions share: the draw of an
// operator by its odds, and the local optimisation a perturbed tree starts with.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/model/tree.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/search/params.h"
#include "model/random.h"

namespace csgfit::search_ops {

/// What one island's perturbations of either dimension hold: the shared problem, the island's
/// random numbers and its counters.
template <typename Problem>
class IslandOperators {
 public:
  IslandOperators(const Problem& problem, std::uint64_t seed) : pb_(problem), rng_(seed) {}

  std::size_t trees = 0;        ///< perturbations made
  std::size_t evaluations = 0;  ///< tree evaluations they cost

  rnd::Rng& rng() { return rng_; }

 protected:
  const Problem& pb_;
  rnd::Rng rng_;
};

/// Seed 000's perturbations (Table 1) and INT.
enum class Operator { Rep, Add, Cut, Mod, Intersect };

/// Draws an operator with the given odds (one uniform number).
inline Operator draw_operator(rnd::Rng& rng, const OperatorOdds& odds) {
  const double total = odds.rep + odds.add + odds.cut + odds.mod + odds.intersect;
  const double r = rnd::uniform(rng, 0, total);
  double edge = odds.add;
  if (r < edge) return Operator::Add;
  edge += odds.intersect;
  if (r < edge) return Operator::Intersect;
  edge += odds.cut;
  if (r < edge) return Operator::Cut;
  edge += odds.mod;
  if (r < edge) return Operator::Mod;
  return Operator::Rep;
}

/// CUT: removes a random subtree other than the root; false for a single leaf.
template <typename Tree>
bool cut(Tree& tree, rnd::Rng& rng) {
  const std::size_t n = tree.node_count();
  if (n <= 1) return false;
  return erase_subtree(tree, 1 + rnd::pick(rng, n - 1));
}

/// A primitive read off the input (its surface in 3D, its boundary in 2D) with its sign: what
/// ADD tries beside the residual's own pieces (issue 11: the designer's cylinder or hole, not
/// the pieces that fill its pixels).
template <typename Prim>
struct Proposal {
  Prim primitive;
  bool positive = true;
};

/// ADD with a proposal: one of `proposals`, unioned with the root or a random subtree when
/// positive, cut from it otherwise; false when there are none.
template <typename Prim>
bool add_proposal(CsgNode<Prim>& tree, const std::vector<Proposal<Prim>>& proposals,
                  rnd::Rng& rng, std::vector<Prim>& fresh) {
  if (proposals.empty()) return false;
  const Proposal<Prim>& p = proposals[rnd::pick(rng, proposals.size())];
  fresh.push_back(p.primitive);
  CsgNode<Prim>* at = (rng() % 2 == 0) ? &tree : node_at(tree, rnd::pick(rng, tree.node_count()));
  graft(*at, p.positive ? NodeKind::Union : NodeKind::Difference, CsgNode<Prim>::leaf(p.primitive));
  return true;
}

/// The local optimisation of a perturbed tree: the leaves that are new (equal to one of
/// `fresh`) with `new_leaf`, then every leaf with `all_leaves` when it is given.
template <typename Evaluator, typename Prim>
void optimise_perturbed(Evaluator& ev, const std::vector<Prim>& fresh, const LocalOptOptions& new_leaf,
                        const LocalOptOptions* all_leaves) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < ev.leaf_count() && !fresh.empty(); ++i)
    if (std::find(fresh.begin(), fresh.end(), ev.leaf(i)) != fresh.end()) idx.push_back(i);
  if (!idx.empty()) optimize_leaves(ev, new_leaf, idx);
  if (all_leaves) optimize_leaves(ev, *all_leaves);
}

}  // namespace csgfit::search_ops

// Internal to search/: seed 000's morphing search, written once over the dimension. A candidate
// is a pair of trees identical in structure, one per target; REP, ADD, CUT (and INT in 3D)
// act on both trees alike, MOD changes one leaf's kind in both trees (each in its own place),
// and each tree's leaves are optimised against its own target. The pair scores the mean of its
// two trees' scores. `Dim` (morph_dims.h) says how one dimension proposes primitives.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "csgfit/search/params.h"
#include "model/random.h"
#include "search/operators.h"

namespace csgfit::morph {

/// What a morph search shares between its islands: the two targets' problems.
template <typename Dim>
struct PairProblem {
  const typename Dim::Problem* a = nullptr;
  const typename Dim::Problem* b = nullptr;
  SearchParams params;
};

/// Two trees of one structure, each scored against its own target.
template <typename Dim>
struct PairCandidate {
  typename Dim::Single a, b;
  std::size_t primitives = 0;
  double score = std::numeric_limits<double>::infinity();
};

/// One island's perturbations of pairs: its own random numbers for the structure, and one
/// single-tree operator set per target for the primitives.
template <typename Dim>
class PairOperators {
 public:
  using Candidate = PairCandidate<Dim>;
  using Tree = typename Dim::Tree;
  using Prim = typename Dim::Prim;
  using Ops = typename Dim::Ops;

  PairOperators(const PairProblem<Dim>& problem, std::uint64_t seed)
      : pb_(problem),
        rng_(seed),
        a_(*problem.a, rnd::splitmix(seed ^ 0xa11ce)),
        b_(*problem.b, rnd::splitmix(seed ^ 0xb0b)) {}

  std::size_t trees = 0;        ///< perturbations made
  std::size_t evaluations = 0;  ///< tree evaluations of both targets

  rnd::Rng& rng() { return rng_; }

  /// The pair of two copies of `tree`, each tree's leaves equal to one of `fresh` optimised
  /// against its own target, then scored.
  Candidate copies(const Tree& tree, const std::vector<Prim>& fresh) {
    return pair(tree, tree, fresh, fresh);
  }

  /// Seed 000's random first pair: norm(a, s) primitives, the same in both trees.
  Candidate random_pair() {
    std::vector<Prim> fresh;
    const int count = rnd::norm_count(rng_, pb_.params.initial_size_mean, pb_.params.initial_size_sd);
    Tree t = Dim::random_subtree(a_, count, fresh);
    ++trees;
    return copies(t, fresh);
  }

  Candidate perturb(const Candidate& parent) {
    Tree ta = parent.a.tree, tb = parent.b.tree;
    std::vector<Prim> fa, fb;
    // The primitives of ADD, INT and REP come from one target's operators, drawn in turn.
    const bool from_a = rng_() & 1;
    Ops& x = from_a ? a_ : b_;
    const typename Dim::Single& px = from_a ? parent.a : parent.b;
    bool done = false;
    switch (search_ops::draw_operator(rng_, pb_.params.odds)) {
      case search_ops::Operator::Add: done = add(x, px, ta, tb, fa, fb); break;
      case search_ops::Operator::Intersect: done = intersect(x, ta, tb, fa, fb); break;
      case search_ops::Operator::Cut: done = cut(ta, tb); break;
      case search_ops::Operator::Mod: done = mod(ta, tb, fa, fb); break;
      case search_ops::Operator::Rep: break;
    }
    if (!done) rep(x, from_a, ta, tb, fa, fb);
    ++trees;
    return pair(std::move(ta), std::move(tb), fa, fb);
  }

  /// An accepted pair loses every leaf whose removal from both trees does not raise the
  /// pair's score (seed 000 prunes single trees; a pair must lose a leaf in both at once).
  void accept(Candidate& c) {
    for (std::size_t i = c.primitives; i-- > 0 && c.primitives > 1;) {
      Tree ta = c.a.tree, tb = c.b.tree;
      if (!erase_leaf(ta, leaves(ta)[i]) || !erase_leaf(tb, leaves(tb)[i])) continue;
      if (!simplify(ta) || !simplify(tb)) continue;
      Candidate smaller = scored(std::move(ta), std::move(tb));
      if (smaller.score <= c.score + 1e-9) c = std::move(smaller);
    }
  }

  /// Both trees scored as they are (no optimisation).
  Candidate scored(Tree ta, Tree tb) {
    Candidate c;
    c.a = Ops::scored(*pb_.a, std::move(ta), evaluations);
    c.b = Ops::scored(*pb_.b, std::move(tb), evaluations);
    return combine(std::move(c));
  }

 private:
  Candidate combine(Candidate c) {
    c.primitives = c.a.primitives;
    c.score = 0.5 * (c.a.score + c.b.score);
    return c;
  }

  Candidate pair(Tree ta, Tree tb, const std::vector<Prim>& fa, const std::vector<Prim>& fb) {
    Candidate c;
    const std::size_t before = a_.evaluations + b_.evaluations;
    c.a = Dim::evaluate(a_, std::move(ta), fa);
    c.b = Dim::evaluate(b_, std::move(tb), fb);
    evaluations += a_.evaluations + b_.evaluations - before;
    // simplify() acts on structure alone, so both trees stay alike; a tree that lost every
    // leaf scores infinity.
    return combine(std::move(c));
  }

  // A node index both trees share, the root half of the time (as the single-tree ADD).
  std::size_t graft_point(const Tree& t) {
    return (rng_() % 2 == 0) ? 0 : rnd::pick(rng_, t.node_count());
  }

  bool add(Ops& x, const typename Dim::Single& px, Tree& ta, Tree& tb, std::vector<Prim>& fa,
           std::vector<Prim>& fb) {
    const bool as_union = rng_() & 1;
    Tree added;
    std::vector<Prim> fresh;
    if (!Dim::added(x, px, as_union, added, fresh)) return false;
    const std::size_t at = graft_point(ta);
    const NodeKind kind = as_union ? NodeKind::Union : NodeKind::Difference;
    graft(*node_at(ta, at), kind, added);
    graft(*node_at(tb, at), kind, std::move(added));
    fa.insert(fa.end(), fresh.begin(), fresh.end());
    fb.insert(fb.end(), fresh.begin(), fresh.end());
    return true;
  }

  bool intersect(Ops& x, Tree& ta, Tree& tb, std::vector<Prim>& fa, std::vector<Prim>& fb) {
    Prim hull;
    if (!Dim::trimming(x, hull)) return false;
    const std::size_t at = (rng_() % 4 != 0) ? 0 : rnd::pick(rng_, ta.node_count());
    graft(*node_at(ta, at), NodeKind::Intersection, Tree::leaf(hull));
    graft(*node_at(tb, at), NodeKind::Intersection, Tree::leaf(hull));
    fa.push_back(hull);
    fb.push_back(hull);
    return true;
  }

  bool cut(Tree& ta, Tree& tb) {
    const std::size_t n = ta.node_count();
    if (n <= 1) return false;
    const std::size_t at = 1 + rnd::pick(rng_, n - 1);
    return erase_subtree(ta, at) && erase_subtree(tb, at);
  }

  // MOD: one leaf becomes another kind in both trees, each where it is.
  bool mod(Tree& ta, Tree& tb, std::vector<Prim>& fa, std::vector<Prim>& fb) {
    const auto& kinds = Dim::kinds(*pb_.a);
    if (kinds.size() < 2) return false;
    std::vector<Prim*> la = leaves(ta), lb = leaves(tb);
    const std::size_t i = rnd::pick(rng_, la.size());
    auto kind = kinds[rnd::pick(rng_, kinds.size())];
    while (kind == la[i]->kind) kind = kinds[rnd::pick(rng_, kinds.size())];
    *la[i] = Dim::rekinded(a_, *la[i], kind);
    *lb[i] = Dim::rekinded(b_, *lb[i], kind);
    fa.push_back(*la[i]);
    fb.push_back(*lb[i]);
    return true;
  }

  // REP: a new random subtree (2D) or a new leaf (3D) at one place, the same in both trees.
  void rep(Ops& x, bool from_a, Tree& ta, Tree& tb, std::vector<Prim>& fa, std::vector<Prim>& fb) {
    std::vector<Prim> fresh;
    Tree& tx = from_a ? ta : tb;
    Tree& ty = from_a ? tb : ta;
    const std::size_t at = Dim::rep_point(rng_, tx);
    Tree* nx = node_at(tx, at);
    Tree replacement = Dim::replacement(x, rng_, *nx, pb_.params, fresh);
    *node_at(ty, at) = replacement;
    *nx = std::move(replacement);
    fa.insert(fa.end(), fresh.begin(), fresh.end());
    fb.insert(fb.end(), fresh.begin(), fresh.end());
  }

  const PairProblem<Dim>& pb_;
  rnd::Rng rng_;
  Ops a_, b_;
};

}  // namespace csgfit::morph

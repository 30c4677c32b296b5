// Internal to search/: the 2D search's candidate trees and perturbations (seed 000's REP, ADD,
// CUT, MOD), for the island driver (islands.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "csgfit/eval/mismatch.h"
#include "csgfit/features/features2d.h"
#include "csgfit/model/bitmap.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/refine/local_opt.h"
#include "csgfit/search/params.h"
#include "search/operators.h"

namespace csgfit {

struct Candidate2D {
  Node tree;
  Mismatch mismatch;
  std::size_t primitives = 0;
  double score = 0;
};

/// Everything one 2D search shares between its islands (read-only while they run).
struct Problem2D {
  const Bitmap* target = nullptr;
  double k = 25;
  SearchParams params;
  std::vector<PrimitiveKind> kinds;
  std::vector<DistancePeak> shape_peaks;       // of the target: where ADD puts unions
  std::vector<DistancePeak> background_peaks;  // of the complement: where ADD puts cuts
  // Primitives read off the boundary, with their sign: what ADD tries beside the peaks.
  std::vector<search_ops::Proposal<Primitive>> proposals;
  LocalOptOptions new_leaf_opt, all_leaf_opt;
};

/// One island's perturbations and their random numbers.
class Operators2D : public search_ops::IslandOperators<Problem2D> {
 public:
  using Candidate = Candidate2D;
  using IslandOperators::IslandOperators;

  /// Scores a tree after optimising the leaves equal to one of `fresh`, then all leaves a
  /// little, and pruning it (unless `pruned` is false: a morph's trees keep their structure).
  Candidate evaluate(Node tree, const std::vector<Primitive>& fresh, bool pruned = true);
  /// `tree` scored as it is (no optimisation), its evaluations added to `evaluations`; a tree
  /// without leaves scores infinity.
  static Candidate scored(const Problem2D& pb, Node tree, std::size_t& evaluations);
  /// A child of `parent`: one perturbation drawn by the odds, then evaluate().
  Candidate perturb(const Candidate& parent);
  /// Nothing to do: evaluate() already pruned the child.
  void accept(Candidate&) {}
  /// Seed 000's random subtree of `count` primitives: uniform positions in the middle half,
  /// random operators.
  Node random_subtree(int count, std::vector<Primitive>& fresh);
  /// ADD's new subtree: a' primitives at peaks of the target's distance map (of its
  /// complement when it is to be cut), unioned; false when there is no such peak.
  bool added_subtree(bool as_union, Node& added, std::vector<Primitive>& fresh);
  /// MOD's new primitive: `p` as another kind in the same place.
  Primitive rekinded(Primitive p, PrimitiveKind kind);

 private:
  Primitive random_primitive(double cx, double cy, double size);
  // REP: the subtree at a random node (of the n the tree had) replaced by a random one.
  void rep(Node& tree, std::size_t n, std::vector<Primitive>& fresh);
  // ADD: a small subtree at maxima of a distance map, unioned with or cut from a subtree.
  bool add(Node& tree, std::vector<Primitive>& fresh);
  // MOD: one primitive becomes another kind in the same place.
  bool mod(Node& tree, std::vector<Primitive>& fresh);
};

}  // namespace csgfit

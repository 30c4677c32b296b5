// Seed 000's pruning, written once for 2D and 3D trees.
#include "csgfit/optimise/prune.h"

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/eval/evaluator3d.h"

namespace csgfit {

namespace {

template <typename Evaluator, typename Tree, typename Grid>
std::size_t prune_tree(Tree& tree, const Grid& target, double k) {
  std::size_t removed = 0;
  const std::size_t target_count = target.count();
  for (;;) {
    if (tree.primitive_count() <= 1) break;
    Evaluator ev(target, tree);
    const std::size_t base = ev.mismatch().total();
    std::size_t best_leaf = 0;
    double best_gain = 0;
    for (std::size_t i = 0; i < ev.leaf_count(); ++i) {
      const Mismatch m = ev.try_without_leaf(i);
      if (m.excess == 0 && m.uncovered == target_count) continue;  // would leave nothing
      // Removing a leaf saves k; it pays when the extra mismatch is below that.
      const double gain = k - (static_cast<double>(m.total()) - static_cast<double>(base));
      if (gain > best_gain) {
        best_gain = gain;
        best_leaf = i;
      }
    }
    if (best_gain <= 0) break;
    // Remove the leaf from its parent, then let simplify collapse what is left.
    erase_leaf(tree, leaves(tree)[best_leaf]);
    if (!simplify(tree)) break;  // cannot happen: more than one leaf was present
    ++removed;
  }
  return removed;
}

}  // namespace

std::size_t prune(Node& tree, const Bitmap& target, double k) {
  return prune_tree<TreeEvaluator>(tree, target, k);
}

std::size_t prune(Node3D& tree, const VoxelGrid& target, double k) {
  return prune_tree<TreeEvaluator3D>(tree, target, k);
}

std::size_t prune_refitted(Node& tree, const Bitmap& target, double k, const LocalOptOptions& refit,
                           std::size_t& evaluations, int rounds) {
  auto score = [&](const TreeEvaluator& ev, const Node& t) {
    return static_cast<double>(ev.mismatch().total()) + k * static_cast<double>(t.primitive_count());
  };
  std::size_t removed = 0;
  for (int round = 0; round < rounds && tree.primitive_count() > 1; ++round) {
    double best = score(TreeEvaluator(target, tree), tree);
    Node best_tree;
    bool found = false;
    for (std::size_t i = 0; i < tree.primitive_count(); ++i) {
      Node trial = tree;
      erase_leaf(trial, leaves(trial)[i]);
      if (!simplify(trial)) continue;
      TreeEvaluator ev(target, trial);
      optimize_leaves(ev, refit);
      evaluations += ev.evaluations();
      const double s = score(ev, trial);
      if (s < best) best = s, best_tree = std::move(trial), found = true;
    }
    if (!found) break;
    tree = std::move(best_tree);
    ++removed;
  }
  return removed;
}

}  // namespace csgfit

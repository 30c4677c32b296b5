#include "csgfit/optimise/prune.h"

#include <functional>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/eval/evaluator3d.h"

namespace csgfit {

std::size_t prune(Node& tree, const Bitmap& target, double k) {
  std::size_t removed = 0;
  for (;;) {
    if (tree.primitive_count() <= 1) break;
    TreeEvaluator ev(target, tree);
    const std::size_t base = ev.mismatch().total();
    const std::size_t target_count = target.count();
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
    std::vector<Primitive*> ls = leaves(tree);
    const Primitive* target_leaf = ls[best_leaf];
    std::function<bool(Node&)> erase = [&](Node& n) -> bool {
      for (std::size_t c = 0; c < n.children.size(); ++c) {
        Node& ch = n.children[c];
        if (ch.is_leaf() && &ch.primitive == target_leaf) {
          if (n.kind == NodeKind::Difference && c == 0) {
            n.children.clear();  // the difference loses its base: the whole node goes
          } else {
            n.children.erase(n.children.begin() + static_cast<std::ptrdiff_t>(c));
          }
          return true;
        }
        if (!ch.is_leaf() && erase(ch)) return true;
      }
      return false;
    };
    erase(tree);
    if (!simplify(tree)) break;  // cannot happen: more than one leaf was present
    ++removed;
  }
  return removed;
}

std::size_t prune(Node3D& tree, const VoxelGrid& target, double k) {
  std::size_t removed = 0;
  const std::size_t target_count = target.count();
  for (;;) {
    if (tree.primitive_count() <= 1) break;
    TreeEvaluator3D ev(target, tree);
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
    std::vector<Primitive3D*> ls = leaves(tree);
    const Primitive3D* victim = ls[best_leaf];
    std::function<bool(Node3D&)> erase = [&](Node3D& n) -> bool {
      for (std::size_t c = 0; c < n.children.size(); ++c) {
        Node3D& ch = n.children[c];
        if (ch.is_leaf() && &ch.primitive == victim) {
          if (n.kind == NodeKind::Difference && c == 0)
            n.children.clear();  // the difference loses its base: the whole node goes
          else
            n.children.erase(n.children.begin() + static_cast<std::ptrdiff_t>(c));
          return true;
        }
        if (!ch.is_leaf() && erase(ch)) return true;
      }
      return false;
    };
    erase(tree);
    if (!simplify(tree)) break;  // cannot happen: more than one leaf was present
    ++removed;
  }
  return removed;
}

}  // namespace csgfit

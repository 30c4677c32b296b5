// The incremental evaluator against the brute-force reference on random trees.
#include <gtest/gtest.h>

#include <random>

#include "csgfit/eval/evaluator2d.h"
#include "csgfit/model/tree2d.h"

using namespace csgfit;

namespace {

Primitive random_primitive(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(5, 59), dim(3, 30), ang(0, 360), apex(-1, 1);
  switch (rng() % 4) {
    case 0: return Primitive::rectangle(pos(rng), pos(rng), dim(rng), dim(rng), ang(rng));
    case 1: return Primitive::circle(pos(rng), pos(rng), dim(rng) / 2);
    case 2: return Primitive::ellipse(pos(rng), pos(rng), dim(rng) / 2, dim(rng) / 2, ang(rng));
    default: return Primitive::triangle(pos(rng), pos(rng), dim(rng), dim(rng), ang(rng), apex(rng));
  }
}

Node random_tree(std::mt19937_64& rng, int depth) {
  if (depth == 0 || rng() % 4 == 0) return Node::leaf(random_primitive(rng));
  static const NodeKind ops[3] = {NodeKind::Union, NodeKind::Difference, NodeKind::Intersection};
  std::vector<Node> children;
  const int n = 2 + static_cast<int>(rng() % 3);
  for (int i = 0; i < n; ++i) children.push_back(random_tree(rng, depth - 1));
  return Node::op(ops[rng() % 3], std::move(children));
}

// The obviously-correct evaluator: one point at a time.
bool inside(const Node& n, double x, double y) {
  if (n.is_leaf()) return n.primitive.contains(x, y);
  bool v = inside(n.children[0], x, y);
  for (std::size_t i = 1; i < n.children.size(); ++i) {
    const bool c = inside(n.children[i], x, y);
    switch (n.kind) {
      case NodeKind::Union: v = v || c; break;
      case NodeKind::Difference: v = v && !c; break;
      case NodeKind::Intersection: v = v && c; break;
      default: break;
    }
  }
  return v;
}

Bitmap brute_force(const Node& n, int w, int h) {
  Bitmap b(w, h);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c)
      if (inside(n, c + 0.5, h - r - 0.5)) b.set(c, r);
  return b;
}

Mismatch mismatch_of(const Bitmap& raster, const Bitmap& target) {
  return {count_and_not(raster, target), count_and_not(target, raster)};
}

}  // namespace

TEST(Evaluator, RenderMatchesBruteForceOnRandomTrees) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 200; ++i) {
    const Node t = random_tree(rng, 3);
    ASSERT_EQ(render(t, 64, 64), brute_force(t, 64, 64)) << structure_string(t);
  }
}

TEST(Evaluator, IncrementalUpdatesMatchFullEvaluation) {
  std::mt19937_64 rng(5);
  const Node shape = random_tree(rng, 2);
  const Bitmap target = brute_force(shape, 64, 64);
  for (int i = 0; i < 60; ++i) {
    Node t = random_tree(rng, 3);
    TreeEvaluator ev(target, t);
    for (int step = 0; step < 20; ++step) {
      const std::size_t leaf = rng() % ev.leaf_count();
      const Primitive p = random_primitive(rng);
      const Mismatch predicted = ev.try_leaf(leaf, p);
      ev.leaf(leaf) = p;
      const Mismatch updated = ev.update_leaf(leaf);
      const Bitmap reference = brute_force(t, 64, 64);
      const Mismatch expected = mismatch_of(reference, target);
      ASSERT_EQ(ev.result(), reference) << structure_string(t);
      ASSERT_EQ(updated.excess, expected.excess);
      ASSERT_EQ(updated.uncovered, expected.uncovered);
      ASSERT_EQ(predicted.excess, expected.excess);
      ASSERT_EQ(predicted.uncovered, expected.uncovered);
    }
  }
}

TEST(Evaluator, TryWithoutLeafMatchesRemovingIt) {
  std::mt19937_64 rng(9);
  const Bitmap target = brute_force(random_tree(rng, 2), 64, 64);
  for (int i = 0; i < 100; ++i) {
    Node t = random_tree(rng, 3);
    if (t.primitive_count() < 2) continue;
    TreeEvaluator ev(target, t);
    const std::size_t leaf = rng() % ev.leaf_count();
    const Mismatch predicted = ev.try_without_leaf(leaf);
    // Remove the leaf by hand: out of its parent's list; a difference without its base vanishes.
    Node copy = t;
    std::vector<Primitive*> ls = leaves(copy);
    const Primitive* victim = ls[leaf];
    std::function<bool(Node&)> erase = [&](Node& n) {
      for (std::size_t c = 0; c < n.children.size(); ++c) {
        if (n.children[c].is_leaf() && &n.children[c].primitive == victim) {
          if (n.kind == NodeKind::Difference && c == 0) n.children.clear();
          else n.children.erase(n.children.begin() + static_cast<long>(c));
          return true;
        }
        if (erase(n.children[c])) return true;
      }
      return false;
    };
    erase(copy);
    Bitmap reference(64, 64);
    if (simplify(copy)) reference = brute_force(copy, 64, 64);
    const Mismatch expected = mismatch_of(reference, target);
    ASSERT_EQ(predicted.excess, expected.excess) << structure_string(t) << " leaf " << leaf;
    ASSERT_EQ(predicted.uncovered, expected.uncovered) << structure_string(t) << " leaf " << leaf;
  }
}

TEST(Tree, SimplifyKeepsTheShapeAndFlattens) {
  std::mt19937_64 rng(13);
  for (int i = 0; i < 200; ++i) {
    Node t = random_tree(rng, 4);
    const Bitmap before = render(t, 64, 64);
    Node s = t;
    ASSERT_TRUE(simplify(s));
    ASSERT_EQ(render(s, 64, 64), before) << structure_string(t) << " -> " << structure_string(s);
    ASSERT_EQ(s.primitive_count(), t.primitive_count());
    // No union directly under a union, no operator with a single child.
    for_each_node(s, [&](const Node& n, std::size_t) {
      if (n.is_leaf()) return;
      ASSERT_GE(n.children.size(), 2u);
      for (const Node& c : n.children)
        if (n.kind == NodeKind::Union || n.kind == NodeKind::Intersection) ASSERT_NE(c.kind, n.kind);
    });
  }
}

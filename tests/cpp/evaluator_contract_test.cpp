// What the incremental evaluator promises in 2D and 3D alike, tested once over both against the
// brute-force references: a tree renders as its pointwise raster, and every trial, update and
// removal reports the counts of that raster.
#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "evaluator_reference.h"

using namespace csgfit;
using namespace csgfit::reference;

template <typename Dim>
class EvaluatorContract : public ::testing::Test {};
using Dimensions = ::testing::Types<Flat, Solid>;
TYPED_TEST_SUITE(EvaluatorContract, Dimensions);

TYPED_TEST(EvaluatorContract, RenderMatchesBruteForceOnRandomTrees) {
  using D = TypeParam;
  std::mt19937_64 rng(3);
  std::size_t covered = 0;
  for (int i = 0; i < D::kRenderTrials; ++i) {
    const auto t = D::random_tree(rng, 3);
    const auto r = D::render(t);
    ASSERT_EQ(r, D::brute_force(t)) << structure_string(t);
    covered += r.count();
  }
  EXPECT_GT(covered, D::kMinCovered);
}

TYPED_TEST(EvaluatorContract, IncrementalUpdatesMatchFullEvaluation) {
  using D = TypeParam;
  std::mt19937_64 rng(5);
  const auto target = D::brute_force(D::random_tree(rng, 2));
  for (int i = 0; i < D::kUpdateTrees; ++i) {
    auto t = D::random_tree(rng, 3);
    typename D::Evaluator ev(target, t);
    const Mismatch initial = mismatch_of(D::brute_force(t), target);
    ASSERT_EQ(ev.mismatch().excess, initial.excess);
    ASSERT_EQ(ev.mismatch().uncovered, initial.uncovered);
    for (int step = 0; step < D::kUpdateSteps; ++step) {
      const std::size_t leaf = rng() % ev.leaf_count();
      const auto p = D::random_primitive(rng);
      const Mismatch predicted = ev.try_leaf(leaf, p);
      ev.leaf(leaf) = p;
      const Mismatch updated = ev.update_leaf(leaf);
      const auto reference = D::brute_force(t);
      const Mismatch expected = mismatch_of(reference, target);
      ASSERT_EQ(ev.result(), reference) << structure_string(t);
      ASSERT_EQ(updated.excess, expected.excess);
      ASSERT_EQ(updated.uncovered, expected.uncovered);
      ASSERT_EQ(predicted.excess, expected.excess);
      ASSERT_EQ(predicted.uncovered, expected.uncovered);
    }
  }
}

TYPED_TEST(EvaluatorContract, TryWithoutLeafMatchesRemovingIt) {
  using D = TypeParam;
  using Tree = typename D::Tree;
  std::mt19937_64 rng(9);
  const auto target = D::brute_force(D::random_tree(rng, 2));
  for (int i = 0; i < D::kRemovalTrials; ++i) {
    Tree t = D::random_tree(rng, 3);
    if (t.primitive_count() < 2) continue;
    typename D::Evaluator ev(target, t);
    const std::size_t leaf = rng() % ev.leaf_count();
    const Mismatch predicted = ev.try_without_leaf(leaf);
    // Remove the leaf by hand: out of its parent's list; a difference without its base vanishes.
    Tree copy = t;
    const auto* victim = leaves(copy)[leaf];
    std::function<bool(Tree&)> erase = [&](Tree& n) {
      for (std::size_t c = 0; c < n.children.size(); ++c) {
        if (n.children[c].is_leaf() && &n.children[c].primitive == victim) {
          if (n.kind == NodeKind::Difference && c == 0)
            n.children.clear();
          else
            n.children.erase(n.children.begin() + static_cast<long>(c));
          return true;
        }
        if (erase(n.children[c])) return true;
      }
      return false;
    };
    erase(copy);
    auto reference = D::empty();
    if (simplify(copy)) reference = D::brute_force(copy);
    const Mismatch expected = mismatch_of(reference, target);
    ASSERT_EQ(predicted.excess, expected.excess) << structure_string(t) << " leaf " << leaf;
    ASSERT_EQ(predicted.uncovered, expected.uncovered) << structure_string(t) << " leaf " << leaf;
  }
}

TYPED_TEST(EvaluatorContract, SimplifyKeepsTheShapeAndFlattens) {
  using D = TypeParam;
  using Tree = typename D::Tree;
  std::mt19937_64 rng(13);
  for (int i = 0; i < D::kSimplifyTrials; ++i) {
    Tree t = D::random_tree(rng, 4);
    const auto before = D::render(t);
    Tree s = t;
    ASSERT_TRUE(simplify(s));
    ASSERT_EQ(D::render(s), before) << structure_string(t) << " -> " << structure_string(s);
    ASSERT_EQ(s.primitive_count(), t.primitive_count());
    // No union directly under a union, no operator with a single child.
    for_each_node(s, [&](const Tree& n, std::size_t) {
      if (n.is_leaf()) return;
      ASSERT_GE(n.children.size(), 2u);
      for (const Tree& c : n.children)
        if (n.kind == NodeKind::Union || n.kind == NodeKind::Intersection)
          ASSERT_NE(c.kind, n.kind);
    });
  }
}

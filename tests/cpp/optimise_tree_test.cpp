// Seed 001's optimiser: each rule, the decomposition, proximity, the generator, and the
// invariant a user relies on: the optimised tree is the same solid and never larger.
#include <gtest/gtest.h>

#include <random>

#include "csgfit/error.h"
#include "csgfit/optimise/expression.h"
#include "csgfit/optimise/inflate.h"
#include "csgfit/optimise/optimize_tree.h"
#include "csgfit/optimise/redundancy.h"
#include "csgfit/optimise/structural_rules.h"
#include "csgfit/optimise/tree_expression.h"
#include "random_trees.h"

namespace csgfit::opt {
namespace {

Expr h(int i) { return Expr::halfspace(i); }
Expr U(std::vector<Expr> k) { return Expr::make(ExprOp::Union, std::move(k)); }
Expr I(std::vector<Expr> k) { return Expr::make(ExprOp::Intersection, std::move(k)); }
Expr D(std::vector<Expr> k) { return Expr::make(ExprOp::Difference, std::move(k)); }
Expr N(Expr e) { return Expr::complement(std::move(e)); }

Halfspace<3> sphere(double x, double y, double z, double r) {
  Halfspace<3> s;
  s.bounds = {{x - r, y - r, z - r}, {x + r, y + r, z + r}};
  s.contains = [=](const Point<3>& p) {
    return (p[0] - x) * (p[0] - x) + (p[1] - y) * (p[1] - y) + (p[2] - z) * (p[2] - z) <= r * r;
  };
  return s;
}

Halfspace<3> box(double x0, double y0, double z0, double x1, double y1, double z1) {
  Halfspace<3> b;
  b.bounds = {{x0, y0, z0}, {x1, y1, z1}};
  b.contains = [bb = b.bounds](const Point<3>& p) { return bb.contains(p); };
  return b;
}

bool inside(const Expr& e, const HalfspaceList<3>& hs, const Point<3>& p) {
  switch (e.op) {
    case ExprOp::Halfspace: return hs[static_cast<std::size_t>(e.index)].contains(p);
    case ExprOp::Empty: return false;
    case ExprOp::Universe: return true;
    case ExprOp::Complement: return !inside(e.kids[0], hs, p);
    case ExprOp::Union:
      return std::any_of(e.kids.begin(), e.kids.end(), [&](const Expr& k) { return inside(k, hs, p); });
    case ExprOp::Intersection:
      return std::all_of(e.kids.begin(), e.kids.end(), [&](const Expr& k) { return inside(k, hs, p); });
    case ExprOp::Difference:
      return inside(e.kids[0], hs, p) &&
             std::none_of(e.kids.begin() + 1, e.kids.end(), [&](const Expr& k) { return inside(k, hs, p); });
    default: throw std::logic_error("opaque");
  }
}

// Points where the two trees disagree, of `n` uniform ones in [lo, hi]^3.
std::size_t disagreements(const Expr& a, const Expr& b, const HalfspaceList<3>& hs, std::size_t n, double lo,
                          double hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::size_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point<3> p{u(rng), u(rng), u(rng)};
    bad += inside(a, hs, p) != inside(b, hs, p);
  }
  return bad;
}

TEST(StructuralRules, DoubleComplementAndConstants) {
  Expr e = N(N(h(0)));
  apply_structural_rules(e);
  EXPECT_EQ(e, h(0));
  e = U({h(0), Expr::empty(), I({h(1), Expr::universe()})});
  apply_structural_rules(e);
  EXPECT_EQ(to_text(e), "union(h0, h1)");
  e = I({h(0), Expr::empty()});
  apply_structural_rules(e);
  EXPECT_EQ(e.op, ExprOp::Empty);
  e = D({h(0), h(0)});
  apply_structural_rules(e);
  EXPECT_EQ(e.op, ExprOp::Empty);
}

TEST(StructuralRules, IdenticalOperandsAbsorptionAndFactoring) {
  Expr e = U({h(0), h(0), I({h(0), h(1)})});  // CSI then ALI
  apply_structural_rules(e);
  EXPECT_EQ(e, h(0));
  e = I({h(2), U({h(2), h(3)})});
  apply_structural_rules(e);
  EXPECT_EQ(e, h(2));
  e = U({I({h(0), h(1)}), I({h(0), h(2)})});  // DLI
  apply_structural_rules(e);
  EXPECT_EQ(to_text(e), "inter(h0, union(h1, h2))");
  e = U({D({h(1), h(0)}), D({h(2), h(0)})});
  apply_structural_rules(e);
  EXPECT_EQ(to_text(e), "diff(union(h1, h2), h0)");
  e = D({h(5), D({h(5), h(1)})});  // a double complement written with a bounding solid
  apply_structural_rules(e);
  EXPECT_EQ(to_text(e), "inter(h5, h1)");
}

TEST(StructuralRules, NeverGrowOnRandomInflations) {
  for (std::uint64_t seed = 1; seed <= 50; ++seed) {
    const Expr base = D({U({h(0), h(1), I({h(2), h(3)})}), h(4)});
    InflateOptions o;
    o.seed = seed;
    Expr e = inflate(base, o);
    const std::size_t before = expression_size(e);
    apply_structural_rules(e);
    EXPECT_LE(expression_size(e), before);
  }
}

class SampledRules : public ::testing::Test {
 protected:
  HalfspaceList<3> hs{box(0, 0, 0, 10, 10, 10), sphere(5, 5, 5, 2), sphere(20, 20, 20, 2), box(2, 2, 2, 8, 8, 8)};
  SampleSet<3> s{hs, {}};
};

TEST_F(SampledRules, EmptyIntersectionAndDisjointSubtrahend) {
  Expr e = I({h(0), h(2)});
  remove_redundancy(e, s);
  EXPECT_EQ(e.op, ExprOp::Empty);
  e = D({h(0), h(2)});
  remove_redundancy(e, s);
  EXPECT_EQ(e, h(0));
}

TEST_F(SampledRules, OperandsTheOthersHold) {
  Expr e = U({h(0), h(1)});  // the sphere is inside the box
  remove_redundancy(e, s);
  EXPECT_EQ(e, h(0));
  e = I({h(0), h(3)});  // the small box is inside the big one
  remove_redundancy(e, s);
  EXPECT_EQ(e, h(3));
  e = D({h(3), h(1), I({h(1), h(0)})});  // the second cut removes nothing the first does not
  remove_redundancy(e, s);
  EXPECT_EQ(to_text(e), "diff(h3, h1)");
}

TEST_F(SampledRules, OpaqueOperandsStay) {
  Expr e = U({Expr::opaque(0), h(0), h(1)});
  remove_redundancy(e, s);
  EXPECT_EQ(to_text(e), "union(opaque0, h0)");
  e = I({Expr::opaque(0), h(0), h(3)});
  remove_redundancy(e, s);
  EXPECT_EQ(to_text(e), "inter(opaque0, h3)");
}

// A solid with a chain of dominant halfspaces as in the seed's Fig. 3: two boxes that lie in
// the solid, a sphere that lies outside it, and a remaining solid (two overlapping boxes'
// intersection) that no halfspace dominates.
TEST(Decomposition, DominantHalfspacesFactorOut) {
  HalfspaceList<3> hs{box(0, 0, 0, 4, 4, 4), box(2, 2, 2, 6, 6, 6), box(10, 0, 0, 14, 4, 4),
                      box(0, 10, 0, 4, 14, 4), sphere(12, 12, 2, 1.5)};
  // The input repeats the dominant ones inside a larger expression.
  const Expr input = U({D({U({I({h(0), h(1)}), h(2), h(3)}), h(4)}), D({I({h(2), U({h(2), h(4)})}), h(4)}),
                        I({h(3), U({h(3), h(0)})})});
  OptimizeResult r = optimize_tree(input, hs, {});
  EXPECT_EQ(r.report.check_mismatches, 0u);
  EXPECT_EQ(halfspaces_used(r.tree), (std::vector<int>{0, 1, 2, 3}));  // the sphere cut nothing
  EXPECT_EQ(expression_size(r.tree), 6u);  // union(inter(h0, h1), h2, h3)
  EXPECT_GE(r.report.dominant_halfspaces, 2u);
  EXPECT_EQ(disagreements(input, r.tree, hs, 100000, -1, 15, 7), 0u);
}

TEST(Proximity, HandMadeTrees) {
  HalfspaceList<3> hs{sphere(0, 0, 0, 1), sphere(1, 0, 0, 1), sphere(10, 0, 0, 1)};
  SampleSet<3> s(hs, {});
  EXPECT_DOUBLE_EQ(proximity(h(0), s), 1.0);
  EXPECT_DOUBLE_EQ(proximity(U({h(0), h(1)}), s), 1.0);
  EXPECT_DOUBLE_EQ(proximity(U({h(0), h(2)}), s), 0.0);
  EXPECT_DOUBLE_EQ(proximity(U({h(0), h(1), h(2)}), s), 0.5);
  EXPECT_DOUBLE_EQ(proximity(D({U({h(0), h(2)}), h(1)}), s), 0.5);
}

// Random trees of random spheres and boxes, inflated by the seed's generator: optimised, they
// are the same solid (the sign at 10^5 points) and no larger than before inflation on average.
TEST(OptimizeTree, SameSolidOnRandomInflatedTrees) {
  std::size_t total_before = 0, total_after = 0, runs = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> c(0, 10), r(1.5, 4);
    HalfspaceList<3> hs;
    for (int i = 0; i < 6; ++i) {
      if (i % 2) hs.push_back(sphere(c(rng), c(rng), c(rng), r(rng)));
      else {
        const double x = c(rng), y = c(rng), z = c(rng), a = r(rng), b = r(rng), d = r(rng);
        hs.push_back(box(x - a, y - b, z - d, x + a, y + b, z + d));
      }
    }
    const Expr base = D({U({h(0), h(1), I({h(2), h(3)})}), h(4), h(5)});
    InflateOptions io;
    io.seed = seed;
    const Expr inflated = inflate(base, io);
    EXPECT_EQ(disagreements(base, inflated, hs, 20000, -5, 15, seed), 0u) << "the generator changed the solid";
    OptimizeResult out = optimize_tree(inflated, hs, {});
    EXPECT_EQ(disagreements(inflated, out.tree, hs, 100000, -5, 15, seed + 100), 0u) << to_text(out.tree);
    total_before += expression_size(base);
    total_after += expression_size(out.tree);
    ++runs;
  }
  EXPECT_LE(total_after, total_before);
}

TEST(OptimizeTree, SameSeedSameTree) {
  HalfspaceList<3> hs{box(0, 0, 0, 4, 4, 4), sphere(4, 4, 4, 2), sphere(0, 0, 0, 1.5), box(1, 1, 1, 3, 3, 3)};
  const Expr e = U({D({h(0), h(1)}), I({h(2), h(3)}), D({h(0), h(1), h(2)})});
  for (auto method : {RemainingMethod::Espresso, RemainingMethod::Genetic}) {
    OptimizeOptions o;
    o.method = method;
    EXPECT_EQ(optimize_tree(e, hs, o).tree, optimize_tree(e, hs, o).tree);
  }
}

TEST(OptimizeTree, EmptyTreeIsRefused) {
  HalfspaceList<3> hs{sphere(0, 0, 0, 1), sphere(5, 0, 0, 1)};
  EXPECT_THROW(optimize_tree(I({h(0), h(1)}), hs, {}), InputError);
}

// A 2D fit's tree: a circle inside a rectangle it is united with goes.
TEST(OptimizeTree, OurTwoDimensionalTrees) {
  const Node tree = Node::op(NodeKind::Union, {Node::leaf(Primitive::rectangle(50, 50, 40, 30)),
                                              Node::leaf(Primitive::circle(50, 50, 5)),
                                              Node::leaf(Primitive::circle(90, 50, 5))});
  OptimizeReport report;
  const Node better = optimize_csg_tree(tree, {}, &report);
  EXPECT_EQ(better.primitive_count(), 2u);
  EXPECT_EQ(report.check_mismatches, 0u);
}

}  // namespace
}  // namespace csgfit::opt

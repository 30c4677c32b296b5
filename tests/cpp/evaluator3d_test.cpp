// What only the 3D tree and evaluator do: signed distances, the count beyond the grid, the
// staggered lattice (the contract both dimensions share is evaluator_contract_test.cpp).
#include "csgfit/eval/evaluator3d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "csgfit/model/tree3d.h"
#include "evaluator_reference.h"

using namespace csgfit;

namespace {

using reference::Solid;
constexpr int kNx = Solid::kNx, kNy = Solid::kNy, kNz = Solid::kNz;
const VoxelGrid kFrame = Solid::frame();

Primitive3D random_primitive(std::mt19937_64& rng) { return Solid::random_primitive(rng); }
Node3D random_tree(std::mt19937_64& rng, int depth) { return Solid::random_tree(rng, depth); }

}  // namespace

TEST(Evaluator3D, CountsEvaluations) {
  std::mt19937_64 rng(2);
  Node3D t = random_tree(rng, 2);
  const VoxelGrid target = render(t, kFrame);
  TreeEvaluator3D ev(target, t);
  EXPECT_EQ(ev.mismatch().excess + ev.mismatch().uncovered, 0u);
  EXPECT_EQ(ev.evaluations(), 1u);
  ev.try_leaf(0, ev.leaf(0));
  ev.update_leaf(0);
  EXPECT_EQ(ev.evaluations(), 3u);
}

// A primitive reaching beyond the grid would render where the grid cannot see: the part of the
// tree's box outside the grid counts as `outside`, exactly for a box, and only for the part of
// the tree that can add material (not for a subtracted primitive).
TEST(Evaluator3D, CountsTheTreeBeyondTheGrid) {
  const VoxelGrid target(20, 20, 20, 0, 0, 0, 1.0);
  Node3D inside = Node3D::leaf(Primitive3D::box(10, 10, 10, 8, 8, 8));
  EXPECT_EQ(TreeEvaluator3D(target, inside).mismatch().outside, 0u);
  // x in [16, 26]: 6 of its 10 units beyond x = 20, over a 4 x 4 section.
  Node3D poking = Node3D::leaf(Primitive3D::box(21, 10, 10, 10, 4, 4));
  TreeEvaluator3D ev(target, poking);
  EXPECT_EQ(ev.mismatch().outside, 6u * 4 * 4);
  EXPECT_EQ(ev.try_leaf(0, Primitive3D::box(10, 10, 10, 4, 4, 4)).outside, 0u);
  Node3D cut = Node3D::op(NodeKind::Difference, {Node3D::leaf(Primitive3D::box(10, 10, 10, 8, 8, 8)),
                                                 Node3D::leaf(Primitive3D::box(21, 10, 10, 10, 4, 4))});
  EXPECT_EQ(TreeEvaluator3D(target, cut).mismatch().outside, 0u);
  Node3D clipped = Node3D::op(NodeKind::Intersection,
                              {Node3D::leaf(Primitive3D::box(10, 10, 10, 8, 8, 8)),
                               Node3D::leaf(Primitive3D::sphere(10, 10, 10, 40))});
  EXPECT_EQ(TreeEvaluator3D(target, clipped).mismatch().outside, 0u);
}

// Two lattices: every count is the sum of what each lattice's own evaluator reports, through
// updates, trials and removals.
TEST(Evaluator3D, StaggeredLatticeCountsAreTheSumOfBothLattices) {
  std::mt19937_64 rng(17);
  const double h = kFrame.voxel_size();
  const VoxelGrid shifted_frame(kNx, kNy, kNz, kFrame.origin_x() + h / 2, kFrame.origin_y() + h / 2,
                                kFrame.origin_z() + h / 2, h);
  const Node3D part = random_tree(rng, 2);
  const VoxelGrid target = render(part, kFrame), staggered = render(part, shifted_frame);
  auto sum_equals = [](const Mismatch& both, const Mismatch& a, const Mismatch& b) {
    return both.excess == a.excess + b.excess && both.uncovered == a.uncovered + b.uncovered &&
           both.outside == a.outside + b.outside;
  };
  for (int i = 0; i < 20; ++i) {
    Node3D t = random_tree(rng, 3);
    TreeEvaluator3D both(target, staggered, t), a(target, t), b(staggered, t);
    ASSERT_TRUE(both.staggered());
    ASSERT_TRUE(sum_equals(both.mismatch(), a.mismatch(), b.mismatch()));
    for (int step = 0; step < 8; ++step) {
      const std::size_t leaf = rng() % both.leaf_count();
      const Primitive3D p = random_primitive(rng);
      ASSERT_TRUE(sum_equals(both.try_leaf(leaf, p), a.try_leaf(leaf, p), b.try_leaf(leaf, p)));
      if (both.leaf_count() > 1)
        ASSERT_TRUE(sum_equals(both.try_without_leaf(leaf), a.try_without_leaf(leaf),
                               b.try_without_leaf(leaf)));
      both.leaf(leaf) = p;  // a and b share the tree's leaves
      const Mismatch updated = both.update_leaf(leaf);
      ASSERT_TRUE(sum_equals(updated, a.update_leaf(leaf), b.update_leaf(leaf)));
      ASSERT_EQ(both.result(), a.result());
    }
  }
}

// What the staggered lattice is for: a sheet 0.4 voxel thick between two rows of centres
// (a plate left on top of a part, a slit cut into it) costs nothing on one lattice and renders;
// the staggered lattice's rows run through it.
TEST(Evaluator3D, StaggeredLatticeSeesASheetBetweenRowsOfCentres) {
  // Centres at k + 0.5 on the first lattice, at k on the staggered one.
  const VoxelGrid frame(20, 20, 20, 0, 0, 0, 1.0), shifted(20, 20, 20, 0.5, 0.5, 0.5, 1.0);
  // x, y in [4.2, 15.8]: 12 centres across on the first lattice, 11 on the staggered one.
  const Node3D part = Node3D::leaf(Primitive3D::box(10, 10, 8, 11.6, 11.6, 8));
  const VoxelGrid target = render(part, frame), staggered = render(part, shifted);
  // A plate z in [12.8, 13.2] above the part: between the first lattice's 12.5 and 13.5.
  Node3D sheet =
      Node3D::op(NodeKind::Union, {part, Node3D::leaf(Primitive3D::box(10, 10, 13, 11.6, 11.6, 0.4))});
  EXPECT_EQ(TreeEvaluator3D(target, sheet).mismatch().total(), 0u);
  EXPECT_EQ(TreeEvaluator3D(target, staggered, sheet).mismatch().excess, 11u * 11);
  // A slit z in [7.8, 8.2] through the part: uncovered only on the staggered lattice.
  Node3D slit =
      Node3D::op(NodeKind::Difference, {part, Node3D::leaf(Primitive3D::box(10, 10, 8, 14, 14, 0.4))});
  EXPECT_EQ(TreeEvaluator3D(target, slit).mismatch().total(), 0u);
  EXPECT_EQ(TreeEvaluator3D(target, staggered, slit).mismatch().uncovered, 11u * 11);
}

TEST(Evaluator3D, SurfaceLeafIsThePrimitiveThatMakesTheSurface) {
  // A plate with a bore: on the plate's faces the plate, on the bore's wall the bore (the
  // difference's negative), outside next to the plate the plate.
  Node3D part = Node3D::op(NodeKind::Difference,
                           {Node3D::leaf(Primitive3D::box(10, 10, 10, 12, 12, 4)),
                            Node3D::leaf(Primitive3D::cylinder(10, 10, 10, 2, 10))});
  TreeEvaluator3D ev(kFrame, part);
  EXPECT_EQ(ev.surface_leaf(10, 6, 12), 0u);
  double d = 0;
  EXPECT_EQ(ev.surface_leaf(16.5, 10, 10, &d), 0u);
  EXPECT_NEAR(d, 0.5, 1e-12);
  EXPECT_EQ(ev.surface_leaf(12, 10, 10), 1u);
  EXPECT_EQ(ev.surface_leaf(11.5, 10, 10), 1u);  // in the bore: its wall is nearest
}

TEST(Tree3D, SignedDistanceSignAgreesWithContains) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> px(-1, 19), py(0.5, 18.5), pz(2, 18);
  int inside = 0, outside = 0;
  for (int i = 0; i < 150; ++i) {
    const Node3D t = random_tree(rng, 3);
    for (int s = 0; s < 400; ++s) {
      const double x = px(rng), y = py(rng), z = pz(rng);
      const double d = signed_distance(t, x, y, z);
      if (std::fabs(d) < 1e-9) continue;
      ASSERT_EQ(d < 0, contains(t, x, y, z)) << structure_string(t) << " d=" << d;
      (d < 0 ? inside : outside)++;
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 1000);
}

TEST(Tree3D, SignedDistanceComposition) {
  const Primitive3D a = Primitive3D::sphere(0, 0, 0, 2);
  const Primitive3D b = Primitive3D::box(2, 0, 0, 2, 2, 2);
  const Node3D u = Node3D::op(NodeKind::Union, {Node3D::leaf(a), Node3D::leaf(b)});
  const Node3D d = Node3D::op(NodeKind::Difference, {Node3D::leaf(a), Node3D::leaf(b)});
  const Node3D n = Node3D::op(NodeKind::Intersection, {Node3D::leaf(a), Node3D::leaf(b)});
  // Outside a union the distance is exact: nearest of the two.
  EXPECT_NEAR(signed_distance(u, 5, 0, 0), 2, 1e-12);
  EXPECT_NEAR(signed_distance(u, -5, 0, 0), 3, 1e-12);
  // Inside the sphere, in the box: carved away by the difference, inside the intersection.
  EXPECT_GT(signed_distance(d, 1.5, 0, 0), 0);
  EXPECT_LT(signed_distance(n, 1.5, 0, 0), 0);
  EXPECT_NEAR(signed_distance(d, -1, 0, 0), -1, 1e-12);
  EXPECT_EQ(structure_string(d), "difference(sphere, box)");
  EXPECT_EQ(d.node_count(), 3u);
  EXPECT_EQ(d.depth(), 2u);
}

// ---------------------------------------------------------------------------------------------
// Local optimiser and pruning (local_opt3d.h)

#include "csgfit/refine/local_opt.h"
#include "csgfit/optimise/prune.h"

TEST(LocalOpt3D, RecoversAPerturbedBoxMinusCylinder) {
  VoxelGrid frame(48, 48, 48, 0, 0, 0, 1.0);
  const Primitive3D box = Primitive3D::box(24.2, 23.6, 24.4, 30, 22, 18,
                                           Quaternion::from_euler_deg(0, 0, 12));
  const Primitive3D cyl = Primitive3D::cylinder(26.3, 22.8, 24.1, 6.5, 26,
                                                Quaternion::from_euler_deg(8, 0, 0));
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(box), Node3D::leaf(cyl)});
  const VoxelGrid target = render(truth, frame);
  // Each parameter off by one to two voxels, the orientations by a few degrees.
  Primitive3D b2 = box, c2 = cyl;
  b2.cx += 1.6, b2.cy -= 1.2, b2.cz += 0.9;
  b2.dims[0] -= 2.5, b2.dims[1] += 1.8, b2.dims[2] -= 1.5;
  b2.rotation = Quaternion::from_euler_deg(3, -2, 17);
  c2.cx -= 1.4, c2.cy += 1.1, c2.cz -= 1.0;
  c2.dims[0] += 1.5, c2.dims[2] -= 3;
  c2.rotation = Quaternion::from_euler_deg(2, 4, 0);
  c2.normalize();
  Node3D tree = Node3D::op(NodeKind::Difference, {Node3D::leaf(b2), Node3D::leaf(c2)});
  TreeEvaluator3D ev(target, tree);
  const std::size_t before = ev.mismatch().total();
  const std::size_t moves = optimize_leaves(ev, LocalOptOptions{});
  const std::size_t after = ev.mismatch().total();
  std::printf("local opt 3D: mismatch %zu -> %zu voxels of %zu (%zu moves, %zu evaluations)\n",
              before, after, target.count(), moves, ev.evaluations());
  EXPECT_GT(moves, 0u);
  EXPECT_LT(after, before / 8);
  EXPECT_LT(static_cast<double>(after), 0.01 * static_cast<double>(target.count()));
  // The parameters are back to within a voxel.
  const Primitive3D& rb = ev.leaf(0);
  const Primitive3D& rc = ev.leaf(1);
  EXPECT_NEAR(rb.cx, box.cx, 1.0);
  EXPECT_NEAR(rb.cy, box.cy, 1.0);
  EXPECT_NEAR(rb.cz, box.cz, 1.0);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(rb.dims[i], box.dims[i], 1.0) << i;
  EXPECT_NEAR(rc.dims[0], cyl.dims[0], 0.75);
  EXPECT_NEAR(rb.rotation.euler_deg()[2], 12, 3);
  // The incremental state is the full evaluation.
  EXPECT_EQ(ev.result(), render(tree, frame));
}

TEST(LocalOpt3D, PruneDropsWhatDoesNotPay) {
  VoxelGrid frame(40, 40, 40, 0, 0, 0, 1.0);
  const Primitive3D big = Primitive3D::box(20, 20, 20, 24, 24, 24);
  const Node3D truth = Node3D::leaf(big);
  const VoxelGrid target = render(truth, frame);
  // A useless speck inside the box and a small sphere hanging out of it.
  Node3D tree = Node3D::op(NodeKind::Union, {Node3D::leaf(big),
                                             Node3D::leaf(Primitive3D::sphere(20, 20, 20, 2)),
                                             Node3D::leaf(Primitive3D::sphere(33, 20, 20, 2))});
  const std::size_t removed = prune(tree, target, 50);
  EXPECT_EQ(removed, 2u);
  EXPECT_TRUE(tree.is_leaf());
  EXPECT_EQ(tree.primitive, big);
}

// Trimming hidden material (seed 002's smallest hidden extents, for what a cut takes away) on
// scans rendered from known trees: a dome's hidden lower half under its plate goes, what a view
// saw stays, a seen face is not hollowed into a skin, and a ball flattened on its seen side is
// flattened the same on its hidden side.
#include <gtest/gtest.h>

#include "csgfit/features/range_evidence.h"
#include "csgfit/refine/range_refine.h"
#include "csgfit/search/hidden_trim.h"
#include "range_graphs.h"

namespace csgfit {
namespace {

using testing::evidence_of;
using testing::graph_of;
using testing::looking_at;
using testing::scan_of;
using testing::signed_node;

// The halfspace below (or above) the plane z = height, as the surface candidates give it.
SignedPrimitive halfspace(double height, bool below) {
  SignedPrimitive cut = signed_node(Primitive3D::box(0, 0, height + (below ? -10 : 10), 40, 40, 20), false);
  cut.conjectured = cut.halfspace = true;
  return cut;
}

const Primitive3D kPlate = Primitive3D::box(0, 0, 0, 8, 6, 0.5);  // top face at z = 0.25
const Primitive3D kBall = Primitive3D::sphere(0, 0, 0.25, 2);
const std::vector<SignedPrimitive> kCuts = {halfspace(0.25, true), halfspace(0.25, false)};

TEST(HiddenTrim, ADomesHiddenLowerHalfUnderItsPlateGoes) {
  const Node3D dome = Node3D::op(NodeKind::Difference,
                                 {Node3D::leaf(kBall), Node3D::leaf(kCuts[0].primitive)});
  const RangeEvidence evidence = evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), dome}));
  const PrecedenceGraph g = trim_hidden(graph_of({signed_node(kPlate, true), signed_node(kBall, true)}),
                                        kCuts, evidence, evidence_k(evidence));
  ASSERT_EQ(g.nodes.size(), 3u);
  EXPECT_TRUE(g.nodes[2].conjectured);
  const Node3D tree = precedence_tree(g);
  EXPECT_FALSE(contains(tree, 0, 0, -1.2)) << "the ball's hidden half under the plate is cut";
  EXPECT_TRUE(contains(tree, 0, 0, 1.5)) << "the dome the view saw stays";
  EXPECT_TRUE(contains(tree, 0, 0, 0)) << "the plate is whole";
  EXPECT_TRUE(contains(tree, 3.5, 2.5, 0));
}

TEST(HiddenTrim, WhatAViewSawStays) {
  // The whole ball seen above a plate that reaches only to its middle: the view sees below
  // the plate's plane on the ball's front, so no cut by that plane is unseen.
  const Primitive3D small_plate = Primitive3D::box(-3, 0, 0, 4, 6, 0.5);
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(small_plate), Node3D::leaf(kBall)}));
  const PrecedenceGraph start = graph_of({signed_node(small_plate, true), signed_node(kBall, true)});
  const PrecedenceGraph g = trim_hidden(start, kCuts, evidence, evidence_k(evidence));
  EXPECT_EQ(g.nodes.size(), 2u);
}

TEST(HiddenTrim, ASeenFaceIsNotHollowedIntoASkin) {
  // A plate cut by the plane of its own top face leaves nothing but a surface where the view saw
  // one: the points behind its returns tell. Seen from straight above, where its sides do not.
  const RangeScan scan = scan_of(Node3D::leaf(kPlate), looking_at({0, 0, 0}, 30, 89, 30, 160, 0.08));
  const RangeEvidence evidence = gather_evidence({scan}, 0.1, 6000);
  ASSERT_FALSE(evidence.behind.empty());
  const PrecedenceGraph plate = graph_of({signed_node(kPlate, true)});
  EXPECT_EQ(trim_hidden(plate, kCuts, evidence, evidence_k(evidence)).nodes.size(), 1u);
  RangeEvidence blind = evidence;
  blind.behind.clear();
  EXPECT_EQ(trim_hidden(plate, kCuts, blind, evidence_k(blind)).nodes.size(), 2u)
      << "without them the skin looks the same as the plate";
}

// A ball of radius 2 with a flat at 1.6 from its centre along each of `sides` (unit axes) cut
// from it, as the surface reading gives them: node 0 the ball, then the blocks.
PrecedenceGraph ball_with_flats(const std::vector<Vec3>& sides) {
  PrecedenceGraph g = graph_of({signed_node(Primitive3D::sphere(0, 0, 0, 2), true)});
  for (const Vec3& s : sides) {
    const Vec3 c = {s[0] * 6.6, s[1] * 6.6, s[2] * 6.6};  // a block 10 wide, its face at 1.6
    g = with_node(g, signed_node(Primitive3D::box(c[0], c[1], c[2], 10, 10, 10), false),
                  {{0, static_cast<int>(g.nodes.size()), ArcKind::Subtracting}});
  }
  return g;
}

TEST(HiddenTrim, AFlattenedBallsHiddenFlatsMirrorItsSeenOnes) {
  // A lock's body: the ball within a cube. The view sees the flats facing it, +x, +y and +z.
  const Node3D truth = Node3D::op(NodeKind::Intersection, {Node3D::leaf(Primitive3D::sphere(0, 0, 0, 2)),
                                                          Node3D::leaf(Primitive3D::box(0, 0, 0, 3.2, 3.2, 3.2))});
  const RangeEvidence evidence = evidence_of(truth);
  const PrecedenceGraph seen = ball_with_flats({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const PrecedenceGraph g = trim_hidden(seen, {}, evidence, evidence_k(evidence));
  ASSERT_EQ(g.nodes.size(), 7u);
  const Node3D tree = precedence_tree(g);
  for (const Vec3& p : {Vec3{-1.8, 0, 0}, Vec3{0, -1.8, 0}, Vec3{0, 0, -1.8}})
    EXPECT_FALSE(contains(tree, p[0], p[1], p[2])) << "past the hidden flat along " << p[0] << " " << p[1] << " " << p[2];
  EXPECT_TRUE(contains(tree, -1.5, 0, 0));
  EXPECT_TRUE(contains(tree, 0, -1.5, -1.0));
}

TEST(HiddenTrim, ASeenRoundSideIsNotFlattened) {
  // The ball flattened only underneath, where the view does not see: its seen top stays round.
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(Primitive3D::sphere(0, 0, 0, 2)),
                                                        Node3D::leaf(Primitive3D::box(0, 0, -6.6, 10, 10, 10))});
  const RangeEvidence evidence = evidence_of(truth);
  const PrecedenceGraph g = trim_hidden(ball_with_flats({{0, 0, -1}}), {}, evidence, evidence_k(evidence));
  EXPECT_EQ(g.nodes.size(), 2u);
  EXPECT_TRUE(contains(precedence_tree(g), 0, 0, 1.8));
}

TEST(HiddenTrim, NothingWithoutACamera) {
  RangeEvidence evidence = evidence_of(Node3D::leaf(kPlate));
  evidence.hidden.clear();  // what a scan without a camera gives
  const PrecedenceGraph start = graph_of({signed_node(kPlate, true), signed_node(kBall, true)});
  EXPECT_EQ(trim_hidden(start, kCuts, evidence, evidence_k(evidence)).nodes.size(), 2u);
}

}  // namespace
}  // namespace csgfit

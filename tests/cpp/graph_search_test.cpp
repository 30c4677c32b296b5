// The graph search (seed 002 as generate and test) on scans rendered from known trees: what a
// reading missed comes back from the candidates, what the views contradict goes, a cut lands
// only where it helps, and the same input gives the same graph.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "csgfit/features/range_evidence.h"
#include "csgfit/refine/range_refine.h"
#include "csgfit/search/graph_search.h"
#include "csgfit/seed/evidence_pockets.h"
#include "csgfit/seed/surface_candidates.h"
#include "range_graphs.h"

namespace csgfit {
namespace {

using testing::evidence_of;
using testing::graph_of;
using testing::looking_at;
using testing::scan_of;
using testing::signed_node;

GraphSearchOptions options_for(const RangeEvidence& evidence) {
  GraphSearchOptions o;
  o.k = evidence_k(evidence);
  return o;
}

const Primitive3D kBlock = Primitive3D::box(0, 0, 0, 8, 6, 3);
const Primitive3D kHole = Primitive3D::cylinder(1, 0.5, 0, 1.2, 5);

TEST(GraphSearch, AddsTheCutTheReadingMissed) {
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(kBlock), Node3D::leaf(kHole)});
  const RangeEvidence evidence = evidence_of(truth);
  const std::vector<SignedPrimitive> pool = {signed_node(kBlock, true), signed_node(kHole, false),
                                             signed_node(Primitive3D::sphere(-2, 1, 2, 1), true)};
  GraphSearchStats stats;
  const PrecedenceGraph g =
      search_graph(graph_of({signed_node(kBlock, true)}), pool, evidence, options_for(evidence), &stats);
  ASSERT_EQ(g.nodes.size(), 2u);
  EXPECT_FALSE(g.nodes[1].positive);
  EXPECT_EQ(g.order[1], 2) << "the hole is cut from the block (seed 002's even order)";
  EXPECT_LT(stats.score_after, stats.score_before);
  const Node3D tree = precedence_tree(g);
  EXPECT_FALSE(contains(tree, 1, 0.5, 1.4));
  EXPECT_TRUE(contains(tree, -3, -2, 1.4));
}

TEST(GraphSearch, DropsWhatTheViewsContradict) {
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kBlock));
  // A ball standing where the sensor saw nothing but empty space.
  const SignedPrimitive ball = signed_node(Primitive3D::sphere(0, 0, 3, 1.5), true);
  const PrecedenceGraph g = search_graph(graph_of({signed_node(kBlock, true), ball}), {},
                                         evidence, options_for(evidence));
  ASSERT_EQ(g.nodes.size(), 1u);
  EXPECT_EQ(g.nodes[0].primitive.kind, PrimitiveKind3D::Box);
}

TEST(GraphSearch, CutsOnlyTheSubobjectsItHelps) {
  // A low block beside a tall one: the low one is the tall one's twin cut down by a plane; the
  // same plane cutting the tall one would take away what the sensor saw of it.
  const Primitive3D low = Primitive3D::box(-3, 0, 0, 4, 4, 4);
  const Primitive3D tall = Primitive3D::box(3, 0, 0, 4, 4, 4);
  const Primitive3D above = Primitive3D::box(-3, 0, 6, 8, 8, 10);  // z > 1 over the low block
  const Node3D truth = Node3D::op(
      NodeKind::Union, {Node3D::op(NodeKind::Difference, {Node3D::leaf(low), Node3D::leaf(above)}),
                        Node3D::leaf(tall)});
  const RangeEvidence evidence = evidence_of(truth);
  const SignedPrimitive plane_cut = signed_node(Primitive3D::box(0, 0, 8, 30, 30, 14), false);
  const PrecedenceGraph g = search_graph(
      graph_of({signed_node(low, true), signed_node(tall, true)}), {plane_cut}, evidence,
      options_for(evidence));
  const Node3D tree = precedence_tree(g);
  EXPECT_EQ(tree.primitive_count(), 3u);
  EXPECT_FALSE(contains(tree, -3, 0, 1.5)) << "the low block is cut";
  EXPECT_TRUE(contains(tree, -3, 0, 0.5));
  EXPECT_TRUE(contains(tree, 3, 0, 1.5)) << "the tall one is whole";
}

TEST(EvidenceMismatch, AConjecturedCutPaysForTheHiddenMaterialItErases) {
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kBlock));
  ASSERT_FALSE(evidence.hidden.empty());
  // The block hollowed out inside its walls: the view sees the same.
  const Node3D skin = Node3D::op(NodeKind::Difference,
                                 {Node3D::leaf(kBlock), Node3D::leaf(Primitive3D::box(0, 0, -0.5, 6, 4, 1.6))});
  const Mismatch whole = evidence_mismatch(Node3D::leaf(kBlock), evidence);
  const Mismatch seen_cut = evidence_mismatch(skin, evidence, {false, false});
  const Mismatch conjectured = evidence_mismatch(skin, evidence, {false, true});
  EXPECT_LE(seen_cut.uncovered, whole.uncovered + 64) << "a cut its faces show is free in hiding";
  EXPECT_GT(conjectured.uncovered, seen_cut.uncovered + 64 * 20)
      << "a conjectured one pays for the hidden block it takes away";
}

TEST(DistanceComposer, ComposesEveryLevelAsTheTreeDoes) {
  // Leaves first, last and alone under every operation, three levels deep.
  const Node3D ball = Node3D::leaf(Primitive3D::sphere(1, 0, 0, 2));
  const Node3D inner = Node3D::op(NodeKind::Intersection, {Node3D::leaf(kBlock), ball});
  const Node3D cuts = Node3D::op(NodeKind::Union, {Node3D::leaf(kHole), ball});
  const Node3D tree = Node3D::op(
      NodeKind::Union, {Node3D::op(NodeKind::Difference, {inner, cuts, Node3D::leaf(kHole)}),
                        Node3D::leaf(Primitive3D::box(5, 0, 0, 2, 2, 2)), Node3D::op(NodeKind::Union, {ball})});
  std::vector<Vec3> points;
  for (int i = 0; i < 400; ++i) points.push_back({-6 + 0.03 * i, 0.7 * std::sin(0.1 * i), 2 * std::cos(0.07 * i)});
  std::vector<std::vector<double>> leaf_distances;
  std::vector<const double*> leaf_pointers;
  for (const Primitive3D* p : leaves(tree)) {
    leaf_distances.emplace_back(points.size());
    p->signed_distances(points.data(), points.size(), leaf_distances.back().data());
  }
  for (const auto& d : leaf_distances) leaf_pointers.push_back(d.data());
  DistanceComposer composer;
  const std::vector<double> all = composer.compose(tree, leaf_pointers, points.size());
  const std::vector<double>& tail = composer.compose_from(tree, leaf_pointers, points.size(), 150);
  for (std::size_t s = 0; s < points.size(); ++s) {
    const double want = signed_distance(tree, points[s][0], points[s][1], points[s][2]);
    EXPECT_EQ(all[s], want) << "sample " << s;
    if (s >= 150) EXPECT_EQ(tail[s], want) << "sample " << s;
  }
  const std::vector<double>& alone = composer.compose(Node3D::leaf(kBlock), {leaf_pointers[0]}, points.size());
  EXPECT_TRUE(std::equal(alone.begin(), alone.end(), leaf_distances[0].begin()));
}

TEST(GraphSearch, SameInputSameGraph) {
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(kBlock), Node3D::leaf(kHole)});
  const RangeEvidence evidence = evidence_of(truth);
  const std::vector<SignedPrimitive> pool = {signed_node(kHole, false),
                                             signed_node(Primitive3D::box(2, 2, 2, 1, 1, 1), true)};
  const auto run = [&] {
    return precedence_tree(search_graph(graph_of({signed_node(kBlock, true)}), pool, evidence,
                                        options_for(evidence)));
  };
  EXPECT_EQ(run(), run());
}

TEST(GraphSearch, GraphEditsKeepTheirIndices) {
  PrecedenceGraph g = graph_of({signed_node(kBlock, true)});
  g = with_node(g, signed_node(kHole, false), {{0, 1, ArcKind::Subtracting}});
  g = with_node(g, signed_node(Primitive3D::sphere(1, 0.5, 0, 0.5), true), {{1, 2, ArcKind::Appending}});
  EXPECT_EQ(g.order, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(g.subobjects, 1);
  std::vector<int> kept;
  const PrecedenceGraph without_block = without_node(g, 0, &kept);
  // The cut cuts nothing once the block is gone, and goes with it.
  EXPECT_EQ(kept, (std::vector<int>{2}));
  ASSERT_EQ(without_block.nodes.size(), 1u);
  EXPECT_EQ(without_block.nodes[0].primitive.kind, PrimitiveKind3D::Sphere);
}

TEST(PocketProposals, AnEdgeNotchSeenEmptyBecomesAConjecturedCut) {
  // A slot down the block's vertical edge on the silhouette: rays pass through where the
  // block alone would have material.
  const Primitive3D slot = Primitive3D::box(-4, 3, 0, 2, 2, 4);
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(kBlock), Node3D::leaf(slot)});
  const RangeEvidence evidence = evidence_of(truth);
  const std::vector<SignedPrimitive> cuts =
      pocket_proposals(graph_of({signed_node(kBlock, true)}), evidence, 0.3);
  // No plane takes the slot without the block's faces beside it: the box alone.
  ASSERT_EQ(cuts.size(), 1u) << "one cluster of empty points inside the block";
  const SignedPrimitive& cut = cuts[0];
  EXPECT_FALSE(cut.positive);
  EXPECT_TRUE(cut.conjectured);
  EXPECT_TRUE(cut.primitive.contains(-3.5, 2.5, 0)) << "the slot's middle";
  EXPECT_TRUE(cut.primitive.contains(-3.9, 2.9, 1.45)) << "reaching through the faces it meets";
  EXPECT_FALSE(cut.primitive.contains(-2, 1, 0)) << "the block's material stays";
}

TEST(PocketProposals, AChamferedEdgeSeenEmptyBecomesASlantedCut) {
  // The block's top edge along y on the +x side bevelled at 45 degrees: the bevel's plane,
  // not a box square to the block, is what takes the empty wedge and leaves the rest.
  const Primitive3D bevel =
      Primitive3D::box(4, 0, 1.5, 2 * std::sqrt(2.0), 8, 2 * std::sqrt(2.0),
                       Quaternion::from_axis_angle(0, 1, 0, 45));
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(kBlock), Node3D::leaf(bevel)});
  const RangeEvidence evidence = evidence_of(truth);
  const std::vector<SignedPrimitive> cuts =
      pocket_proposals(graph_of({signed_node(kBlock, true)}), evidence, 0.3);
  // The wedge's cluster gives its square box and the slanted cut (a sliver along the edge,
  // where rays graze both faces, may give more).
  const auto through_wedge = [](const SignedPrimitive& c) {
    return !c.primitive.rotation.is_identity(1e-6) && c.primitive.contains(3.8, 0, 1.3);
  };
  const auto it = std::find_if(cuts.begin(), cuts.end(), through_wedge);
  ASSERT_NE(it, cuts.end()) << "a slanted cut through the wedge";
  const Primitive3D& slanted = it->primitive;
  EXPECT_TRUE(it->conjectured);
  EXPECT_TRUE(slanted.contains(3.9, 2.9, 1.4)) << "all along the edge";
  EXPECT_FALSE(slanted.contains(2.5, 0, 0.5)) << "the block's material below the bevel stays";
  EXPECT_FALSE(slanted.contains(3.5, 0, -1)) << "and its side below the bevel";
  EXPECT_TRUE(cuts[0].primitive.contains(2.5, 0, 0.5)) << "where the wedge's square box cuts too deep";
}

TEST(PocketProposals, NoneWhereTheTreeAgreesWithTheViews) {
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kBlock));
  EXPECT_TRUE(pocket_proposals(graph_of({signed_node(kBlock, true)}), evidence, 0.3).empty());
}

}  // namespace
}  // namespace csgfit

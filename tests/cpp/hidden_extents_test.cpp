// Hidden faces aligned with the part's planes, on scans rendered from known trees: a plate's
// unseen underside goes down to the tangent plane of the rod along its edge, a block's to its
// own width, a face the view sees does not move, and a hole or a pocket goes through unless its
// bottom is seen; a leg's hidden top goes up to the plate it carries; a halfspace cut through a
// block's top becomes the block's own top; a cut that stops a hair short of a face goes through.
#include <gtest/gtest.h>

#include <cmath>

#include "csgfit/features/range_evidence.h"
#include "csgfit/refine/range_refine.h"
#include "csgfit/search/hidden_extents.h"
#include "range_graphs.h"

namespace csgfit {
namespace {

using testing::evidence_of;
using testing::graph_of;
using testing::kPlate;
using testing::signed_node;

// A rod of radius 0.75 along the plate's +y edge, turned by half a degree as a fit leaves it.
const Primitive3D kRod =
    Primitive3D::cylinder(0, 3, 0, 0.75, 8, Quaternion::from_axis_angle(0, 1, 0, 90.5));

// The ends along z of a block or an upright cylinder.
double bottom(const Primitive3D& p) { return p.cz - p.dims[2] / 2; }
double top(const Primitive3D& p) { return p.cz + p.dims[2] / 2; }

TEST(HiddenExtents, AnUnseenUndersideMeetsTheRodsTangentPlane) {
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), Node3D::leaf(kRod)}));
  // The plate as one view leaves it: top and sides right, the underside as high as it agrees.
  const Primitive3D thin = Primitive3D::box(0, 0, 0.225, 8, 6, 1.05);
  const PrecedenceGraph g = align_hidden_faces(
      graph_of({signed_node(thin, true), signed_node(kRod, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.75, 1e-9) << "down to the rod's lowest line";
  EXPECT_NEAR(top(g.nodes[0].primitive), 0.75, 1e-9) << "top stays";
  EXPECT_NEAR(g.nodes[0].primitive.dims[0], 8, 1e-9);
}

TEST(HiddenExtents, RodsThatAgreeOutvoteOneReadThin) {
  // Rods of radius 0.75 along all four edges, as a fit leaves them: three within 0.01, the
  // one along the near x edge read 0.6 thin. Its tangent plane is the nearest, not the part's.
  const auto rod_x = [](double y, double r) {
    return Primitive3D::cylinder(0, y, 0, r, 8, Quaternion::from_axis_angle(0, 1, 0, 90));
  };
  const auto rod_y = [](double x, double r) {
    return Primitive3D::cylinder(x, 0, 0, r, 6, Quaternion::from_axis_angle(1, 0, 0, 90));
  };
  Node3D truth = Node3D::leaf(kPlate);
  for (const Primitive3D& r : {rod_x(3, 0.75), rod_x(-3, 0.75), rod_y(4, 0.75), rod_y(-4, 0.75)})
    truth = Node3D::op(NodeKind::Union, {truth, Node3D::leaf(r)});
  const RangeEvidence evidence = evidence_of(truth);
  const Primitive3D thin = Primitive3D::box(0, 0, 0.225, 8, 6, 1.05);
  const PrecedenceGraph g = align_hidden_faces(
      graph_of({signed_node(thin, true), signed_node(rod_x(3, 0.74), true), signed_node(rod_x(-3, 0.76), true),
                signed_node(rod_y(4, 0.6), true), signed_node(rod_y(-4, 0.75), true)}),
      evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.75, 0.011) << "on the three rods' plane, not at -0.6";
}

TEST(HiddenExtents, OfPlanesAsWellSupportedTheCloserAgreementWins) {
  // Rods along both long edges, and a post whose bottom the search buried in the plate 0.08
  // above their lowest line: within the tolerance (0.1) each plane has the other two beside it.
  const auto rod = [](double y) {
    return Primitive3D::cylinder(0, y, 0, 0.75, 8, Quaternion::from_axis_angle(0, 1, 0, 90));
  };
  const Primitive3D post = Primitive3D::cylinder(0, 0, 0.415, 0.5, 2.17);
  Node3D truth = Node3D::leaf(kPlate);
  for (const Primitive3D& p : {rod(3), rod(-3), post}) truth = Node3D::op(NodeKind::Union, {truth, Node3D::leaf(p)});
  const RangeEvidence evidence = evidence_of(truth);
  const Primitive3D thin = Primitive3D::box(0, 0, 0.225, 8, 6, 1.05);
  const PrecedenceGraph g = align_hidden_faces(
      graph_of({signed_node(thin, true), signed_node(rod(3), true), signed_node(rod(-3), true),
                signed_node(post, true)}),
      evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.75, 1e-9) << "the rods' line, not the post's buried end";
}

TEST(HiddenExtents, AnUndersideTheSearchLeftTooDeepComesUpToTheRodsPlane) {
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), Node3D::leaf(kRod)}));
  // The underside at -3, which no view sees: the smallest extent, then the rod's lowest line.
  const Primitive3D deep = Primitive3D::box(0, 0, -1.125, 8, 6, 3.75);
  const PrecedenceGraph g = align_hidden_faces(
      graph_of({signed_node(deep, true), signed_node(kRod, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.75, 1e-9);
  EXPECT_NEAR(top(g.nodes[0].primitive), 0.75, 1e-9) << "top stays";
}

TEST(HiddenExtents, WithNoPlaneToGoToAFaceStaysWhereItWas) {
  // A plate alone, its underside at -3: the smallest extent has nothing to align with.
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kPlate));
  const Primitive3D deep = Primitive3D::box(0, 0, -1.125, 8, 6, 3.75);
  const PrecedenceGraph g = align_hidden_faces(graph_of({signed_node(deep, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -3, 1e-9);
}

TEST(HiddenExtents, AFaceTheViewSeesStays) {
  // A block beside the plate reaching lower: the view sees under the plate's near edges, so
  // its underside may not go down to the block's.
  const Primitive3D block = Primitive3D::box(6, 0, -0.2, 2, 2, 2.2);
  const Node3D truth = Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), Node3D::leaf(block)});
  const RangeEvidence evidence = evidence_of(truth);
  const PrecedenceGraph g = align_hidden_faces(
      graph_of({signed_node(kPlate, true), signed_node(block, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.75, 1e-9);
  EXPECT_NEAR(top(g.nodes[0].primitive), 0.75, 1e-9)
      << "nor its top up to the block's";
}

TEST(HiddenExtents, ABlockSeenAsDeepAsItIsWideBecomesACube) {
  // A 3 cube seen from above: the views allow its underside anywhere below the seen sides'
  // lower edges, and its own width is the designer's size.
  const Primitive3D cube = Primitive3D::box(0, 0, 0, 3, 3, 3);
  const RangeEvidence evidence = evidence_of(Node3D::leaf(cube));
  const Primitive3D shallow = Primitive3D::box(0, 0, 0.6, 3, 3, 1.8);
  const PrecedenceGraph g = align_hidden_faces(graph_of({signed_node(shallow, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -1.5, 1e-9);
}

TEST(HiddenExtents, AnUndersideTheSearchLeftTooDeepComesUpToTheCubesWidth) {
  // The same cube, its underside left at -3.5: the smallest extent the view allows is a hair
  // deeper than the cube is wide (the halving steps stop short), and the width is the size.
  const Primitive3D cube = Primitive3D::box(0, 0, 0, 3, 3, 3);
  const RangeEvidence evidence = evidence_of(Node3D::leaf(cube));
  const Primitive3D deep = Primitive3D::box(0, 0, -1, 3, 3, 5);
  const PrecedenceGraph g = align_hidden_faces(graph_of({signed_node(deep, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -1.5, 1e-9);
  EXPECT_NEAR(top(g.nodes[0].primitive), 1.5, 1e-9) << "top stays";
}

TEST(HiddenExtents, APlateSeenFromAboveStaysAPlate) {
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kPlate));
  const Primitive3D thin = Primitive3D::box(0, 0, 0.225, 8, 6, 1.05);
  const PrecedenceGraph g = align_hidden_faces(graph_of({signed_node(thin, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.3, 1e-9) << "six wide is no reason to be six deep";
}

TEST(HiddenExtents, WhichFacesTurnTheirBackOnTheView) {
  // Seen from azimuth 30, elevation 35: from +x, +y and above.
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kPlate));
  EXPECT_TRUE(faces_away_from_every_view(evidence, {0, 0, -0.75}, {0, 0, -1})) << "the underside";
  EXPECT_TRUE(faces_away_from_every_view(evidence, {-4, 0, 0}, {-1, 0, 0})) << "the far end";
  EXPECT_FALSE(faces_away_from_every_view(evidence, {0, 0, 0.75}, {0, 0, 1})) << "the top";
  EXPECT_FALSE(faces_away_from_every_view(evidence, {4, 0, 0}, {1, 0, 0})) << "the near end";
  // Square to the view: a grazing face may be seen.
  EXPECT_FALSE(faces_away_from_every_view(evidence, {0, 0, 0}, {-0.5, std::sqrt(0.75), 0}));
  RangeEvidence blind = evidence;
  blind.cameras.clear();
  EXPECT_FALSE(faces_away_from_every_view(blind, {0, 0, -0.75}, {0, 0, -1})) << "no camera, no view";
}

TEST(HiddenExtents, NothingWithoutACamera) {
  RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), Node3D::leaf(kRod)}));
  evidence.hidden.clear();  // what a scan without a camera gives
  const Primitive3D thin = Primitive3D::box(0, 0, 0.225, 8, 6, 1.05);
  const PrecedenceGraph g = align_hidden_faces(
      graph_of({signed_node(thin, true), signed_node(kRod, true)}), evidence);
  EXPECT_NEAR(bottom(g.nodes[0].primitive), -0.3, 1e-9);
}

TEST(HiddenExtents, LegsGoUpToTheTopTheyCarry) {
  // Four legs of radius 0.3 under the plate, inset by 1: the plate hides their upper ends.
  Node3D truth = Node3D::leaf(kPlate);
  PrecedenceGraph g = graph_of({signed_node(kPlate, true)});
  for (double x : {-3.0, 3.0})
    for (double y : {-2.0, 2.0}) {
      truth = Node3D::op(NodeKind::Union, {truth, Node3D::leaf(Primitive3D::cylinder(x, y, -2.75, 0.3, 4))});
      // As the view leaves them: ending 0.55 below the plate, where no ray reaches.
      g = with_node(g, signed_node(Primitive3D::cylinder(x, y, -3.025, 0.3, 3.45), true), {});
    }
  const PrecedenceGraph out = align_hidden_faces(g, evidence_of(truth));
  for (int i = 1; i <= 4; ++i) EXPECT_NEAR(top(out.nodes[i].primitive), -0.75, 1e-9) << "leg " << i;
}

TEST(HiddenExtents, APostBesideThePlateDoesNotReachItsPlane) {
  // A post standing beside the plate, its top seen at 0: the plate's top plane is no landing.
  const Primitive3D post = Primitive3D::cylinder(6, 0, -2, 0.4, 4);
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), Node3D::leaf(post)}));
  const PrecedenceGraph out =
      align_hidden_faces(graph_of({signed_node(kPlate, true), signed_node(post, true)}), evidence);
  EXPECT_NEAR(top(out.nodes[1].primitive), 0, 1e-12);
}

// The plate with a hole cut from it: node 0 the plate, node 1 the hole.
PrecedenceGraph plate_minus(const Primitive3D& hole) {
  return with_node(graph_of({signed_node(kPlate, true)}), signed_node(hole, false),
                   {{0, 1, ArcKind::Subtracting}});
}

TEST(HolesThrough, AHoleWhoseBottomNoViewSeesGoesThrough) {
  // Radius 0.5 through the 1.5 plate: from 35 degrees up no ray reaches its lower half.
  const Primitive3D through = Primitive3D::cylinder(1, 0.5, 0, 0.5, 2);
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Difference, {Node3D::leaf(kPlate), Node3D::leaf(through)}));
  // As the surface reading leaves it: as deep as its wall was seen.
  const Primitive3D blind = Primitive3D::cylinder(1, 0.5, 0.5, 0.5, 0.5);
  const PrecedenceGraph g = holes_through(plate_minus(blind), evidence);
  EXPECT_LT(bottom(g.nodes[1].primitive), -0.75) << "through the plate's underside";
  EXPECT_GE(top(g.nodes[1].primitive), 0.75) << "still open at the top";
  EXPECT_LE(top(g.nodes[1].primitive), 0.75 + evidence.tolerance + 1e-9) << "and no further out than through";
  EXPECT_NEAR(g.nodes[1].primitive.dims[0], 0.5, 1e-12);
}

TEST(HolesThrough, ABlindHoleWhoseBottomIsSeenStays) {
  // A wide shallow counterbore: the view sees its floor.
  const Primitive3D bore = Primitive3D::cylinder(0, 0, 0.75, 1.5, 0.6);
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Difference, {Node3D::leaf(kPlate), Node3D::leaf(bore)}));
  const PrecedenceGraph g = holes_through(plate_minus(bore), evidence);
  EXPECT_NEAR(bottom(g.nodes[1].primitive), 0.45, 1e-9);
}

TEST(HolesThrough, APocketWhoseFloorNoViewSeesGoesThrough) {
  // A slot through the plate's +y edge, read as a pocket whose floor the plate's wall hides.
  const Primitive3D slot = Primitive3D::box(0, 3, 0, 2, 2, 3);
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Difference, {Node3D::leaf(kPlate), Node3D::leaf(slot)}));
  SignedPrimitive pocket = signed_node(Primitive3D::box(0, 3, 0.25, 2, 2, 1.5), false);
  pocket.conjectured = true;
  const PrecedenceGraph g =
      with_node(graph_of({signed_node(kPlate, true)}), pocket, {{0, 1, ArcKind::Subtracting}});
  const PrecedenceGraph through = holes_through(g, evidence);
  EXPECT_LT(bottom(through.nodes[1].primitive), -0.75) << "through the plate's underside";
  EXPECT_NEAR(through.nodes[1].primitive.dims[0], 2, 1e-12) << "its seen walls stay";
}

TEST(HolesThrough, APocketWhoseFloorIsSeenStays) {
  const Primitive3D pocket = Primitive3D::box(0, 0, 0.75, 2, 2, 1);
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Difference, {Node3D::leaf(kPlate), Node3D::leaf(pocket)}));
  const PrecedenceGraph g = holes_through(plate_minus(pocket), evidence);
  EXPECT_NEAR(bottom(g.nodes[1].primitive), 0.25, 1e-9);
}

// A notch through the plate's corner, x > 2.5 and y > 1.5, and the same cut as a fit reads it:
// its top a hair under the plate's, which leaves a skin over the notch.
const Primitive3D kNotch = Primitive3D::box(4, 3, 0, 3, 3, 3);
const Primitive3D kNotchShort = Primitive3D::box(4, 3, -0.3775, 3, 3, 2.245);

TEST(ClearSkins, ACutEndingAHairUnderTheTopGoesThrough) {
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Difference, {Node3D::leaf(kPlate), Node3D::leaf(kNotch)}));
  ASSERT_LT(top(kNotchShort), 0.75);
  const PrecedenceGraph g = clear_skins(plate_minus(kNotchShort), evidence, evidence_k(evidence));
  EXPECT_GT(top(g.nodes[1].primitive), 0.75) << "no skin over the notch";
  EXPECT_LE(top(g.nodes[1].primitive), 0.75 + evidence.tolerance + 1e-9) << "and no further";
  EXPECT_NEAR(bottom(g.nodes[1].primitive), bottom(kNotchShort), 1e-12) << "its other faces stay";
}

TEST(ClearSkins, ACutUnderASeenFaceStays) {
  // The plate is whole: the view sees its top over the cut, so the skin is the part's top.
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kPlate));
  const Primitive3D under = Primitive3D::box(0, 0, -0.0025, 3, 3, 1.495);
  const PrecedenceGraph g = clear_skins(plate_minus(under), evidence, evidence_k(evidence));
  EXPECT_NEAR(top(g.nodes[1].primitive), top(under), 1e-12);
}

// A halfspace through the plate's top plane (z = 0.75), subtracted from `targets`.
PrecedenceGraph cut_at_top(PrecedenceGraph g, const std::vector<int>& targets,
                           const Primitive3D& cut = Primitive3D::box(0, 0, 10.75, 40, 40, 20)) {
  SignedPrimitive half = signed_node(cut, false);
  half.conjectured = half.halfspace = true;
  std::vector<PrecedenceArc> arcs;
  for (int t : targets) arcs.push_back({t, static_cast<int>(g.nodes.size()), ArcKind::Subtracting});
  return with_node(g, half, arcs);
}

TEST(FacesFromCuts, AHalfspaceThroughABlocksTopBecomesItsTop) {
  const RangeEvidence evidence = evidence_of(Node3D::leaf(kPlate));
  // As the search leaves it: a plate turned by two degrees, reaching above its seen top, which
  // the cut makes.
  const Primitive3D tall =
      Primitive3D::box(0, 0, 0.1, 8, 6, 1.5, Quaternion::from_axis_angle(0, 1, 0, 2));
  const PrecedenceGraph g =
      faces_from_cuts(cut_at_top(graph_of({signed_node(tall, true)}), {0}), evidence, evidence_k(evidence));
  ASSERT_EQ(g.nodes.size(), 1u) << "the cut is gone";
  const Primitive3D& plate = g.nodes[0].primitive;
  EXPECT_NEAR(std::abs(plate.rotation.matrix()[2][2]), 1, 1e-12) << "square to the cut's plane";
  EXPECT_NEAR(top(plate), 0.75, 1e-9) << "its top on that plane";
  EXPECT_NEAR(bottom(plate), 0.1 - 0.75, 0.02) << "its underside where it was";
}

TEST(FacesFromCuts, ACutThatAlsoTrimsARodStays) {
  const Primitive3D rod = Primitive3D::cylinder(0, 3, 0.5, 0.75, 8, Quaternion::from_axis_angle(0, 1, 0, 90));
  const RangeEvidence evidence =
      evidence_of(Node3D::op(NodeKind::Union, {Node3D::leaf(kPlate), Node3D::leaf(rod)}));
  const Primitive3D tall = Primitive3D::box(0, 0, 0.1, 8, 6, 1.5);
  const PrecedenceGraph g = faces_from_cuts(
      cut_at_top(graph_of({signed_node(tall, true), signed_node(rod, true)}), {0, 1}), evidence,
      evidence_k(evidence));
  EXPECT_EQ(g.nodes.size(), 3u) << "a rod has no face to take the cut";
}

TEST(FacesFromCuts, APocketIsNoFace) {
  // A cut through the top plane that takes only part of the top: a step, not the plate's face.
  const Primitive3D step = Primitive3D::box(2, 0, 10.75, 4, 40, 20);
  const Primitive3D tall = Primitive3D::box(0, 0, 0.1, 8, 6, 1.5);
  const Node3D truth = Node3D::op(NodeKind::Difference, {Node3D::leaf(tall), Node3D::leaf(step)});
  const RangeEvidence evidence = evidence_of(truth);
  const PrecedenceGraph g =
      faces_from_cuts(cut_at_top(graph_of({signed_node(tall, true)}), {0}, step), evidence, evidence_k(evidence));
  EXPECT_EQ(g.nodes.size(), 2u);
  EXPECT_NEAR(top(g.nodes[0].primitive), 0.85, 1e-12);
}

}  // namespace
}  // namespace csgfit

// Morphing (seed 000): interpolation and turns, the pair search in 2D and 3D (one structure,
// each tree matching its own shape, same seed same pair), primitives seen in one shape only,
// the animated .scad and the JSON, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "csgfit/error.h"
#include "csgfit/eval/evaluator2d.h"
#include "csgfit/io/json.h"
#include "csgfit/model/interpolate.h"
#include "csgfit/pipeline/fit_morph.h"
#include "scad_writer.h"
#include "scad_writer3d.h"

using namespace csgfit;

namespace {

// A plate with a hole, and a bar with a turned tab: topologically different shapes.
Bitmap plate_with_hole() {
  return render(Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(48, 40, 60, 44, 0)),
                                                Node::leaf(Primitive::circle(48, 40, 12))}),
                96, 80);
}

Bitmap bar_and_tab() {
  return render(Node::op(NodeKind::Union, {Node::leaf(Primitive::rectangle(48, 40, 70, 14, 0)),
                                           Node::leaf(Primitive::rectangle(60, 52, 16, 30, 20))}),
                96, 80);
}

MorphOptions quick(std::uint64_t seed = 1) {
  MorphOptions o;
  o.fit.seed = seed;
  o.fit.threads = 1;
  o.fit.time_limit = 120;  // generous: these runs end by convergence, which keeps them deterministic
  o.fit.search = SearchParams::for_morph("default");
  o.fit.search.max_stale = 400;
  o.fit.search.max_trees = 3000;
  return o;
}

std::vector<NodeKind> operators(const Node& t) {
  std::vector<NodeKind> out;
  for_each_node(t, [&](const Node& n, std::size_t) { out.push_back(n.kind); });
  return out;
}

std::vector<PrimitiveKind> kinds(const Node& t) {
  std::vector<PrimitiveKind> out;
  for (const Primitive* p : leaves(t)) out.push_back(p->kind);
  return out;
}

}  // namespace

TEST(Interpolate, EndsAreTheTreesAndTheMiddleIsBetween) {
  const Node a = Node::leaf(Primitive::rectangle(20, 20, 10, 10, 0));
  Node b = Node::leaf(Primitive::rectangle(40, 30, 20, 6, 0));
  EXPECT_EQ(interpolate(a, b, 0), a);
  EXPECT_EQ(interpolate(a, b, 1), b);
  const Primitive mid = interpolate(a, b, 0.5).primitive;
  EXPECT_DOUBLE_EQ(mid.cx, 30);
  EXPECT_DOUBLE_EQ(mid.w, 15);
  const Node other = Node::leaf(Primitive::circle(1, 1, 1));
  EXPECT_THROW(interpolate(a, other, 0.5), std::invalid_argument);
  EXPECT_THROW(interpolate(a, Node::op(NodeKind::Union, {a, b}), 0.5), std::invalid_argument);
}

TEST(Interpolate, TurnsTakeTheDirectionAskedModuloTheShapesSymmetry) {
  const Node a = Node::leaf(Primitive::rectangle(0, 0, 4, 2, 10));
  auto turned = [&](double to, TurnDirection d, PrimitiveKind kind = PrimitiveKind::Rectangle) {
    Node from = a, b = Node::leaf(Primitive::rectangle(0, 0, 4, 2, 0));
    from.primitive.kind = b.primitive.kind = kind;
    b.primitive.angle = to;
    choose_turns(from, b, d);
    return b.primitive.angle;
  };
  EXPECT_DOUBLE_EQ(turned(170, TurnDirection::Shortest), -10);  // a rectangle repeats every 180
  EXPECT_DOUBLE_EQ(turned(170, TurnDirection::CounterClockwise), 170);
  EXPECT_DOUBLE_EQ(turned(50, TurnDirection::Clockwise), -130);
  EXPECT_DOUBLE_EQ(turned(10, TurnDirection::Clockwise), 10);  // no turn stays no turn
  EXPECT_DOUBLE_EQ(turned(350, TurnDirection::Shortest, PrimitiveKind::Triangle), -10);
  EXPECT_DOUBLE_EQ(turned(190, TurnDirection::CounterClockwise, PrimitiveKind::Triangle), 190);
  EXPECT_EQ(turn_direction_from_string("cw"), TurnDirection::Clockwise);
  EXPECT_THROW(turn_direction_from_string("left"), std::invalid_argument);
}

TEST(Interpolate, A3DTurnEndsAtBsRotationTheShortWay) {
  const Primitive3D a = Primitive3D::box(0, 0, 0, 4, 2, 1, Quaternion::from_euler_deg(10, 20, 30));
  const Primitive3D b = Primitive3D::box(2, 0, 0, 2, 2, 1, Quaternion::from_euler_deg(-40, 5, 120));
  const Primitive3D end = interpolate(a, b, 1);
  const Mat3 mb = b.rotation.matrix(), me = end.rotation.matrix();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(me[i][j], mb[i][j], 1e-9);
  Vec3 axis;
  double degrees = 0;
  relative_turn(a.rotation, b.rotation, axis, degrees);
  EXPECT_LE(degrees, 180.0);
  relative_turn(a.rotation, a.rotation, axis, degrees);
  EXPECT_EQ(degrees, 0);
}

TEST(Morph2D, PairHasOneStructureAndEachTreeMatchesItsShape) {
  const Bitmap a = plate_with_hole(), b = bar_and_tab();
  const MorphResult r = morph_bitmaps(a, b, quick());
  EXPECT_EQ(operators(r.a), operators(r.b)) << structure_string(r.a) << " vs " << structure_string(r.b);
  EXPECT_EQ(kinds(r.a), kinds(r.b));
  ASSERT_EQ(r.leaves.size(), r.a.primitive_count());
  EXPECT_GT(iou(render(r.a, 96, 80), a), 0.95) << structure_string(r.a);
  EXPECT_GT(iou(render(r.b, 96, 80), b), 0.95) << structure_string(r.b);
  // The stats are those of the returned trees, and the frames at the ends are the trees.
  EXPECT_NEAR(r.stats_a.iou, iou(render(r.a, 96, 80), a), 1e-12);
  EXPECT_EQ(render(interpolate(r.a, r.b, 0), 96, 80), render(r.a, 96, 80));
  EXPECT_EQ(render(interpolate(r.a, r.b, 1), 96, 80), render(r.b, 96, 80));
  EXPECT_GT(render(interpolate(r.a, r.b, 0.5), 96, 80).count(), 0u);
}

TEST(Morph2D, SameSeedGivesTheSamePair) {
  const Bitmap a = plate_with_hole(), b = bar_and_tab();
  const MorphResult x = morph_bitmaps(a, b, quick(7)), y = morph_bitmaps(a, b, quick(7));
  ASSERT_EQ(x.stats_a.stop_reason, "converged");
  EXPECT_EQ(x.a, y.a);
  EXPECT_EQ(x.b, y.b);
}

TEST(Morph2D, ALeafSeenInOneShapeOnlyHasZeroSizeThere) {
  // A plate whose hole is absent in B: the pair needs the hole in both trees.
  const Bitmap a = plate_with_hole();
  const Bitmap b = render(Node::leaf(Primitive::rectangle(48, 40, 60, 44, 0)), 96, 80);
  const MorphResult r = morph_bitmaps(a, b, quick());
  const std::vector<const Primitive*> la = leaves(r.a), lb = leaves(r.b);
  for (std::size_t i = 0; i < r.leaves.size(); ++i) {
    if (!r.leaves[i].in_a) EXPECT_EQ(la[i]->w, 0);
    if (!r.leaves[i].in_b) EXPECT_EQ(lb[i]->w, 0);
  }
  EXPECT_GT(iou(render(r.b, 96, 80), b), 0.97);
}

TEST(Morph2D, RefusesShapesOfDifferentSizesAndEmptyShapes) {
  const Bitmap a = plate_with_hole();
  EXPECT_THROW(morph_bitmaps(a, Bitmap(40, 40), quick()), std::invalid_argument);
  EXPECT_THROW(morph_bitmaps(a, Bitmap(96, 80), quick()), std::invalid_argument);
}

TEST(MorphScad, EveryDimensionMixesItsTwoEnds) {
  const Node a = Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(40, 30, 50, 30, 0)),
                                                 Node::leaf(Primitive::circle(40, 30, 8))});
  Node b = a;
  b.children[0].primitive.w = 30;
  b.children[0].primitive.angle = -20;
  b.children[1].primitive.w = b.children[1].primitive.h = 0;
  ModelFrame frame;
  frame.source = "a.png";
  const std::string scad = to_scad_morph(a, b, frame, "b.png");
  EXPECT_NE(scad.find("morph = -1; // [-1:0.01:1]"), std::string::npos);
  EXPECT_NE(scad.find("rect_1_w = mix(rect_1_w_a, rect_1_w_b);"), std::string::npos) << scad;
  EXPECT_NE(scad.find("rect_1_angle_b = -20;"), std::string::npos) << scad;
  EXPECT_NE(scad.find("circle_2_r_b = 0;"), std::string::npos) << scad;
  EXPECT_NE(scad.find("rect_1_h = 30;"), std::string::npos) << scad;  // equal ends: one value
  EXPECT_THROW(to_scad_morph(a, Node::leaf(Primitive::circle(1, 1, 1)), frame, "b.png"), InputError);
  EXPECT_THROW(to_scad(b, frame), InputError);  // a zero size is for morphs only
}

TEST(MorphScad, A3DTurnIsOneRotateAfterAsRotation) {
  const Node3D a = Node3D::leaf(Primitive3D::box(0, 0, 0, 4, 2, 1));
  const Node3D b = Node3D::leaf(Primitive3D::box(0, 0, 0, 4, 2, 1, Quaternion::from_axis_angle(0, 0, 1, 30)));
  const std::string scad = to_scad_morph(a, b, "b.stl");
  EXPECT_NE(scad.find("box_1_turn_b = 30;"), std::string::npos) << scad;
  EXPECT_NE(scad.find("rotate(a = box_1_turn, v = [0, 0, 1])"), std::string::npos) << scad;
}

TEST(MorphJson, HoldsBothTreesAndWhereEachLeafIsSeen) {
  MorphResult r;
  r.a = Node::leaf(Primitive::rectangle(10, 10, 4, 4, 0));
  r.b = Node::leaf(Primitive::rectangle(12, 10, 4, 4, 0));
  r.b.primitive.w = r.b.primitive.h = 0;  // as the morph leaves them: unnormalised
  r.b.primitive.angle = 370;
  r.leaves = {MorphLeaf{true, false}};
  r.width = r.height = 32;
  ModelFrame frame;
  frame.source = "a.png";
  const std::string text = to_json_morph(r, frame, "b.png", TurnDirection::CounterClockwise);
  EXPECT_NE(text.find("\"source_b\": \"b.png\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"rotate\": \"ccw\""), std::string::npos);
  EXPECT_NE(text.find("\"angle\": 370.0"), std::string::npos) << text;  // the turn's end, unwrapped
  EXPECT_NE(text.find("\"in_b\": false"), std::string::npos);
  // A morph document is still A's document for readers of one tree.
  EXPECT_EQ(from_json(text).tree, r.a);
}

TEST(Morph3D, PairOfVoxelShapesHasOneStructure) {
  const VoxelGrid lattice(40, 40, 40, 0, 0, 0, 1.0);
  const VoxelGrid a = render(Node3D::leaf(Primitive3D::box(20, 20, 20, 24, 16, 12)), lattice);
  const VoxelGrid b = render(
      Node3D::op(NodeKind::Difference, {Node3D::leaf(Primitive3D::box(20, 20, 20, 30, 20, 10)),
                                         Node3D::leaf(Primitive3D::cylinder(20, 20, 20, 5, 14))}),
      lattice);
  FitOptions3D opt;
  opt.time_limit = 120;
  opt.threads = 1;
  opt.search.max_stale = 60;
  const MorphResult3D r = morph_voxels(a, b, opt);
  EXPECT_EQ(structure_string(r.a), structure_string(r.b));
  EXPECT_GT(iou(render(r.a, a), a), 0.9) << structure_string(r.a);
  EXPECT_GT(iou(render(r.b, b), b), 0.9) << structure_string(r.b);
  EXPECT_EQ(render(interpolate(r.a, r.b, 1), b), render(r.b, b));
  EXPECT_THROW(morph_voxels(a, VoxelGrid(20, 20, 20), opt), std::invalid_argument);
}

TEST(MorphJson, ReadsBackWhatItWrote) {
  MorphResult r;
  r.a = Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(40, 30, 50, 30, 10)),
                                        Node::leaf(Primitive::triangle(40, 30, 8, 6, 0, 0.5))});
  r.b = r.a;
  r.b.children[0].primitive.angle = -170;  // the end of a turn, not wrapped
  r.b.children[1].primitive.w = r.b.children[1].primitive.h = 0;
  r.leaves = {MorphLeaf{true, true}, MorphLeaf{true, false}};
  r.width = 96;
  r.height = 64;
  ModelFrame frame;
  frame.pixel_size = 0.5;
  frame.source = "a.png";
  const std::string text = to_json_morph(r, frame, "b.png", TurnDirection::Clockwise);
  ASSERT_TRUE(is_json_morph(text));
  ModelFrame f;
  std::string source_b;
  TurnDirection rotate = TurnDirection::Shortest;
  const MorphResult back = morph_from_json(text, &f, &source_b, &rotate);
  EXPECT_EQ(back.a, r.a);
  EXPECT_EQ(back.b, r.b);
  EXPECT_EQ(back.leaves[1].in_b, false);
  EXPECT_EQ(source_b, "b.png");
  EXPECT_EQ(rotate, TurnDirection::Clockwise);
  EXPECT_EQ(to_json_morph(back, f, source_b, rotate), text);
  // A tree_b of another structure is refused, naming it.
  std::string broken = text;
  broken.replace(broken.rfind("\"triangle\""), 10, "\"circle\"");
  EXPECT_THROW(morph_from_json(broken), InputError);
  EXPECT_FALSE(is_json_morph("{\"schema\": \"csgfit/1\"}"));
}

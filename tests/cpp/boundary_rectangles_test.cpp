// Boundary walls and the rectangles read off them: exact bars found at their true angle and
// size, and the greedy first tree of a rotated cross made of its two bars.
#include <gtest/gtest.h>

#include <cmath>

#include "csgfit/features/boundary_walls.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/pipeline/fit_bitmap.h"
#include "csgfit/seed/boundary_primitives.h"
#include "csgfit/seed/boundary_rectangles.h"
#include "csgfit/seed/greedy2d.h"

using namespace csgfit;

namespace {

double angle_diff(double a, double b, double period) {
  double d = std::fmod(std::fabs(a - b), period);
  return std::min(d, period - d);
}

// A plus sign of two bars turned by `angle` degrees about (64, 64).
Node cross(double angle, double length = 80, double width = 16) {
  return Node::op(NodeKind::Union, {Node::leaf(Primitive::rectangle(64, 64, length, width, angle)),
                                    Node::leaf(Primitive::rectangle(64, 64, width, length, angle))});
}

// Whether `found` holds a rectangle of `truth`'s size and place at its angle (modulo 90
// degrees, with the sides exchanged for a quarter turn).
bool holds(const std::vector<Primitive>& found, const Primitive& truth) {
  for (const Primitive& p : found) {
    const bool turned = angle_diff(p.angle, truth.angle + 90, 180) < 1.0;
    if (!turned && angle_diff(p.angle, truth.angle, 180) >= 1.0) continue;
    const double w = turned ? p.h : p.w, h = turned ? p.w : p.h;
    if (std::fabs(p.cx - truth.cx) < 0.75 && std::fabs(p.cy - truth.cy) < 0.75 &&
        std::fabs(w - truth.w) < 1.5 && std::fabs(h - truth.h) < 1.5)
      return true;
  }
  return false;
}

}  // namespace

TEST(BoundaryWalls, FindTheOrientationAndTheFourSidesOfATurnedRectangle) {
  const Primitive truth = Primitive::rectangle(60, 66, 70, 30, 30);
  Bitmap b(128, 128);
  rasterize(truth, b);
  const auto families = boundary_walls(b);
  ASSERT_FALSE(families.empty());
  EXPECT_LT(angle_diff(families.front().angle, 30, 90), 1.0);
  const double c = std::cos(30 * 3.14159265358979 / 180), s = std::sin(30 * 3.14159265358979 / 180);
  const double u = truth.cx * c + truth.cy * s, v = -truth.cx * s + truth.cy * c;
  const double expected[4] = {u + 35, v + 15, -(u - 35), -(v - 15)};
  for (int k = 0; k < 4; ++k) {
    ASSERT_FALSE(families.front().walls[k].empty()) << "side " << k;
    EXPECT_NEAR(families.front().walls[k].front().offset, expected[k], 0.5) << "side " << k;
  }
}

TEST(BoundaryRectangles, ReadTheBarsOfCrossesAtAnyAngle) {
  for (double angle : {0.0, 45.0, 17.0}) {
    const Bitmap b = render(cross(angle), 128, 128);
    const auto found = boundary_rectangles(b);
    EXPECT_TRUE(holds(found, Primitive::rectangle(64, 64, 80, 16, angle))) << angle;
    EXPECT_TRUE(holds(found, Primitive::rectangle(64, 64, 16, 80, angle))) << angle;
    // A maximal rectangle lies inside the shape: no proposal is the bounding square.
    for (const Primitive& p : found) EXPECT_LT(p.area(), 80 * 16 + 200) << angle;
  }
}

TEST(BoundaryRectangles, FindNothingOnADisc) {
  Bitmap b(128, 128);
  rasterize(Primitive::circle(64, 64, 40), b);
  EXPECT_TRUE(boundary_rectangles(b).empty());
}

TEST(GreedyCover, BuildsATurnedCrossFromItsTwoBars) {
  const Bitmap b = render(cross(45), 128, 128);
  GreedyOptions o;
  o.primitives = PrimitiveSet::parse("rectangle");
  o.proposals = boundary_rectangles(b);
  const Node tree = greedy_cover(b, o);
  EXPECT_EQ(tree.primitive_count(), 2u);
  Bitmap wrong = render(tree, 128, 128);
  Bitmap missing = b;
  missing.subtract(wrong);
  wrong.subtract(b);
  EXPECT_LT(static_cast<double>(wrong.count() + missing.count()), 0.01 * static_cast<double>(b.count()));
}

TEST(BoundaryRectangles, ReadAPlateAcrossTheHolesCutFromIt) {
  // A turned plate with one hole on its edge and one inside: more than 3 % of the plate lies
  // outside the shape, so only the holes' pixels let the plate be read.
  const Primitive plate = Primitive::rectangle(62, 64, 70, 46, 30);
  const Primitive edge_hole = Primitive::circle(62 - 35 * std::cos(0.5236), 64 - 35 * std::sin(0.5236), 12);
  const Primitive inner_hole = Primitive::circle(70, 66, 8);
  const Node part = Node::op(NodeKind::Difference,
                             {Node::leaf(plate), Node::leaf(edge_hole), Node::leaf(inner_hole)});
  const Bitmap b = render(part, 128, 128);
  EXPECT_FALSE(holds(boundary_rectangles(b), plate));
  Bitmap drilled(128, 128);
  rasterize_into(edge_hole, drilled);
  rasterize_into(inner_hole, drilled);
  EXPECT_TRUE(holds(boundary_rectangles(b, 48, 0.03, &drilled), plate));
  // boundary_primitives reads the holes' arcs first and so proposes the plate itself.
  EXPECT_TRUE(holds(boundary_primitives(b, PrimitiveSet::all()).positives, plate));
}

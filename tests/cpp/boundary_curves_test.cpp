// Arcs, ellipses and straight segments read off the boundary: exact discs, holes and half discs
// found with their centre and radius to a fraction of a pixel and the right sign, ellipses with
// their axes and turn, straight edges at their angle and offset, triangles, slots and holes from
// them, and first trees of a plate with holes built from what the boundary shows.
#include <gtest/gtest.h>

#include <cmath>

#include "csgfit/features/boundary_curves.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/seed/boundary_primitives.h"
#include "csgfit/seed/candidate_selection.h"
#include "csgfit/seed/greedy2d.h"

using namespace csgfit;

namespace {

Bitmap drawn(const Node& tree) { return render(tree, 128, 128); }

const BoundaryArc* near_circle(const std::vector<BoundaryArc>& arcs, double cx, double cy, double r) {
  for (const BoundaryArc& a : arcs)
    if (std::hypot(a.cx - cx, a.cy - cy) < 0.3 && std::fabs(a.r - r) < 0.3) return &a;
  return nullptr;
}

}  // namespace

TEST(SubpixelContour, LiesOnTheCircleWithOutwardNormals) {
  const Bitmap b = drawn(Node::leaf(Primitive::circle(60.3, 70.7, 20)));
  const auto pts = subpixel_contour(b);
  ASSERT_GT(pts.size(), 100u);
  for (const ContourPoint& p : pts) {
    const double dx = p.x - 60.3, dy = p.y - 70.7, d = std::hypot(dx, dy);
    EXPECT_NEAR(d, 20, 0.6);
    EXPECT_GT((dx * p.nx + dy * p.ny) / d, 0.95);
  }
}

TEST(BoundaryArcs, FindADiscWithItsCentreAndRadius) {
  const auto arcs = boundary_arcs(drawn(Node::leaf(Primitive::circle(60.3, 70.7, 20))));
  ASSERT_FALSE(arcs.empty());
  const BoundaryArc* a = near_circle(arcs, 60.3, 70.7, 20);
  ASSERT_NE(a, nullptr) << arcs.front().cx << " " << arcs.front().cy << " " << arcs.front().r;
  EXPECT_FALSE(a->hole);
  EXPECT_GT(a->coverage, 0.9);
}

TEST(BoundaryArcs, FindHolesAsHolesAndNoArcOnStraightEdges) {
  const Node plate = Node::op(
      NodeKind::Difference, {Node::leaf(Primitive::rectangle(64, 64, 90, 70, 0)),
                             Node::leaf(Primitive::circle(45.5, 60.2, 10)),
                             Node::leaf(Primitive::circle(85.2, 70.6, 6))});
  const auto arcs = boundary_arcs(drawn(plate));
  ASSERT_EQ(arcs.size(), 2u);
  for (const auto& [cx, cy, r] : {std::array<double, 3>{45.5, 60.2, 10}, {85.2, 70.6, 6}}) {
    const BoundaryArc* a = near_circle(arcs, cx, cy, r);
    ASSERT_NE(a, nullptr) << "hole at " << cx << ", " << cy;
    EXPECT_TRUE(a->hole);
  }
  EXPECT_TRUE(boundary_arcs(drawn(Node::leaf(Primitive::rectangle(64, 64, 70, 40, 20)))).empty());
}

TEST(BoundaryArcs, FindTheCircleOfAHalfDisc) {
  const Node half = Node::op(NodeKind::Intersection,
                             {Node::leaf(Primitive::circle(64, 64, 30)),
                              Node::leaf(Primitive::rectangle(64, 44, 80, 40, 0))});
  const auto arcs = boundary_arcs(drawn(half));
  ASSERT_FALSE(arcs.empty());
  const BoundaryArc* a = near_circle(arcs, 64, 64, 30);
  ASSERT_NE(a, nullptr);
  EXPECT_FALSE(a->hole);
  EXPECT_NEAR(a->coverage, 0.5, 0.1);
}

TEST(BoundaryArcs, NoneOnAnEmptyBitmap) {
  EXPECT_TRUE(boundary_arcs(Bitmap(32, 32)).empty());
  EXPECT_TRUE(subpixel_contour(Bitmap(32, 32)).empty());
}

TEST(BoundaryLines, FindTheFourSidesOfATurnedRectangle) {
  const Primitive truth = Primitive::rectangle(60, 66, 70, 30, 20);
  const auto lines = boundary_lines(drawn(Node::leaf(truth)));
  ASSERT_GE(lines.size(), 4u);
  const double pi = 3.14159265358979323846;
  const double half[4] = {35, 15, 35, 15};
  for (int k = 0; k < 4; ++k) {
    const double a = (20 + 90 * k) * pi / 180, nx = std::cos(a), ny = std::sin(a);
    const double offset = nx * truth.cx + ny * truth.cy + half[k];
    bool found = false;
    for (const BoundaryLine& l : lines)
      if (l.nx * nx + l.ny * ny > std::cos(0.5 * pi / 180) && std::fabs(l.offset - offset) < 0.3)
        found = found || l.t1 - l.t0 > 2 * half[(k + 1) % 4] - 6;
    EXPECT_TRUE(found) << "side " << k;
  }
}

namespace {

bool holds_triangle(const std::vector<Primitive>& found, const Primitive& truth) {
  const auto want = truth.triangle_vertices();
  for (const Primitive& p : found) {
    if (p.kind != PrimitiveKind::Triangle) continue;
    const auto got = p.triangle_vertices();
    int matched = 0;
    for (const auto& w : want)
      for (const auto& g : got) matched += std::hypot(w[0] - g[0], w[1] - g[1]) < 1.0;
    if (matched == 3) return true;
  }
  return false;
}

}  // namespace

TEST(BoundaryPrimitives, ReadATriangleAndATriangularHole) {
  const Primitive tri = Primitive::triangle(64, 60, 80, 50, 10, 0.3);
  EXPECT_TRUE(holds_triangle(boundary_primitives(drawn(Node::leaf(tri)), PrimitiveSet::all()).positives, tri));
  const Primitive cut = Primitive::triangle(64, 64, 40, 30, -25, -0.2);
  const Node plate = Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(64, 64, 100, 90, 0)),
                                                     Node::leaf(cut)});
  const BoundaryPrimitives read = boundary_primitives(drawn(plate), PrimitiveSet::all());
  EXPECT_TRUE(holds_triangle(read.holes, cut));
  EXPECT_FALSE(holds_triangle(read.positives, cut));
}

TEST(BoundaryPrimitives, GiveTheGreedyTreeOfAPlateWithTwoHolesItsProgram) {
  const Node plate = Node::op(
      NodeKind::Difference, {Node::leaf(Primitive::rectangle(64, 64, 90, 70, 0)),
                             Node::leaf(Primitive::circle(45.5, 60.2, 10)),
                             Node::leaf(Primitive::circle(85.2, 70.6, 6))});
  const Bitmap target = drawn(plate);
  const BoundaryPrimitives read = boundary_primitives(target, PrimitiveSet::all());
  GreedyOptions opt;
  opt.proposals = read.positives;
  opt.cut_proposals = read.holes;
  const Node tree = greedy_cover(target, opt);
  EXPECT_EQ(tree.primitive_count(), 3u);
  const Bitmap got = render(tree, 128, 128);
  Bitmap differ = got;
  differ.subtract(target);
  Bitmap missed = target;
  missed.subtract(got);
  EXPECT_LT(differ.count() + missed.count(), 40u);
}

TEST(BoundaryEllipses, FindATurnedEllipseAndAnEllipticHoleButNoCircle) {
  const Node part = Node::op(NodeKind::Difference,
                             {Node::leaf(Primitive::ellipse(60.3, 64.7, 40, 22, 25)),
                              Node::leaf(Primitive::ellipse(66.2, 62.1, 12, 6, 100))});
  const Bitmap b = drawn(part);
  const Contour c = contour_of(b);
  const auto found = boundary_ellipses(c, boundary_arcs(c), boundary_lines(c));
  auto near = [&](double cx, double cy, double rx, double ry, double angle, bool hole) {
    for (const BoundaryEllipse& e : found) {
      const double turn = std::fmod(std::fabs(e.angle - angle) + 180, 180);
      if (std::hypot(e.cx - cx, e.cy - cy) < 0.5 && std::fabs(e.rx - rx) < 0.5 &&
          std::fabs(e.ry - ry) < 0.5 && std::min(turn, 180 - turn) < 1.5 && e.hole == hole)
        return true;
    }
    return false;
  };
  EXPECT_TRUE(near(60.3, 64.7, 40, 22, 25, false));
  EXPECT_TRUE(near(66.2, 62.1, 12, 6, 100, true));
  const Bitmap disc = drawn(Node::leaf(Primitive::circle(64, 64, 25)));
  EXPECT_TRUE(boundary_ellipses(contour_of(disc), {}, {}).empty());
}

TEST(BoundaryPrimitives, ReadASlotAsARectangularHole) {
  const Primitive slot = Primitive::rectangle(70, 60, 30, 8, 0);
  const Node plate = Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(64, 64, 90, 60, 0)),
                                                     Node::leaf(slot)});
  const BoundaryPrimitives read = boundary_primitives(drawn(plate), PrimitiveSet::all());
  bool found = false;
  for (const Primitive& p : read.holes)
    found = found || (p.kind == PrimitiveKind::Rectangle && std::fabs(p.cx - slot.cx) < 0.75 &&
                      std::fabs(p.cy - slot.cy) < 0.75 && std::fabs(p.area() - slot.area()) < 30);
  EXPECT_TRUE(found);
}

TEST(CandidateSelection, ChoosesTheProgramAmongDistractors) {
  const Primitive plate_p = Primitive::rectangle(64, 64, 90, 70, 0);
  const Primitive hole_a = Primitive::circle(45.5, 60.2, 10), hole_b = Primitive::circle(85.2, 70.6, 6);
  const Bitmap target = drawn(Node::op(NodeKind::Difference,
                                       {Node::leaf(plate_p), Node::leaf(hole_a), Node::leaf(hole_b)}));
  const std::vector<Primitive> positives = {Primitive::circle(64, 64, 30), plate_p,
                                            Primitive::rectangle(40, 64, 40, 70, 0)};
  const std::vector<Primitive> holes = {Primitive::circle(20, 20, 8), hole_b, hole_a,
                                        Primitive::rectangle(64, 64, 10, 10, 0)};
  const auto tree = select_candidates(target, positives, holes, 25);
  ASSERT_TRUE(tree.has_value());
  EXPECT_EQ(tree->primitive_count(), 3u);
  EXPECT_EQ(render(*tree, 128, 128), target);
  // Nothing worth a primitive: no tree.
  EXPECT_FALSE(select_candidates(target, {Primitive::circle(10, 10, 3)}, {}, 25).has_value());
}

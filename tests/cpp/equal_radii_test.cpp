// One radius for the legs a designer drew alike, on scans rendered from known trees: a leg the
// fit read thick takes the others' radius with its seen side in place; a leg that is thick
// stays so; two radii alone say nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "csgfit/features/range_evidence.h"
#include "csgfit/refine/range_refine.h"
#include "csgfit/search/equal_radii.h"
#include "range_graphs.h"

namespace csgfit {
namespace {

using namespace testing;

// A table: the plate (top at 0.75) on four legs 4 long, inset by 1 from its corners.
Primitive3D leg(double x, double y, double r) { return Primitive3D::cylinder(x, y, -2.75, r, 4); }
const double kCorners[4][2] = {{3, 2}, {-3, 2}, {3, -2}, {-3, -2}};

RangeEvidence table_with_legs(const std::vector<double>& radii) {
  Node3D truth = Node3D::leaf(kPlate);
  for (int i = 0; i < 4; ++i)
    truth = Node3D::op(NodeKind::Union, {truth, Node3D::leaf(leg(kCorners[i][0], kCorners[i][1], radii[i]))});
  return evidence_of(truth);
}

// The near leg (+x, +y: the view is from azimuth 30) read `r` with the side the view sees in
// place, the others right.
PrecedenceGraph fitted_table(double r) {
  std::vector<SignedPrimitive> nodes{signed_node(kPlate, true)};
  for (int i = 0; i < 3; ++i) nodes.push_back(signed_node(leg(kCorners[i + 1][0], kCorners[i + 1][1], 0.3), true));
  const double back = r - 0.3;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  nodes.push_back(signed_node(leg(3 - back * c, 2 - back * s, r), true));
  return graph_of(nodes);
}

TEST(EqualRadii, ALegReadThickTakesTheOthersRadius) {
  const RangeEvidence evidence = table_with_legs({0.3, 0.3, 0.3, 0.3});
  const PrecedenceGraph g = equal_radii(fitted_table(0.36), evidence, evidence_k(evidence));
  const Primitive3D& near = g.nodes[4].primitive;
  EXPECT_NEAR(near.dims[0], 0.3, 1e-12);
  EXPECT_NEAR(near.cx, 3, 0.03) << "its axis back where the others' radius puts it";
  EXPECT_NEAR(near.cy, 2, 0.03);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(g.nodes[i].primitive.dims[0], 0.3);
}

TEST(EqualRadii, ALegThatIsThickStays) {
  const RangeEvidence evidence = table_with_legs({0.36, 0.3, 0.3, 0.3});
  const PrecedenceGraph g = equal_radii(fitted_table(0.36), evidence, evidence_k(evidence));
  EXPECT_EQ(g.nodes[4].primitive.dims[0], 0.36) << "the view sees it thicker";
}

TEST(EqualRadii, TwoRadiiSayNothing) {
  const RangeEvidence evidence = table_with_legs({0.3, 0.3, 0.3, 0.3});
  PrecedenceGraph g = fitted_table(0.36);
  g = without_node(g, 1);
  g = without_node(g, 1);
  const PrecedenceGraph out = equal_radii(g, evidence, evidence_k(evidence));
  EXPECT_EQ(out.nodes[2].primitive.dims[0], 0.36);
}

}  // namespace
}  // namespace csgfit

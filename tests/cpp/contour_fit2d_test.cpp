// The least-squares fit of a 2D tree's primitives to the bitmap's sub-pixel contour: exact
// shapes drawn on the canvas are recovered to a tenth of a pixel from starts half a pixel off,
// and the fit never costs a pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "csgfit/features/boundary_curves.h"
#include "csgfit/model/tree2d.h"
#include "csgfit/refine/contour_fit2d.h"

using namespace csgfit;

namespace {

// The tree's leaves after refine_to_contour from `start`, against the bitmap of `truth`.
std::vector<Primitive> refined(const Node& truth, Node start) {
  const Bitmap target = render(truth, 128, 128);
  TreeEvaluator ev(target, start);
  const std::size_t before = ev.mismatch().total();
  refine_to_contour(ev, contour_of(target).points);
  EXPECT_LE(ev.mismatch().total(), before);
  std::vector<Primitive> out;
  for (std::size_t i = 0; i < ev.leaf_count(); ++i) out.push_back(ev.leaf(i));
  return out;
}

void expect_close(const Primitive& got, const Primitive& want, double tol = 0.1) {
  EXPECT_NEAR(got.cx, want.cx, tol);
  EXPECT_NEAR(got.cy, want.cy, tol);
  EXPECT_NEAR(got.w, want.w, 2 * tol);
  EXPECT_NEAR(got.h, want.h, 2 * tol);
  EXPECT_NEAR(got.angle, want.angle, 0.3);
}

}  // namespace

TEST(ContourFit, RecoversADiscToATenthOfAPixel) {
  const Primitive disc = Primitive::circle(60.4, 63.7, 17.3);
  const auto got = refined(Node::leaf(disc), Node::leaf(Primitive::circle(61.0, 63.2, 16.8)));
  expect_close(got[0], disc);
}

TEST(ContourFit, RecoversATurnedRectangleAndEllipse) {
  const Primitive plate = Primitive::rectangle(58.3, 61.6, 60.4, 31.7, 23);
  expect_close(refined(Node::leaf(plate), Node::leaf(Primitive::rectangle(58.8, 61.2, 59.6, 32.3, 22)))[0],
               plate);
  const Primitive oval = Primitive::ellipse(64.2, 60.9, 30.6, 17.2, 35);
  expect_close(refined(Node::leaf(oval), Node::leaf(Primitive::ellipse(63.7, 61.4, 31.2, 16.7, 34)))[0],
               oval);
}

TEST(ContourFit, RecoversAPlateAndTheHoleCutFromIt) {
  // Turned: an axis-aligned edge anywhere between two pixel centres draws the same pixels, so
  // the bitmap does not know it to a tenth.
  const Primitive plate = Primitive::rectangle(64.3, 62.6, 80.4, 50.2, 12);
  const Primitive hole = Primitive::circle(50.6, 66.2, 9.7);
  const Node truth = Node::op(NodeKind::Difference, {Node::leaf(plate), Node::leaf(hole)});
  const Node start = Node::op(NodeKind::Difference, {Node::leaf(Primitive::rectangle(63.8, 63.0, 81.0, 49.6, 11.5)),
                                                     Node::leaf(Primitive::circle(51.1, 65.8, 9.2))});
  const auto got = refined(truth, start);
  expect_close(got[0], plate, 0.15);
  expect_close(got[1], hole, 0.15);
}

TEST(ContourFit, LeavesAnExactTreeAlone) {
  const Primitive disc = Primitive::circle(64.5, 64.5, 20.25);
  const Bitmap target = render(Node::leaf(disc), 128, 128);
  Node tree = Node::leaf(disc);
  TreeEvaluator ev(target, tree);
  ASSERT_EQ(ev.mismatch().total(), 0u);
  refine_to_contour(ev, contour_of(target).points);
  EXPECT_EQ(ev.mismatch().total(), 0u);
}

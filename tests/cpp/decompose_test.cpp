// Seed 003: the moment matcher on exact primitives and the recursive decomposition.
#include <gtest/gtest.h>

#include <cmath>

#include "csgfit/seed/decompose2d.h"
#include "csgfit/eval/evaluator2d.h"

using namespace csgfit;

namespace {

Bitmap raster_of(const Primitive& p, int w = 128, int h = 128) {
  Bitmap b(w, h);
  rasterize(p, b);
  return b;
}

double angle_diff(double a, double b, double period) {
  double d = std::fmod(std::fabs(a - b), period);
  return std::min(d, period - d);
}

}  // namespace

TEST(Matcher, RecognisesExactRectangles) {
  const Primitive truth = Primitive::rectangle(60.3, 70.1, 50, 22, 27);
  const auto m = match_region(raster_of(truth), PrimitiveSet::all());
  ASSERT_TRUE(m);
  EXPECT_EQ(m->primitive.kind, PrimitiveKind::Rectangle);
  EXPECT_NEAR(m->primitive.cx, truth.cx, 0.5);
  EXPECT_NEAR(m->primitive.cy, truth.cy, 0.5);
  EXPECT_NEAR(m->primitive.w, truth.w, 1.0);
  EXPECT_NEAR(m->primitive.h, truth.h, 1.0);
  EXPECT_LT(angle_diff(m->primitive.angle, truth.angle, 180), 1.5);
  EXPECT_LT(m->mismatch, 30u);
  EXPECT_LT(m->boundary_deviation, 0.01);
}

TEST(Matcher, RecognisesCirclesAndEllipses) {
  const Primitive circle = Primitive::circle(64, 64, 30);
  auto m = match_region(raster_of(circle), PrimitiveSet::all());
  ASSERT_TRUE(m);
  EXPECT_TRUE(m->primitive.kind == PrimitiveKind::Circle || m->primitive.kind == PrimitiveKind::Ellipse);
  EXPECT_NEAR(m->primitive.w, 60, 1.0);
  EXPECT_NEAR(m->primitive.h, 60, 1.0);

  const Primitive ellipse = Primitive::ellipse(70, 50, 40, 18, 120);
  m = match_region(raster_of(ellipse), PrimitiveSet::all());
  ASSERT_TRUE(m);
  EXPECT_EQ(m->primitive.kind, PrimitiveKind::Ellipse);
  EXPECT_NEAR(m->primitive.w, 80, 1.5);
  EXPECT_NEAR(m->primitive.h, 36, 1.5);
  EXPECT_LT(angle_diff(m->primitive.angle, 120, 180), 2.0);
  EXPECT_LT(m->mismatch, 40u);
}

TEST(Matcher, RecognisesIsoscelesRightAndGeneralTriangles) {
  for (double apex : {0.0, 1.0, -1.0, 0.45}) {
    const Primitive truth = Primitive::triangle(64, 60, 70, 50, 35, apex);
    const Bitmap region = raster_of(truth);
    const auto m = match_region(region, PrimitiveSet::all());
    ASSERT_TRUE(m);
    EXPECT_EQ(m->primitive.kind, PrimitiveKind::Triangle) << "apex " << apex;
    EXPECT_NEAR(m->primitive.area(), truth.area(), 0.03 * truth.area()) << "apex " << apex;
    // Fewer than 2 % of the region's pixels differ.
    EXPECT_LT(static_cast<double>(m->mismatch), 0.02 * static_cast<double>(region.count()))
        << "apex " << apex;
  }
}

TEST(Matcher, RespectsTheAllowedKinds) {
  const auto m = match_region(raster_of(Primitive::circle(64, 64, 30)),
                              PrimitiveSet::parse("rectangle"));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->primitive.kind, PrimitiveKind::Rectangle);
}

TEST(Decompose, FrameWithHoleIsBoxMinusHole) {
  Bitmap target(96, 96);
  for (int r = 10; r < 80; ++r) target.set_span(r, 12, 90);
  Bitmap hole(96, 96);
  rasterize(Primitive::circle(50, 50, 15), hole);
  target.subtract(hole);
  DecomposeOptions opt;
  opt.k = 10;
  const Node tree = decompose(target, opt);
  EXPECT_EQ(tree.kind, NodeKind::Difference) << structure_string(tree);
  EXPECT_EQ(tree.primitive_count(), 2u) << structure_string(tree);
  const Bitmap r = render(tree, 96, 96);
  EXPECT_GT(iou(r, target), 0.99);
}

TEST(Decompose, AlwaysTerminatesWithAValidAccurateTreeOnNoise) {
  // Random blobs: the worst case for matching. With k = 0 every pixel is worth keeping, so the
  // recursion must go all the way down and still reproduce the image exactly.
  std::uint64_t s = 12345;
  Bitmap target(48, 40);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 48; ++c) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      if ((s >> 33) % 3 == 0) target.set(c, r);
    }
  DecomposeOptions opt;
  opt.k = 0;
  opt.max_depth = 64;
  const Node tree = decompose(target, opt);
  EXPECT_GT(tree.primitive_count(), 0u);
  const Bitmap r = render(tree, 48, 40);
  EXPECT_GT(iou(r, target), 0.97);
}

TEST(Decompose, RejectsAnEmptyTarget) {
  EXPECT_THROW(decompose(Bitmap(8, 8), DecomposeOptions{}), std::invalid_argument);
}

// Scan conversion against analytic areas and the pointwise inside test.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "csgfit/model/primitive2d.h"

using namespace csgfit;

namespace {

Primitive random_primitive(std::mt19937_64& rng, int size) {
  std::uniform_real_distribution<double> pos(size * 0.3, size * 0.7), dim(8, size * 0.5),
      ang(0, 360), apex(-1.5, 1.5);
  switch (rng() % 4) {
    case 0: return Primitive::rectangle(pos(rng), pos(rng), dim(rng), dim(rng), ang(rng));
    case 1: return Primitive::circle(pos(rng), pos(rng), dim(rng) / 2);
    case 2: return Primitive::ellipse(pos(rng), pos(rng), dim(rng) / 2, dim(rng) / 2, ang(rng));
    default: return Primitive::triangle(pos(rng), pos(rng), dim(rng), dim(rng), ang(rng), apex(rng));
  }
}

}  // namespace

TEST(ScanConversion, AxisAlignedRectangleIsExact) {
  Bitmap b(32, 32);
  // Edges on pixel boundaries: exactly 10 x 6 pixel centres inside.
  rasterize(Primitive::rectangle(15, 13, 10, 6), b);
  EXPECT_EQ(b.count(), 60u);
  // Pixel (col 10, row 32-16=16) has centre (10.5, 15.5): inside.
  EXPECT_TRUE(b.get(10, 16));
  EXPECT_FALSE(b.get(9, 16));
}

TEST(ScanConversion, PixelCountMatchesAnalyticArea) {
  std::mt19937_64 rng(7);
  for (int i = 0; i < 400; ++i) {
    const Primitive p = random_primitive(rng, 256);
    Bitmap b(256, 256);
    rasterize(p, b);
    // Counting lattice points: the error grows with the perimeter, not the area.
    const double perimeter_bound = 2.0 * (p.w + p.h) + 8;
    EXPECT_NEAR(static_cast<double>(b.count()), p.area(), perimeter_bound)
        << "kind " << to_string(p.kind) << " w " << p.w << " h " << p.h << " angle " << p.angle;
  }
}

TEST(ScanConversion, LargeShapesConvergeToArea) {
  // Relative error shrinks as the shape grows: a 1000-pixel-wide ellipse within 0.2 %.
  const Primitive e = Primitive::ellipse(600, 500, 500, 300, 33);
  Bitmap b(1200, 1000);
  rasterize(e, b);
  EXPECT_NEAR(static_cast<double>(b.count()) / e.area(), 1.0, 2e-3);
  const Primitive t = Primitive::triangle(600, 500, 600, 500, 71, 0.4);
  rasterize(t, b);
  EXPECT_NEAR(static_cast<double>(b.count()) / t.area(), 1.0, 2e-3);
}

TEST(ScanConversion, AgreesWithPointwiseInsideTestAndSignedDistance) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < 100; ++i) {
    const Primitive p = random_primitive(rng, 64);
    Bitmap b(64, 64);
    rasterize(p, b);
    for (int r = 0; r < 64; ++r)
      for (int c = 0; c < 64; ++c) {
        const double x = c + 0.5, y = 64 - r - 0.5;
        ASSERT_EQ(b.get(c, r), p.contains(x, y)) << to_string(p.kind) << " at " << c << "," << r;
        const double d = p.signed_distance(x, y);
        // Away from the boundary, the sign of the distance says inside or out.
        if (std::fabs(d) > 1e-6) ASSERT_EQ(d < 0, b.get(c, r)) << to_string(p.kind) << " d=" << d;
      }
  }
}

TEST(ScanConversion, ShapesOffCanvasAndNaNDrawNothing) {
  Bitmap b(16, 16);
  rasterize(Primitive::circle(-50, -50, 10), b);
  EXPECT_EQ(b.count(), 0u);
  Primitive p = Primitive::rectangle(8, 8, 4, 4);
  p.cx = std::nan("");
  rasterize(p, b);
  EXPECT_EQ(b.count(), 0u);
}

TEST(ScanConversion, SpecialTrianglesOfSeed003) {
  // apex 0: isosceles; apex 1: right angle at the base's right end.
  const Primitive iso = Primitive::triangle(0, 0, 4, 3, 0, 0);
  const auto v = iso.triangle_vertices();
  EXPECT_DOUBLE_EQ(v[2][0], 0.0);
  const Primitive right = Primitive::triangle(0, 0, 4, 3, 0, 1);
  const auto u = right.triangle_vertices();
  EXPECT_DOUBLE_EQ(u[2][0], u[1][0]);
  EXPECT_DOUBLE_EQ(right.area(), 6.0);
}

TEST(Bitmap, SpansAndCountsAcrossWordBoundaries) {
  Bitmap b(130, 3);
  b.set_span(1, 60, 129);
  EXPECT_EQ(b.count(), 69u);
  EXPECT_TRUE(b.get(64, 1));
  EXPECT_FALSE(b.get(129, 1));
  const Bitmap inv = b.inverted();
  EXPECT_EQ(inv.count(), 130u * 3 - 69);
  Bitmap full(70, 2);
  full.fill();
  EXPECT_EQ(full.count(), 140u);
}

TEST(PrimitiveSet, ParsesNamesAndRejectsUnknown) {
  const PrimitiveSet s = PrimitiveSet::parse("rectangle, circle");
  EXPECT_TRUE(s.has(PrimitiveKind::Rectangle));
  EXPECT_TRUE(s.has(PrimitiveKind::Circle));
  EXPECT_FALSE(s.has(PrimitiveKind::Triangle));
  EXPECT_THROW(PrimitiveSet::parse("rectangle,hexagon"), std::invalid_argument);
  EXPECT_THROW(PrimitiveSet::parse(""), std::invalid_argument);
}

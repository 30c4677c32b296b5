// The polygonal cylinder and cone (Primitive3D::sides): OpenSCAD's cylinder($fn = n), vertex 0
// on local +x. Values worked out by hand, and the prism's distance against a construction of
// its own; primitive3d_test.cpp runs them through every kind's rasterize / contains / distance
// checks as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "bounds_checks.h"
#include "csgfit/model/primitive3d.h"

namespace csgfit {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kSqrt3 = std::sqrt(3.0);

Primitive3D with_sides(Primitive3D p, int sides) {
  p.sides = sides;
  p.normalize();
  return p;
}

TEST(PolygonalPrimitive, VolumeIsTheSectionsAreaTimesHeightOrThePrismatoids) {
  EXPECT_NEAR(with_sides(Primitive3D::cylinder(0, 0, 0, 2, 3), 6).volume(), 18 * kSqrt3, 1e-12);
  EXPECT_NEAR(with_sides(Primitive3D::cylinder(0, 0, 0, std::sqrt(2.0), 1), 4).volume(), 4, 1e-12);
  // A square pyramid on a 2 x 2 base, 3 high; and its frustum from a 4 x 4 to a 2 x 2 square.
  EXPECT_NEAR(with_sides(Primitive3D::cone(0, 0, 0, std::sqrt(2.0), 0, 3), 4).volume(), 4, 1e-12);
  EXPECT_NEAR(
      with_sides(Primitive3D::cone(0, 0, 0, 2 * std::sqrt(2.0), std::sqrt(2.0), 3), 4).volume(), 28,
      1e-12);
}

TEST(PolygonalPrimitive, VerticesLieOnTheCircleAndTheTwistTurnsThem) {
  const Primitive3D hex = with_sides(Primitive3D::cylinder(0, 0, 0, 10, 4), 6);
  auto at = [](double radius, double degrees, double z) {
    return Vec3{radius * std::cos(degrees * kPi / 180), radius * std::sin(degrees * kPi / 180), z};
  };
  auto inside = [](const Primitive3D& p, const Vec3& q) { return p.contains(q[0], q[1], q[2]); };
  // Just inside a vertex, and as far out towards an edge's middle (the apothem is 8.66).
  EXPECT_TRUE(inside(hex, at(9.9, 0, 0)));
  EXPECT_TRUE(inside(hex, at(9.9, 60, 1.9)));
  EXPECT_FALSE(inside(hex, at(9.9, 30, 0)));
  EXPECT_TRUE(inside(hex, at(8.6, 30, 0)));
  EXPECT_FALSE(inside(hex, at(8.7, 30, 0)));
  EXPECT_FALSE(inside(hex, at(5, 0, 2.1)));
  Primitive3D turned = hex;
  turned.rotation = Quaternion::from_axis_angle(0, 0, 1, 30);
  EXPECT_TRUE(inside(turned, at(9.9, 30, 0)));
  EXPECT_FALSE(inside(turned, at(9.9, 0, 0)));
  // A square pyramid 10 high: halfway up its circumradius is 5, its apothem 3.54.
  const Primitive3D pyramid = with_sides(Primitive3D::cone(0, 0, 0, 10, 0, 10), 4);
  EXPECT_TRUE(inside(pyramid, at(4.9, 0, 0)));
  EXPECT_FALSE(inside(pyramid, at(4.9, 45, 0)));
  EXPECT_TRUE(inside(pyramid, at(3.5, 45, 0)));
  EXPECT_FALSE(inside(pyramid, at(3.6, 45, 0)));
}

TEST(PolygonalPrimitive, BoundsAreThoseOfTheVertices) {
  using testing::expect_bounds;
  const Primitive3D hex = with_sides(Primitive3D::cylinder(1, 2, 3, 2, 4), 6);
  expect_bounds(hex, {-1, 2 - kSqrt3, 1}, {3, 2 + kSqrt3, 5});
  Primitive3D turned = hex;
  turned.rotation = Quaternion::from_axis_angle(0, 0, 1, 30);
  expect_bounds(turned, {1 - kSqrt3, 0, 1}, {1 + kSqrt3, 4, 5});
  // A triangle's frustum: vertex 0 reaches x = r1, the other two x = -r1 / 2.
  expect_bounds(with_sides(Primitive3D::cone(0, 0, 0, 2, 1, 2), 3), {-1, -kSqrt3, -1},
                {2, kSqrt3, 1});
}

TEST(PolygonalPrimitive, LineIntervalsCrossTheFaces) {
  const Primitive3D hex = with_sides(Primitive3D::cylinder(0, 0, 0, 2, 4), 6);
  double lo[4], hi[4];
  ASSERT_EQ(line_intervals(hex, {-5, 0, 0}, {1, 0, 0}, lo, hi), 1);
  EXPECT_NEAR(lo[0], 3, 1e-12);
  EXPECT_NEAR(hi[0], 7, 1e-12);
  ASSERT_EQ(line_intervals(hex, {0, -5, 1}, {0, 1, 0}, lo, hi), 1);
  EXPECT_NEAR(lo[0], 5 - kSqrt3, 1e-12);
  EXPECT_NEAR(hi[0], 5 + kSqrt3, 1e-12);
  EXPECT_EQ(line_intervals(hex, {-5, 1.9, 0}, {1, 0, 0}, lo, hi), 0);
}

// The prism's distance from an independent construction: the polygon's corners, an inside test
// by the sides' cross products, the nearest point of the solid by cases.
TEST(PolygonalPrimitive, PrismDistanceIsExact) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> pt(-9, 9);
  const Quaternion q = Quaternion::from_euler_deg(15, -40, 65);
  for (int n = 3; n <= 12; ++n) {
    const double r = 4, h = 6;
    const Primitive3D p = with_sides(Primitive3D::cylinder(0.5, -1, 2, r, h, q), n);
    std::vector<std::array<double, 2>> corner;
    for (int i = 0; i < n; ++i)
      corner.push_back({r * std::cos(2 * kPi * i / n), r * std::sin(2 * kPi * i / n)});
    for (int s = 0; s < 500; ++s) {
      const Vec3 l = p.to_local(pt(rng), pt(rng), pt(rng));
      bool in2 = true;
      double edge = 1e300;
      for (int i = 0; i < n; ++i) {
        const auto& a = corner[static_cast<std::size_t>(i)];
        const auto& b = corner[static_cast<std::size_t>((i + 1) % n)];
        const double ex = b[0] - a[0], ey = b[1] - a[1];
        if (ex * (l[1] - a[1]) - ey * (l[0] - a[0]) < 0) in2 = false;
        const double t =
            std::clamp(((l[0] - a[0]) * ex + (l[1] - a[1]) * ey) / (ex * ex + ey * ey), 0.0, 1.0);
        edge = std::min(edge, std::hypot(l[0] - a[0] - t * ex, l[1] - a[1] - t * ey));
      }
      const double dz = std::fabs(l[2]) - h / 2;
      double want;
      if (in2 && dz <= 0)
        want = -std::min(edge, -dz);
      else if (in2)
        want = dz;
      else
        want = std::hypot(edge, std::max(dz, 0.0));
      ASSERT_NEAR(p.signed_distance_local(l), want, 1e-9) << n << " sides";
    }
  }
}

// The frustum's face planes: with equal radii it is the prism, exactly so inside; outside the
// planes' distance is never more than the true one.
TEST(PolygonalPrimitive, FrustumDistanceIsTheLargestOfItsFacePlanes) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> pt(-9, 9);
  const Quaternion q = Quaternion::from_euler_deg(-25, 10, 40);
  const Primitive3D prism = with_sides(Primitive3D::cylinder(0, 0, 0, 4, 6, q), 7);
  const Primitive3D frustum = with_sides(Primitive3D::cone(0, 0, 0, 4, 4, 6, q), 7);
  int inside = 0;
  for (int s = 0; s < 2000; ++s) {
    const double x = pt(rng), y = pt(rng), z = pt(rng);
    const double exact = prism.signed_distance(x, y, z), planes = frustum.signed_distance(x, y, z);
    if (exact <= 0) {
      ASSERT_NEAR(planes, exact, 1e-12);
      ++inside;
    } else {
      ASSERT_LE(planes, exact + 1e-12);
      ASSERT_GT(planes, 0);
    }
  }
  EXPECT_GT(inside, 50);
  // Outside the middle of a side face the planes' distance is exact: 1 beyond a square
  // pyramid's face. Turned by 45 degrees it has a face towards +x: x = c (5 - z) with c the
  // apothem ratio cos 45, whose normal is (1, 0, c) / sqrt(1 + c^2).
  Primitive3D pyramid = with_sides(Primitive3D::cone(0, 0, 0, 10, 0, 10), 4);
  pyramid.rotation = Quaternion::from_axis_angle(0, 0, 1, 45);
  const double c = std::cos(kPi / 4), norm = std::sqrt(1 + c * c);
  EXPECT_NEAR(pyramid.signed_distance(5 * c + 1 / norm, 0, c / norm), 1, 1e-12);
}

TEST(PolygonalPrimitive, NormalIsTheFacesNotTheCircles) {
  const Primitive3D hex = with_sides(Primitive3D::cylinder(0, 0, 0, 10, 4), 6);
  // A quarter of the way along edge 0 (vertex 0 to vertex 1), one out along its normal.
  const double px = 10 + 0.25 * (5 - 10) + std::cos(kPi / 6),
               py = 0.25 * 5 * kSqrt3 + std::sin(kPi / 6);
  const Vec3 n = hex.normal_at(px, py, 0);
  EXPECT_NEAR(n[0], std::cos(kPi / 6), 1e-6);
  EXPECT_NEAR(n[1], std::sin(kPi / 6), 1e-6);
  EXPECT_NEAR(n[2], 0, 1e-6);
}

TEST(PolygonalPrimitive, NormalizeKeepsSidesForCylindersAndConesOnly) {
  EXPECT_EQ(with_sides(Primitive3D::cylinder(0, 0, 0, 1, 2), 6).sides, 6);
  EXPECT_EQ(with_sides(Primitive3D::cone(0, 0, 0, 1, 0.5, 2), 12).sides, 12);
  EXPECT_EQ(with_sides(Primitive3D::cylinder(0, 0, 0, 1, 2), 5000).sides, Primitive3D::kMaxSides);
  EXPECT_EQ(with_sides(Primitive3D::cylinder(0, 0, 0, 1, 2), 2).sides, 3);
  EXPECT_EQ(with_sides(Primitive3D::cylinder(0, 0, 0, 1, 2), -4).sides, 0);
  EXPECT_EQ(with_sides(Primitive3D::box(0, 0, 0, 1, 2, 3), 6).sides, 0);
  EXPECT_EQ(with_sides(Primitive3D::sphere(0, 0, 0, 1), 6).sides, 0);
  EXPECT_EQ(with_sides(Primitive3D::torus(0, 0, 0, 2, 1), 6).sides, 0);
}

TEST(PolygonalPrimitive, SidesAndTheTwistAreWhatMakesThePrimitive) {
  const Primitive3D round = Primitive3D::cylinder(0, 0, 0, 1, 2);
  const Primitive3D hex = with_sides(round, 6);
  EXPECT_NE(round, hex);
  EXPECT_NE(hex, with_sides(round, 8));
  EXPECT_EQ(hex, with_sides(round, 6));
  EXPECT_TRUE(is_axially_symmetric(round));
  EXPECT_FALSE(is_axially_symmetric(hex));
  EXPECT_FALSE(is_axially_symmetric(with_sides(Primitive3D::cone(0, 0, 0, 1, 0, 2), 5)));
  EXPECT_TRUE(is_axially_symmetric(hex.kind));  // the kind alone still says round
  EXPECT_FALSE(round.is_polygonal());
  EXPECT_TRUE(hex.is_polygonal());
}

}  // namespace
}  // namespace csgfit

// The rounded box (PrimitiveKind3D::RoundedBox): a box whose four edges along local z are
// rounded with radius `corner`. Values worked out by hand, and the distance against a
// construction of its own from the section's four sides and four arcs; primitive3d_test.cpp runs
// it through every kind's rasterize / contains / distance / bounds checks as well.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "bounds_checks.h"
#include "csgfit/model/primitive3d.h"

namespace csgfit {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool inside(const Primitive3D& p, double x, double y, double z) { return p.contains(x, y, z); }

TEST(RoundedBoxPrimitive, NamesAndSets) {
  EXPECT_EQ(to_string(PrimitiveKind3D::RoundedBox), "rounded_box");
  for (const char* name : {"rounded_box", "rounded-box", "roundedbox"})
    EXPECT_EQ(primitive_kind3d_from_string(name), PrimitiveKind3D::RoundedBox) << name;
  // Named on its own: "all" keeps the kinds it had (a search drawing from it fits as before).
  EXPECT_FALSE(PrimitiveSet3D::all().has(PrimitiveKind3D::RoundedBox));
  EXPECT_TRUE(PrimitiveSet3D::all().has(PrimitiveKind3D::TriangularPrism));
  EXPECT_FALSE(PrimitiveSet3D::matchable().has(PrimitiveKind3D::RoundedBox));
  EXPECT_TRUE(PrimitiveSet3D::matchable().has(PrimitiveKind3D::TriangularPrism));
  const PrimitiveSet3D some = PrimitiveSet3D::parse("box, rounded-box");
  EXPECT_TRUE(some.has(PrimitiveKind3D::RoundedBox));
  EXPECT_FALSE(some.has(PrimitiveKind3D::Sphere));
  try {
    primitive_kind3d_from_string("rounded");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rounded_box"), std::string::npos) << e.what();
  }
}

TEST(RoundedBoxPrimitive, VolumeIsTheRoundedRectanglesAreaTimesTheHeight) {
  // 20 x 10 less four 3 x 3 squares plus four quarter discs of radius 3, 4 high.
  EXPECT_NEAR(Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3).volume(),
              4 * (200 - 36 + 9 * kPi), 1e-12);
  // A stadium: a 10 x 10 square and a disc of radius 5, 2 high; a disc when the sides are equal.
  EXPECT_NEAR(Primitive3D::rounded_box(0, 0, 0, 20, 10, 2, 5).volume(), 2 * (100 + 25 * kPi),
              1e-12);
  EXPECT_NEAR(Primitive3D::rounded_box(0, 0, 0, 8, 8, 3, 4).volume(), 3 * 16 * kPi, 1e-12);
}

TEST(RoundedBoxPrimitive, ContainsTheFlatsButNotTheCornersBeyondTheArcs) {
  const Primitive3D p = Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3);
  EXPECT_TRUE(inside(p, 9.99, 0, 0));        // the flat face at x = 10
  EXPECT_TRUE(inside(p, 6.9, 4.99, 1.99));   // the flat face at y = 5, beside the corner
  EXPECT_FALSE(inside(p, 10.01, 0, 0));
  EXPECT_FALSE(inside(p, 0, 0, 2.01));
  // The corner's arc is centred at (7, 2): 45 degrees round it, 3 out, is on the surface.
  const double on = 3 / std::sqrt(2.0);
  EXPECT_TRUE(inside(p, 7 + on - 1e-6, 2 + on - 1e-6, 0));
  EXPECT_FALSE(inside(p, 7 + on + 1e-6, 2 + on + 1e-6, 0));
  EXPECT_FALSE(inside(p, -9.8, -4.8, 0));    // a box's corner, cut off
  EXPECT_TRUE(inside(p, -9.8, -2, 0));
  // Turned by 90 degrees about x: the rounded edges run along model y.
  const Primitive3D turned =
      Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3, Quaternion::from_axis_angle(1, 0, 0, 90));
  EXPECT_TRUE(inside(turned, 9.8, 1.9, -4.8 + 3));
  EXPECT_FALSE(inside(turned, 9.8, 1.9, -4.8));
  EXPECT_FALSE(inside(turned, 9.8, 0, 4.8));
  EXPECT_TRUE(inside(turned, 9.8, 0, 1.9));
}

TEST(RoundedBoxPrimitive, NormalizeKeepsTheCornerWithinHalfTheNarrowerSide) {
  auto corner = [](double sx, double sy, double c) {
    return Primitive3D::rounded_box(0, 0, 0, sx, sy, 1, c).corner;
  };
  EXPECT_EQ(corner(20, 10, 3), 3);
  EXPECT_EQ(corner(20, 10, 5), 5);
  EXPECT_EQ(corner(20, 10, 7), 5);
  EXPECT_EQ(corner(6, 10, 7), 3);
  for (double bad : {0.0, -2.0, std::numeric_limits<double>::quiet_NaN()}) {
    const double c = corner(20, 10, bad);
    EXPECT_GT(c, 0) << bad;
    EXPECT_LT(c, 1e-6) << bad;  // no rounding worth the name: the box
  }
  // A size shrinking under the corner takes the corner with it.
  Primitive3D p = Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 4);
  p.dims[1] = -6;
  p.normalize();
  EXPECT_EQ(p.dims[1], 6);
  EXPECT_EQ(p.corner, 3);
  // Its corners are round only: the polygonal corners of hull() over $fn-gons are not held.
  p.sides = 8;
  p.normalize();
  EXPECT_EQ(p.sides, 0);
  // Every other kind has no corner.
  Primitive3D box = Primitive3D::box(0, 0, 0, 2, 3, 4);
  box.corner = 1;
  box.normalize();
  EXPECT_EQ(box.corner, 0);
}

TEST(RoundedBoxPrimitive, TheCornerIsPartOfThePrimitive) {
  const Primitive3D a = Primitive3D::rounded_box(1, 2, 3, 20, 10, 4, 3);
  EXPECT_EQ(a, Primitive3D::rounded_box(1, 2, 3, 20, 10, 4, 3));
  EXPECT_NE(a, Primitive3D::rounded_box(1, 2, 3, 20, 10, 4, 2));
  Primitive3D box = a;
  box.kind = PrimitiveKind3D::Box;
  EXPECT_NE(a, box);
}

TEST(RoundedBoxPrimitive, BoundsAreTheCoresPlusTheCornerCircles) {
  using testing::expect_bounds;
  expect_bounds(Primitive3D::rounded_box(1, 2, 3, 20, 10, 4, 3), {-9, -3, 1}, {11, 7, 5});
  // Turned 90 degrees about x: local y becomes model z, local z model -y.
  expect_bounds(Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3,
                                         Quaternion::from_axis_angle(1, 0, 0, 90)),
                {-10, -2, -5}, {10, 2, 5});
  // Turned 45 degrees about z: the corner arcs, not the box's corners, reach furthest along x:
  // the corner centre (7, 2) lands at x = 9 / sqrt 2, the arc 3 beyond it.
  const double reach = 9 / std::sqrt(2.0) + 3;
  expect_bounds(Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3,
                                         Quaternion::from_axis_angle(0, 0, 1, 45)),
                {-reach, -reach, -2}, {reach, reach, 2});
}

TEST(RoundedBoxPrimitive, LineIntervalsCrossTheFlatsAndTheArcs) {
  const Primitive3D p = Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3);
  double lo[4], hi[4];
  // Through the middle along x: the flats at x = +-10.
  ASSERT_EQ(line_intervals(p, {-15, 0, 0}, {1, 0, 0}, lo, hi), 1);
  EXPECT_NEAR(lo[0], 5, 1e-12);
  EXPECT_NEAR(hi[0], 25, 1e-12);
  // At y = 4, beyond the core (|y| <= 2): the arcs, x = +-(7 + sqrt(9 - 4)).
  ASSERT_EQ(line_intervals(p, {-15, 4, 0}, {1, 0, 0}, lo, hi), 1);
  EXPECT_NEAR(lo[0], 15 - 7 - std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(hi[0], 15 + 7 + std::sqrt(5.0), 1e-12);
  // Along the diagonal through the corner centre (7, 2): the arc 3 beyond it.
  const double s = 1 / std::sqrt(2.0);
  ASSERT_EQ(line_intervals(p, {5, 0, 1}, {s, s, 0}, lo, hi), 1);
  EXPECT_NEAR(hi[0], 2 * std::sqrt(2.0) + 3, 1e-12);
  // Along z through the corner region: inside the arc or not at all.
  ASSERT_EQ(line_intervals(p, {9, 3, -10}, {0, 0, 1}, lo, hi), 1);
  EXPECT_NEAR(lo[0], 8, 1e-12);
  EXPECT_NEAR(hi[0], 12, 1e-12);
  EXPECT_EQ(line_intervals(p, {9.5, 4.5, -10}, {0, 0, 1}, lo, hi), 0);
  EXPECT_EQ(line_intervals(p, {-15, 5.5, 0}, {1, 0, 0}, lo, hi), 0);
  // A stadium, along its long axis: the discs' ends at x = +-10.
  const Primitive3D stadium = Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 5);
  ASSERT_EQ(line_intervals(stadium, {-15, 3, 0}, {1, 0, 0}, lo, hi), 1);
  EXPECT_NEAR(lo[0], 15 - 5 - 4, 1e-12);
  EXPECT_NEAR(hi[0], 15 + 5 + 4, 1e-12);
}

// The distance in the section from its boundary's pieces: four flat sides and four quarter
// arcs, each a curve of its own; the sign from contains(); then the extrusion by cases.
double reference_distance(double sx, double sy, double sz, double r, const Vec3& l) {
  const double a = sx / 2, b = sy / 2, ca = a - r, cb = b - r;
  double edge = std::numeric_limits<double>::infinity();
  const double x = l[0], y = l[1];
  edge = std::min(edge, std::hypot(std::fabs(x) - a, std::fabs(y) - std::min(std::fabs(y), cb)));
  edge = std::min(edge, std::hypot(std::fabs(y) - b, std::fabs(x) - std::min(std::fabs(x), ca)));
  for (double ex : {-ca, ca})
    for (double ey : {-cb, cb}) {
      // The arc's quarter faces away from the core: its angle range is that quadrant's.
      const double dx = x - ex, dy = y - ey;
      const bool facing = dx * ex >= 0 && dy * ey >= 0;
      if (facing) {
        edge = std::min(edge, std::fabs(std::hypot(dx, dy) - r));
      } else {
        for (double ax : {ex + (ex > 0 ? r : -r), ex})
          for (double ay : {ey, ey + (ey > 0 ? r : -r)})
            if ((ax == ex) != (ay == ey)) edge = std::min(edge, std::hypot(x - ax, y - ay));
      }
    }
  const bool in2 = std::fabs(x) <= a && std::fabs(y) <= b &&
                   (std::fabs(x) <= ca || std::fabs(y) <= cb ||
                    std::hypot(std::fabs(x) - ca, std::fabs(y) - cb) <= r);
  const double dz = std::fabs(l[2]) - sz / 2;
  if (in2 && dz <= 0) return -std::min(edge, -dz);
  if (in2) return dz;
  if (dz <= 0) return edge;
  return std::hypot(edge, dz);
}

TEST(RoundedBoxPrimitive, DistanceIsExact) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> pt(-14, 14);
  const Quaternion q = Quaternion::from_euler_deg(25, -30, 60);
  // Rounded boxes, a stadium and a disc: {sx, sy, sz, corner}.
  const double cases[4][4] = {{20, 10, 6, 3}, {12, 18, 5, 1.5}, {20, 10, 6, 5}, {10, 10, 4, 5}};
  for (const auto& c : cases) {
    const Primitive3D p = Primitive3D::rounded_box(0.5, -1, 2, c[0], c[1], c[2], c[3], q);
    int in = 0;
    for (int s = 0; s < 2000; ++s) {
      const double x = pt(rng), y = pt(rng), z = pt(rng);
      const Vec3 l = p.to_local(x, y, z);
      const double want = reference_distance(c[0], c[1], c[2], c[3], l);
      ASSERT_NEAR(p.signed_distance(x, y, z), want, 1e-9)
          << "corner " << c[3] << " at " << l[0] << ", " << l[1] << ", " << l[2];
      in += want < 0;
    }
    EXPECT_GT(in, 15) << "corner " << c[3];  // the disc fills 1.4 % of the cube sampled
  }
}

TEST(RoundedBoxPrimitive, NormalOnTheArcPointsAwayFromItsCentre) {
  const Primitive3D p = Primitive3D::rounded_box(0, 0, 0, 20, 10, 4, 3);
  // One out from the arc centred at (7, 2), 30 degrees round.
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  const Vec3 n = p.normal_at(7 + 4 * c, 2 + 4 * s, 0.5);
  EXPECT_NEAR(n[0], c, 1e-6);
  EXPECT_NEAR(n[1], s, 1e-6);
  EXPECT_NEAR(n[2], 0, 1e-6);
  EXPECT_NEAR(p.signed_distance(7 + 4 * c, 2 + 4 * s, 0.5), 1, 1e-12);
}

}  // namespace
}  // namespace csgfit

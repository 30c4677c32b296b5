// 3D primitives: volumes of their voxelisations, rasterize against contains() voxel by voxel,
// signed distances (sign, exactness), Euler angles, bounds, and rasterize timings; every kind,
// and the polygonal cylinder and cone (polygonal_primitive_test.cpp and
// rounded_box_primitive_test.cpp have their own values).
#include "csgfit/model/primitive3d.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

using namespace csgfit;

namespace {

constexpr double kPi = 3.14159265358979323846;
const PrimitiveKind3D kKinds[] = {PrimitiveKind3D::Box,      PrimitiveKind3D::Sphere,
                                  PrimitiveKind3D::Cylinder, PrimitiveKind3D::Cone,
                                  PrimitiveKind3D::Ellipsoid, PrimitiveKind3D::Torus,
                                  PrimitiveKind3D::TriangularPrism, PrimitiveKind3D::RoundedBox};

// A kind, round or with a regular polygon of 3 to 12 sides as its section.
struct Shape {
  PrimitiveKind3D kind;
  bool polygonal = false;
};
// Every kind, then the polygonal ones and the rounded box last (the older kinds draw the
// random numbers they drew before those were added).
const Shape kShapes[] = {{PrimitiveKind3D::Box},      {PrimitiveKind3D::Sphere},
                         {PrimitiveKind3D::Cylinder}, {PrimitiveKind3D::Cone},
                         {PrimitiveKind3D::Ellipsoid}, {PrimitiveKind3D::Torus},
                         {PrimitiveKind3D::TriangularPrism}, {PrimitiveKind3D::Cylinder, true},
                         {PrimitiveKind3D::Cone, true}, {PrimitiveKind3D::RoundedBox}};

Primitive3D polygonal(Primitive3D p, int sides) {
  p.sides = sides;
  return p;
}

std::string name(const Shape& shape) {
  return std::string(to_string(shape.kind)) + (shape.polygonal ? " (polygonal)" : "");
}

Quaternion random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  Quaternion q{g(rng), g(rng), g(rng), g(rng)};
  q.normalize();
  return q;
}

// A primitive of the kind with sizes in [lo, hi], centred at c, randomly rotated.
Primitive3D random_round(std::mt19937_64& rng, PrimitiveKind3D kind, double c[3], double lo,
                         double hi) {
  std::uniform_real_distribution<double> size(lo, hi), apex(-1.2, 1.2), unit(0, 1);
  const Quaternion q = random_rotation(rng);
  switch (kind) {
    case PrimitiveKind3D::Box:
      return Primitive3D::box(c[0], c[1], c[2], size(rng), size(rng), size(rng), q);
    case PrimitiveKind3D::Sphere: return Primitive3D::sphere(c[0], c[1], c[2], size(rng) / 2);
    case PrimitiveKind3D::Cylinder:
      return Primitive3D::cylinder(c[0], c[1], c[2], size(rng) / 2, size(rng), q);
    case PrimitiveKind3D::Cone: {
      // Every third cone is a full cone (one radius 0).
      const double r2 = unit(rng) < 0.33 ? 0.0 : size(rng) / 2;
      return Primitive3D::cone(c[0], c[1], c[2], size(rng) / 2, r2, size(rng), q);
    }
    case PrimitiveKind3D::Ellipsoid:
      return Primitive3D::ellipsoid(c[0], c[1], c[2], size(rng) / 2, size(rng) / 2,
                                    size(rng) / 2, q);
    case PrimitiveKind3D::Torus: {
      const double R = size(rng) / 2;
      return Primitive3D::torus(c[0], c[1], c[2], R, R * (0.15 + 0.8 * unit(rng)), q);
    }
    case PrimitiveKind3D::TriangularPrism:
      return Primitive3D::prism(c[0], c[1], c[2], size(rng), size(rng), size(rng), apex(rng), q);
    case PrimitiveKind3D::RoundedBox: {
      // Every fourth is a stadium (the corner half the narrower side).
      const double sx = size(rng), sy = size(rng), sz = size(rng);
      const double most = std::min(sx, sy) / 2;
      const double corner = unit(rng) < 0.25 ? most : most * (0.05 + 0.9 * unit(rng));
      return Primitive3D::rounded_box(c[0], c[1], c[2], sx, sy, sz, corner, q);
    }
    case PrimitiveKind3D::Nurbs: break;  // nurbs_terminal_test.cpp
  }
  return {};
}

Primitive3D random_primitive(std::mt19937_64& rng, const Shape& shape, double c[3], double lo,
                             double hi) {
  const Primitive3D p = random_round(rng, shape.kind, c, lo, hi);
  return shape.polygonal ? polygonal(p, 3 + static_cast<int>(rng() % 10)) : p;
}

}  // namespace

TEST(Quaternion, EulerAnglesFollowOpenScadRotate) {
  auto rx = [](double a) { return Quaternion::from_axis_angle(1, 0, 0, a); };
  auto ry = [](double a) { return Quaternion::from_axis_angle(0, 1, 0, a); };
  auto rz = [](double a) { return Quaternion::from_axis_angle(0, 0, 1, a); };
  // rotate([90, 0, 0]) turns +y into +z.
  const Mat3 m = Quaternion::from_euler_deg(90, 0, 0).matrix();
  EXPECT_NEAR(m[2][1], 1, 1e-12);
  // rotate([0, 0, 90]) turns +x into +y.
  EXPECT_NEAR(Quaternion::from_euler_deg(0, 0, 90).matrix()[1][0], 1, 1e-12);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ang(-180, 180), tilt(-89, 89);
  for (int i = 0; i < 500; ++i) {
    const double a = ang(rng), b = tilt(rng), c = ang(rng);
    Quaternion expected = rz(c) * ry(b) * rx(a);
    expected.normalize();
    const Quaternion q = Quaternion::from_euler_deg(a, b, c);
    const Vec3 e = q.euler_deg();
    EXPECT_NEAR(e[0], a, 1e-7);
    EXPECT_NEAR(e[1], b, 1e-7);
    EXPECT_NEAR(e[2], c, 1e-7);
    const Mat3 m1 = q.matrix(), m2 = expected.matrix();
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) EXPECT_NEAR(m1[r][col], m2[r][col], 1e-12);
    // Any rotation survives the round trip through Euler angles.
    const Quaternion rnd = random_rotation(rng);
    const Vec3 er = rnd.euler_deg();
    const Mat3 back = Quaternion::from_euler_deg(er[0], er[1], er[2]).matrix();
    const Mat3 orig = rnd.matrix();
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) EXPECT_NEAR(back[r][col], orig[r][col], 1e-9);
  }
  // Gimbal lock still round-trips.
  for (double b : {90.0, -90.0}) {
    const Quaternion q = Quaternion::from_euler_deg(30, b, 10);
    const Vec3 e = q.euler_deg();
    const Mat3 back = Quaternion::from_euler_deg(e[0], e[1], e[2]).matrix();
    const Mat3 orig = q.matrix();
    for (int r = 0; r < 3; ++r)
      for (int col = 0; col < 3; ++col) EXPECT_NEAR(back[r][col], orig[r][col], 1e-9);
  }
}

TEST(Primitive3D, NamesRoundTrip) {
  for (PrimitiveKind3D k : kKinds) EXPECT_EQ(primitive_kind3d_from_string(to_string(k)), k);
  EXPECT_EQ(primitive_kind3d_from_string("cube"), PrimitiveKind3D::Box);
  EXPECT_THROW(primitive_kind3d_from_string("blob"), std::invalid_argument);
}

TEST(Primitive3D, ExactVolumes) {
  EXPECT_DOUBLE_EQ(Primitive3D::box(0, 0, 0, 2, 3, 4).volume(), 24);
  EXPECT_DOUBLE_EQ(Primitive3D::sphere(0, 0, 0, 2).volume(), 32.0 / 3.0 * kPi);
  EXPECT_DOUBLE_EQ(Primitive3D::cylinder(0, 0, 0, 2, 5).volume(), 20 * kPi);
  EXPECT_DOUBLE_EQ(Primitive3D::cone(0, 0, 0, 3, 0, 4).volume(), 12 * kPi);
  EXPECT_DOUBLE_EQ(Primitive3D::cone(0, 0, 0, 2, 1, 3).volume(), 7 * kPi);
  EXPECT_DOUBLE_EQ(Primitive3D::ellipsoid(0, 0, 0, 1, 2, 3).volume(), 8 * kPi);
  EXPECT_DOUBLE_EQ(Primitive3D::torus(0, 0, 0, 5, 2).volume(), 40 * kPi * kPi);
  EXPECT_DOUBLE_EQ(Primitive3D::prism(0, 0, 0, 4, 3, 5, 0.3).volume(), 30);
}

TEST(Primitive3D, NormalizeKeepsShapesValid) {
  Primitive3D t = Primitive3D::torus(0, 0, 0, 2, 5);  // r > R cannot be revolved
  EXPECT_DOUBLE_EQ(t.dims[1], 2);
  Primitive3D s = Primitive3D::sphere(0, 0, 0, -3);
  EXPECT_DOUBLE_EQ(s.dims[0], 3);
  EXPECT_DOUBLE_EQ(s.dims[2], 3);
  Primitive3D c = Primitive3D::cylinder(0, 0, 0, 2, 4, Quaternion{2, 0, 0, 0});
  EXPECT_TRUE(c.rotation.is_identity());
  EXPECT_DOUBLE_EQ(c.rotation.w, 1);
  EXPECT_DOUBLE_EQ(c.dims[1], 2);
}

// Large primitives (tens of voxels across) are within ~1 % of their analytic volume.
TEST(Primitive3D, VoxelCountMatchesVolume) {
  std::mt19937_64 rng(11);
  VoxelGrid g(128, 128, 128, -64, -64, -64, 1.0);
  for (const Shape& shape : kShapes) {
    for (int trial = 0; trial < 4; ++trial) {
      double c[3] = {0.3, -0.7, 0.2};
      Primitive3D p;
      // Large (a tube of >= 10 voxels for tori) and inside the grid.
      for (;;) {
        p = random_primitive(rng, shape, c, 40, 110);
        const Bounds3 b = p.bounds();
        const bool fits = *std::min_element(b.lo.begin(), b.lo.end()) > -63 &&
                          *std::max_element(b.hi.begin(), b.hi.end()) < 63;
        if (fits && (shape.kind != PrimitiveKind3D::Torus || p.dims[1] >= 10)) break;
      }
      rasterize(p, g);
      const double count = static_cast<double>(g.count());
      EXPECT_NEAR(count / p.volume(), 1.0, 0.01) << name(shape) << " trial " << trial;
    }
  }
}

// rasterize() sets exactly the voxels whose centres contains() accepts.
TEST(Primitive3D, RasterizeAgreesWithContainsOnEveryVoxel) {
  std::mt19937_64 rng(5);
  VoxelGrid g(70, 40, 36, -2.5, 1.0, 0.25, 0.75);
  for (const Shape& shape : kShapes) {
    std::size_t checked = 0;
    for (int trial = 0; trial < 25; ++trial) {
      std::uniform_real_distribution<double> px(-8, 52), py(-2, 30), pz(-3, 28);
      double c[3] = {px(rng), py(rng), pz(rng)};
      const Primitive3D p = random_primitive(rng, shape, c, 2, 30);
      rasterize(p, g);
      std::size_t inside = 0;
      for (int k = 0; k < g.nz(); ++k)
        for (int j = 0; j < g.ny(); ++j)
          for (int i = 0; i < g.nx(); ++i) {
            const bool want = p.contains(g.center_x(i), g.center_y(j), g.center_z(k));
            inside += want;
            ASSERT_EQ(g.get(i, j, k), want)
                << name(shape) << " trial " << trial << " voxel " << i << "," << j << ","
                << k << " sd " << p.signed_distance(g.center_x(i), g.center_y(j), g.center_z(k));
          }
      checked += inside;
    }
    EXPECT_GT(checked, 1000u) << name(shape);  // the test saw real shapes
  }
}

TEST(Primitive3D, AxisAlignedShapesOnTheGrid) {
  VoxelGrid g(20, 20, 20);
  // Faces between voxel centres: exactly 4 x 6 x 8 voxels.
  rasterize(Primitive3D::box(10, 10, 10, 4, 6, 8), g);
  EXPECT_EQ(g.count(), 4u * 6 * 8);
  EXPECT_TRUE(g.get(8, 7, 6));
  EXPECT_FALSE(g.get(7, 7, 6));
  // Outside the grid: nothing, and no crash.
  rasterize(Primitive3D::sphere(100, 10, 10, 3), g);
  EXPECT_EQ(g.count(), 0u);
  Primitive3D nan = Primitive3D::sphere(10, 10, 10, 3);
  nan.cx = std::nan("");
  rasterize(nan, g);
  EXPECT_EQ(g.count(), 0u);
  // Partly outside: clipped.
  rasterize(Primitive3D::box(0, 10, 10, 4, 4, 4), g);
  EXPECT_EQ(g.count(), 2u * 4 * 4);
}

TEST(Primitive3D, SignedDistanceSignAgreesWithContains) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> pt(-20, 20);
  for (const Shape& shape : kShapes) {
    int inside = 0;
    for (int trial = 0; trial < 40; ++trial) {
      double c[3] = {0, 0, 0};
      const Primitive3D p = random_primitive(rng, shape, c, 3, 30);
      for (int s = 0; s < 500; ++s) {
        const double x = pt(rng), y = pt(rng), z = pt(rng);
        const double d = p.signed_distance(x, y, z);
        if (std::fabs(d) < 1e-9) continue;
        ASSERT_EQ(d < 0, p.contains(x, y, z)) << name(shape) << " d=" << d;
        inside += d < 0;
      }
    }
    EXPECT_GT(inside, 100) << name(shape);
  }
}

TEST(Primitive3D, SignedDistancesOfManyPointsAreEachPointsOwn) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> pt(-20, 20);
  for (const Shape& shape : kShapes) {
    double c[3] = {1, -2, 3};
    const Primitive3D p = random_primitive(rng, shape, c, 3, 30);
    std::vector<Vec3> points(300);
    for (Vec3& q : points) q = {pt(rng), pt(rng), pt(rng)};
    std::vector<double> batch(points.size());
    p.signed_distances(points.data(), points.size(), batch.data());
    for (std::size_t i = 0; i < points.size(); ++i)
      ASSERT_EQ(batch[i], p.signed_distance(points[i][0], points[i][1], points[i][2]))
          << name(shape);
  }
}

// Independent closest-point constructions for box, sphere, cylinder and torus.
TEST(Primitive3D, SignedDistanceIsExactForBoxSphereCylinderTorus) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> pt(-12, 12);
  const Quaternion q = Quaternion::from_euler_deg(20, -35, 70);
  const double c[3] = {1.5, -2, 0.5};
  auto check = [&](const Primitive3D& p, auto reference) {
    for (int s = 0; s < 3000; ++s) {
      const double x = pt(rng), y = pt(rng), z = pt(rng);
      const Vec3 l = p.to_local(x, y, z);
      ASSERT_NEAR(p.signed_distance(x, y, z), reference(l), 1e-9) << to_string(p.kind);
    }
  };
  const Primitive3D box = Primitive3D::box(c[0], c[1], c[2], 6, 4, 10, q);
  check(box, [](const Vec3& l) {
    const double h[3] = {3, 2, 5};
    double cl[3], out2 = 0, in = 1e300;
    bool inside = true;
    for (int i = 0; i < 3; ++i) {
      cl[i] = std::clamp(l[i], -h[i], h[i]);
      out2 += (l[i] - cl[i]) * (l[i] - cl[i]);
      if (std::fabs(l[i]) > h[i]) inside = false;
      in = std::min(in, h[i] - std::fabs(l[i]));
    }
    return inside ? -in : std::sqrt(out2);
  });
  const Primitive3D sphere = Primitive3D::sphere(c[0], c[1], c[2], 4);
  check(sphere, [](const Vec3& l) { return std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) - 4; });
  const Primitive3D cyl = Primitive3D::cylinder(c[0], c[1], c[2], 3, 8, q);
  check(cyl, [](const Vec3& l) {
    const double rho = std::hypot(l[0], l[1]);
    const bool inside = rho <= 3 && std::fabs(l[2]) <= 4;
    if (inside) return -std::min(3 - rho, 4 - std::fabs(l[2]));
    // Closest point of the solid: clamp radius and height.
    const double cr = std::min(rho, 3.0), cz = std::clamp(l[2], -4.0, 4.0);
    return std::hypot(rho - cr, l[2] - cz);
  });
  const Primitive3D torus = Primitive3D::torus(c[0], c[1], c[2], 6, 2, q);
  check(torus, [](const Vec3& l) {
    // Closest point on the centre circle, then the tube.
    const double rho = std::hypot(l[0], l[1]);
    return std::sqrt((rho - 6) * (rho - 6) + l[2] * l[2]) - 2;
  });
}

// For an exact distance, stepping -d along the normal lands on the surface, and the distance
// is 1-Lipschitz; cone, prism, the polygonal cylinder and the rounded box are checked this way
// (and box, cylinder, torus again).
TEST(Primitive3D, SignedDistanceProjectsOntoTheSurface) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> pt(-15, 15);
  for (const Shape& shape : kShapes) {
    // Bounds, not exact: the ellipsoid's, and the pyramid frustum's face planes.
    if (shape.kind == PrimitiveKind3D::Ellipsoid ||
        (shape.polygonal && shape.kind == PrimitiveKind3D::Cone))
      continue;
    for (int trial = 0; trial < 10; ++trial) {
      double c[3] = {0, 0, 0};
      const Primitive3D p = random_primitive(rng, shape, c, 4, 20);
      for (int s = 0; s < 300; ++s) {
        const double x = pt(rng), y = pt(rng), z = pt(rng);
        const double d = p.signed_distance(x, y, z);
        const Vec3 n = p.normal_at(x, y, z);
        if (n == Vec3{0, 0, 0}) continue;
        const double on = p.signed_distance(x - d * n[0], y - d * n[1], z - d * n[2]);
        ASSERT_NEAR(on, 0, 1e-4 * (1 + std::fabs(d))) << name(shape) << " d=" << d;
        const double x2 = pt(rng), y2 = pt(rng), z2 = pt(rng);
        const double dist = std::sqrt((x - x2) * (x - x2) + (y - y2) * (y - y2) + (z - z2) * (z - z2));
        ASSERT_LE(std::fabs(d - p.signed_distance(x2, y2, z2)), dist + 1e-9) << name(shape);
      }
    }
  }
}

TEST(Primitive3D, EllipsoidDistanceIsZeroOnTheSurfaceAndExactForSpheres) {
  const Quaternion q = Quaternion::from_euler_deg(10, 20, 30);
  const Primitive3D e = Primitive3D::ellipsoid(1, 2, 3, 2, 3, 5, q);
  const Mat3 m = q.matrix();
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g(0, 1);
  for (int i = 0; i < 200; ++i) {
    double v[3] = {g(rng), g(rng), g(rng)};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double l[3] = {2 * v[0] / n, 3 * v[1] / n, 5 * v[2] / n};
    const double x = 1 + m[0][0] * l[0] + m[0][1] * l[1] + m[0][2] * l[2];
    const double y = 2 + m[1][0] * l[0] + m[1][1] * l[1] + m[1][2] * l[2];
    const double z = 3 + m[2][0] * l[0] + m[2][1] * l[1] + m[2][2] * l[2];
    EXPECT_NEAR(e.signed_distance(x, y, z), 0, 1e-12);
  }
  const Primitive3D round = Primitive3D::ellipsoid(0, 0, 0, 3, 3, 3);
  EXPECT_NEAR(round.signed_distance(5, 0, 0), 2, 1e-12);
  EXPECT_NEAR(round.signed_distance(0, 1, 0), -2, 1e-12);
}

TEST(Primitive3D, BoundsAreTightAndHoldEveryVoxel) {
  std::mt19937_64 rng(31);
  for (const Shape& shape : kShapes) {
    for (int trial = 0; trial < 20; ++trial) {
      double c[3] = {0, 0, 0};
      const Primitive3D p = random_primitive(rng, shape, c, 4, 20);
      const Bounds3 b = p.bounds();
      // A fine grid over the bounds, one voxel of margin: the set voxels reach within two
      // voxels of every face (tight) and none lies outside (sound).
      const double vs = 0.25;
      const int n[3] = {static_cast<int>((b.hi[0] - b.lo[0]) / vs) + 3,
                        static_cast<int>((b.hi[1] - b.lo[1]) / vs) + 3,
                        static_cast<int>((b.hi[2] - b.lo[2]) / vs) + 3};
      VoxelGrid g(n[0], n[1], n[2], b.lo[0] - vs, b.lo[1] - vs, b.lo[2] - vs, vs);
      rasterize(p, g);
      int lo[3] = {1 << 30, 1 << 30, 1 << 30}, hi[3] = {-1, -1, -1};
      for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
          for (int i = 0; i < n[0]; ++i)
            if (g.get(i, j, k)) {
              const int idx[3] = {i, j, k};
              for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], idx[a]), hi[a] = std::max(hi[a], idx[a]);
            }
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(lo[a], 1) << name(shape);
        EXPECT_LE(hi[a], n[a] - 2) << name(shape);
        EXPECT_LE(lo[a], 3) << name(shape) << " axis " << a;
        EXPECT_GE(hi[a], n[a] - 4) << name(shape) << " axis " << a;
      }
    }
  }
}

// Timing on a 128^3 grid (printed; the bound only catches gross regressions).
TEST(Primitive3D, RasterizeTimingOn128Cube) {
  VoxelGrid g(128, 128, 128, 0, 0, 0, 1.0);
  const Quaternion q = Quaternion::from_euler_deg(17, 29, 41);
  const Primitive3D prims[] = {
      Primitive3D::box(64, 64, 64, 70, 50, 60, q),
      Primitive3D::sphere(64, 64, 64, 40),
      Primitive3D::cylinder(64, 64, 64, 30, 80, q),
      Primitive3D::cone(64, 64, 64, 35, 10, 80, q),
      Primitive3D::ellipsoid(64, 64, 64, 50, 35, 25, q),
      Primitive3D::torus(64, 64, 64, 38, 14, q),
      Primitive3D::prism(64, 64, 64, 70, 60, 50, 0.3, q),
      polygonal(Primitive3D::cylinder(64, 64, 64, 30, 80, q), 6),
      polygonal(Primitive3D::cone(64, 64, 64, 35, 10, 80, q), 12),
      Primitive3D::rounded_box(64, 64, 64, 80, 50, 40, 12, q),
  };
  for (const Primitive3D& p : prims) {
    rasterize(p, g);  // warm up
    const int reps = 50;
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) rasterize(p, g);
    const double us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
        reps;
    std::printf("rasterize %-9s %4d sides 128^3: %8.1f us  (%zu voxels)\n",
                std::string(to_string(p.kind)).c_str(), p.sides, us, g.count());
    EXPECT_LT(us, 20000.0) << to_string(p.kind);
  }
}

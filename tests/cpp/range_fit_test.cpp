// Seed 002's stages on inputs whose answer is known: synthetic surface patches, hand-made
// precedence configurations, and whole range images rendered from a known tree.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "csgfit/error.h"
#include "csgfit/eval/range_view.h"
#include "csgfit/features/surface_detect.h"
#include "csgfit/io/range_read.h"
#include "csgfit/pipeline/fit_range.h"
#include "csgfit/seed/precedence_graph.h"
#include "csgfit/seed/range_primitives.h"
#include "range_scans.h"

namespace csgfit {
namespace {

namespace fs = std::filesystem;
using testing::scan_of;
const fs::path kRange = fs::path(CSGFIT_SOURCE_DIR) / ".." / "shared" / "benchmarks" / "range";

struct Cloud {
  std::vector<Vec3> points, normals;
  void add(const Vec3& p, const Vec3& n) { points.push_back(p), normals.push_back(n); }
};

Vec3 unit(Vec3 v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

// Points on a sphere cap seen from +z; `outward` normals point away from the centre (a ball),
// else towards it (a spherical hollow).
Cloud sphere_cap(const Vec3& c, double r, bool outward) {
  Cloud cloud;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 120; ++j) {
      const double polar = 1.2 * i / 59, az = 2 * M_PI * j / 120;
      const Vec3 n{std::sin(polar) * std::cos(az), std::sin(polar) * std::sin(az), std::cos(polar)};
      const Vec3 p{c[0] + r * n[0], c[1] + r * n[1], c[2] + r * n[2]};
      cloud.add(p, outward ? n : Vec3{-n[0], -n[1], -n[2]});
    }
  return cloud;
}

// The largest patch (RANSAC extracts it first); an empty detection fails the test.
SurfacePatch largest(const std::vector<SurfacePatch>& patches) {
  if (patches.empty()) {
    ADD_FAILURE() << "no patch detected";
    return {};
  }
  return patches.front();
}

TEST(SurfaceDetect, PlaneIsFoundWithItsOutwardNormal) {
  Cloud cloud;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) cloud.add({i * 0.1, j * 0.1, 2.0}, {0, 0, 1});
  const SurfacePatch p = largest(detect_surfaces(cloud.points, cloud.normals, {}, 1));
  EXPECT_EQ(p.kind, SurfaceKind::Plane);
  EXPECT_NEAR(p.axis[2], 1.0, 1e-9);
  EXPECT_NEAR(p.point[2], 2.0, 1e-9);
  EXPECT_EQ(p.points.size(), cloud.points.size());
}

TEST(SurfaceDetect, SphereCapGivesCentreRadiusAndConvexity) {
  for (bool outward : {true, false}) {
    const Cloud cloud = sphere_cap({1, 2, 3}, 1.5, outward);
    const SurfacePatch p = largest(detect_surfaces(cloud.points, cloud.normals, {}, 1));
    ASSERT_EQ(p.kind, SurfaceKind::Sphere);
    EXPECT_NEAR(p.radius, 1.5, 1e-6);
    EXPECT_NEAR(p.point[0], 1, 1e-6);
    EXPECT_NEAR(p.point[2], 3, 1e-6);
    EXPECT_EQ(p.convex, outward) << "a ball is convex, a hollow concave (seed 002, Sec. 3.3)";
  }
}

TEST(SurfaceDetect, CylinderGivesAxisRadiusAndConvexity) {
  // Half a cylinder of radius 0.8 about the axis through (0, 1, 0) along (1, 1, 0) / sqrt 2.
  const Vec3 a = unit({1, 1, 0}), u{0, 0, 1}, w = unit({1, -1, 0});
  for (bool outward : {true, false}) {
    Cloud cloud;
    for (int i = 0; i < 80; ++i)
      for (int j = 0; j < 60; ++j) {
        const double t = -2 + 4.0 * i / 79, phi = M_PI * j / 59;
        const Vec3 n{std::cos(phi) * u[0] + std::sin(phi) * w[0], std::cos(phi) * u[1] + std::sin(phi) * w[1],
                     std::cos(phi) * u[2] + std::sin(phi) * w[2]};
        const Vec3 p{t * a[0] + 0.8 * n[0], 1 + t * a[1] + 0.8 * n[1], t * a[2] + 0.8 * n[2]};
        cloud.add(p, outward ? n : Vec3{-n[0], -n[1], -n[2]});
      }
    const SurfacePatch p = largest(detect_surfaces(cloud.points, cloud.normals, {}, 1));
    ASSERT_EQ(p.kind, SurfaceKind::Cylinder);
    EXPECT_NEAR(p.radius, 0.8, 1e-6);
    EXPECT_NEAR(std::abs(p.axis[0] * a[0] + p.axis[1] * a[1]), 1.0, 1e-6);
    EXPECT_EQ(p.convex, outward);
  }
}

TEST(SurfaceDetect, ConeAndTorusAreTheirOwnKinds) {
  Cloud cone;  // apex at the origin, axis +z, half-angle 30 degrees, z in [1, 3]
  const double half = M_PI / 6;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 120; ++j) {
      const double z = 1 + 2.0 * i / 59, az = 2 * M_PI * j / 120, r = z * std::tan(half);
      cone.add({r * std::cos(az), r * std::sin(az), z},
               {std::cos(half) * std::cos(az), std::cos(half) * std::sin(az), -std::sin(half)});
    }
  const SurfacePatch c = largest(detect_surfaces(cone.points, cone.normals, {}, 1));
  ASSERT_EQ(c.kind, SurfaceKind::Cone);
  EXPECT_NEAR(c.angle, half, 0.02);

  Cloud torus;  // R = 2, r = 0.5 about +z, the upper half
  for (int i = 0; i < 160; ++i)
    for (int j = 0; j < 30; ++j) {
      const double az = 2 * M_PI * i / 160, tube = M_PI * j / 29;
      const Vec3 n{std::cos(tube) * std::cos(az), std::cos(tube) * std::sin(az), std::sin(tube)};
      torus.add({2 * std::cos(az) + 0.5 * n[0], 2 * std::sin(az) + 0.5 * n[1], 0.5 * n[2]}, n);
    }
  const SurfacePatch t = largest(detect_surfaces(torus.points, torus.normals, {}, 1));
  ASSERT_EQ(t.kind, SurfaceKind::Torus);
  EXPECT_NEAR(t.radius, 2, 0.02);
  EXPECT_NEAR(t.minor_radius, 0.5, 0.02);
}

TEST(SurfaceDetect, SphereBandSeenBelowACutIsASphere) {
  // A band of a ball, 30 degrees high and 140 wide (a sphere cut above, hidden behind a block
  // below): its normals spread little out of one plane, but no cylinder explains its points.
  Cloud band;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 80; ++j) {
      const double polar = (75 + 30.0 * i / 39) * M_PI / 180, az = (-70 + 140.0 * j / 79) * M_PI / 180;
      const Vec3 n{std::sin(polar) * std::cos(az), std::sin(polar) * std::sin(az), std::cos(polar)};
      band.add({1 + 2 * n[0], 2 * n[1], -1 + 2 * n[2]}, n);
    }
  const SurfacePatch p = largest(detect_surfaces(band.points, band.normals, {}, 1));
  ASSERT_EQ(p.kind, SurfaceKind::Sphere);
  EXPECT_NEAR(p.radius, 2, 1e-6);
  EXPECT_NEAR(p.point[0], 1, 1e-6);
  EXPECT_NEAR(p.point[2], -1, 1e-6);
}

TEST(RangePrimitives, LoneFacePartlyHiddenKeepsItsRectangle) {
  // A 6 x 3 face at z = 1 turned by 30 degrees about z, a quarter of it hidden by something in
  // front: the spread of what is seen turns, the rectangle around it does not.
  const double turn = 30 * M_PI / 180;
  const Vec3 u{std::cos(turn), std::sin(turn), 0}, w{-std::sin(turn), std::cos(turn), 0};
  SurfacePatch face;
  std::vector<Vec3> points;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 30; ++j) {
      const double a = -3 + 6.0 * (i + 0.5) / 60, b = -1.5 + 3.0 * (j + 0.5) / 30;
      if (a > 0 && b > 0) continue;
      face.points.push_back(static_cast<int>(points.size()));
      points.push_back({a * u[0] + b * w[0], a * u[1] + b * w[1], 1});
    }
  face.axis = {0, 0, 1};
  face.point = {0, 0, 1};
  const RecognisedPrimitives rec = recognise_primitives({face}, points, 6.7, 0.13);
  ASSERT_EQ(rec.primitives.size(), 1u);
  const Primitive3D& slab = rec.primitives[0].primitive;
  const Mat3 r = slab.rotation.matrix();
  bool along_side = false;
  for (int c = 0; c < 3; ++c) {
    const double cos_u = std::abs(r[0][c] * u[0] + r[1][c] * u[1]);
    if (cos_u > std::cos(M_PI / 180)) {
      along_side = true;
      EXPECT_NEAR(slab.dims[c], 6, 0.15);
    }
  }
  EXPECT_TRUE(along_side) << "an axis of the slab lies along the face's long side";
}

TEST(SurfaceDetect, SameSeedSamePatches) {
  const Cloud cloud = sphere_cap({0, 0, 0}, 1, true);
  const auto a = detect_surfaces(cloud.points, cloud.normals, {}, 7);
  const auto b = detect_surfaces(cloud.points, cloud.normals, {}, 7);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].points, b[i].points);
}

SignedPrimitive node(const Primitive3D& p, bool positive) {
  SignedPrimitive s;
  s.primitive = p;
  s.positive = positive;
  return s;
}

std::vector<Vec3> on_cylinder_wall(double cx, double cy, double r, double z0, double z1, double from,
                                   double to) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 20; ++i)
    for (int k = 0; k < 10; ++k) {
      const double phi = from + (to - from) * i / 19;
      pts.push_back({cx + r * std::cos(phi), cy + r * std::sin(phi), z0 + (z1 - z0) * (k + 0.5) / 10});
    }
  return pts;
}

// Object B of seed 002's Fig. 10, by hand: a block, a cut into it, two cylinders standing in
// the cut, a cylinder on top.
TEST(PrecedenceGraph, ObjectBHasThePapersOrders) {
  std::vector<SignedPrimitive> nodes = {
      node(Primitive3D::box(1.5, 1.5, 0.75, 3, 3, 1.5), true),
      node(Primitive3D::cylinder(5.2, 1.5, 0.75, 2.5, 1.5), false),
      node(Primitive3D::cylinder(2.85, 0.55, 0.875, 0.5, 1.75), true),
      node(Primitive3D::cylinder(2.85, 2.45, 0.875, 0.5, 1.75), true),
      node(Primitive3D::cylinder(1.1, 1.5, 1.875, 0.75, 0.75), true)};
  const std::vector<std::vector<int>> adjacent = {{1, 4}, {0, 2, 3}, {1}, {1}, {0}};
  std::vector<std::vector<Vec3>> points(5);
  points[1] = on_cylinder_wall(5.2, 1.5, 2.5, 0.1, 1.4, 2.9, 3.3);   // the cut's wall, in the block
  points[2] = on_cylinder_wall(2.85, 0.55, 0.5, 0.1, 1.7, -1, 1);    // outside the block's rest
  points[3] = on_cylinder_wall(2.85, 2.45, 0.5, 0.1, 1.7, -1, 1);
  points[4] = on_cylinder_wall(1.1, 1.5, 0.75, 1.55, 2.2, 0, 6.2);
  points[0] = {{0.5, 0.5, 1.5}, {1, 3, 0.5}};
  const PrecedenceGraph g = build_precedence_graph(nodes, adjacent, points);
  ASSERT_EQ(g.nodes.size(), 5u);
  EXPECT_EQ(g.order, (std::vector<int>{1, 2, 3, 3, 1}));
  EXPECT_EQ(g.subobjects, 2);
  EXPECT_EQ(g.subobject[0], g.subobject[2]);
  EXPECT_NE(g.subobject[0], g.subobject[4]);
  int subtracting = 0, appending = 0;
  for (const PrecedenceArc& a : g.arcs) (a.kind == ArcKind::Subtracting ? subtracting : appending)++;
  EXPECT_EQ(subtracting, 1);
  EXPECT_EQ(appending, 2);
  // The tree: (block - cut) + the two cylinders, then the top cylinder beside it.
  const Node3D tree = precedence_tree(g);
  EXPECT_EQ(tree.primitive_count(), 5u);
  EXPECT_TRUE(contains(tree, 0.5, 0.5, 0.5));    // block
  EXPECT_FALSE(contains(tree, 2.9, 1.5, 0.5));   // cut away
  EXPECT_TRUE(contains(tree, 2.85, 0.55, 1.6));  // appended after the cut
  EXPECT_TRUE(contains(tree, 1.1, 1.5, 2.1));    // on top
}

TEST(PrecedenceGraph, CutThatCutsNothingIsDropped) {
  std::vector<SignedPrimitive> nodes = {node(Primitive3D::box(0, 0, 0, 2, 2, 2), true),
                                        node(Primitive3D::sphere(5, 0, 0, 1), false)};
  std::vector<std::vector<Vec3>> points = {{{0, 0, 1}}, {{5, 0, 1}, {5, 1, 0}}};
  const PrecedenceGraph g = build_precedence_graph(nodes, {{1}, {0}}, points);
  EXPECT_EQ(g.nodes.size(), 1u);
}

TEST(FitRange, BlockWithAHoleComesBackAsTwoPrimitives) {
  const fs::path sidecar = kRange / "one_cube_ortho.png";
  if (!fs::exists(sidecar)) GTEST_SKIP() << "benchmarks not found";
  const RangeCamera camera = *read_range_camera(sidecar.string(), 192, 192, {});
  // A block 8 x 6 x 4 with a vertical hole of radius 1.2 through it, inside the cube's view.
  const Node3D truth = Node3D::op(NodeKind::Difference,
                                  {Node3D::leaf(Primitive3D::box(0, 0, 0, 8, 6, 4)),
                                   Node3D::leaf(Primitive3D::cylinder(1, 0.5, 0, 1.2, 6))});
  const RangeScan scan = scan_of(truth, camera);
  ASSERT_GT(scan.points.size(), 1000u);
  RangeFitOptions options;
  options.time_limit = 10;
  const RangeFitResult a = fit_range({scan}, options);
  ASSERT_EQ(a.tree.primitive_count(), 2u);
  ASSERT_EQ(a.graph.nodes.size(), 2u);
  int negatives = 0;
  for (const SignedPrimitive& n : a.graph.nodes) negatives += !n.positive;
  EXPECT_EQ(negatives, 1);
  ASSERT_EQ(a.views.size(), 1u);
  EXPECT_GT(a.views[0].silhouette_iou, 0.99);
  EXPECT_LT(a.views[0].depth_error, 0.005 * a.diagonal);
  // Hidden faces: the block's far side is not seen, yet its size is (two faces show it).
  EXPECT_FALSE(contains(a.tree, 1, 0.5, 0));
  EXPECT_TRUE(contains(a.tree, -3.5, -2.5, -1.8));
  const RangeFitResult b = fit_range({scan}, options);
  EXPECT_EQ(a.tree, b.tree) << "same seed, same tree";
}

TEST(FitRange, TooFewPointsIsAnInputError) {
  RangeScan scan;
  scan.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  scan.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  EXPECT_THROW(fit_range({scan}, {}), InputError);
}

TEST(FitRange, ViewsOfDifferentPartsAreRefused) {
  RangeScan a, b;
  for (int i = 0; i < 200; ++i) {
    a.points.push_back({i * 0.01, 0, 0}), a.normals.push_back({0, 0, 1});
    b.points.push_back({100 + i * 0.01, 0, 0}), b.normals.push_back({0, 0, 1});
  }
  EXPECT_THROW(fit_range({a, b}, {}), InputError);
}

}  // namespace
}  // namespace csgfit
